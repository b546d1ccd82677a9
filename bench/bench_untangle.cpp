// Untangling one frame (motion.h untangle_motion) of a choppy wave on a 500 × 500 grid
// of 0.5 m cells (250 000 vertices, 498 002 triangles): with the smallest-angle bound
// (16°, the default) beside the area's alone (min_angle_degrees 0), the peer.
#include <benchmark/benchmark.h>

#include "libwave/motion.h"
#include "libwave/surface.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace {

struct Grid {
    std::vector<double> x, y;
    std::vector<std::uint32_t> triangles;
    std::vector<float> moved;
};

// The folding wave of tests/test_untangle.cpp (Q·k = 1.6, crests slanted) pulled along
// its crests too: squeezed one way, stretched the other.
Grid choppy_grid(std::size_t side) {
    Grid g{{}, {}, wave::grid_triangles(side, side), {}};
    const double k = 2.0 * std::numbers::pi / 8.0, q = 1.6 / k;
    for (std::size_t j = 0; j < side; ++j)
        for (std::size_t i = 0; i < side; ++i) {
            const double x = 0.5 * static_cast<double>(i), y = 0.5 * static_cast<double>(j), phase = k * x + 0.3 * y;
            g.x.push_back(x);
            g.y.push_back(y);
            g.moved.insert(g.moved.end(), {static_cast<float>(x - q * std::sin(phase)), static_cast<float>(y + 0.6 * std::cos(phase)),
                                           static_cast<float>(0.5 * std::cos(phase))});
        }
    return g;
}

void BM_untangle_frame(benchmark::State& state) {
    const Grid g = choppy_grid(500);
    const wave::UntanglePlan plan =
        wave::plan_untangle(g.x, g.y, g.triangles, {.min_angle_degrees = static_cast<double>(state.range(0))});
    wave::UntangleWorkspace workspace;
    std::vector<float> p;
    for (auto _ : state) {
        p = g.moved;
        const wave::UntangleReport r = wave::untangle_motion(plan, {}, p, &workspace);
        state.counters["passes"] = static_cast<double>(r.passes);
        state.counters["damped"] = static_cast<double>(r.damped_vertices);
        benchmark::DoNotOptimize(p.data());
    }
}
BENCHMARK(BM_untangle_frame)->Arg(0)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
