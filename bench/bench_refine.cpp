// OpenSubdiv refinement: applying the stencil table per frame versus refining the
// topology again each frame, at ~1 M output vertices (a 251 × 251 grid, Loop level 2,
// and Catmull–Clark level 2 on a 177 × 177 grid).
#include <benchmark/benchmark.h>

#include "libwave/surface.h"

#include <cmath>
#include <vector>

namespace {

struct Mesh {
    std::size_t n;
    std::vector<std::uint32_t> tris;
    std::vector<float> p;
};

Mesh wavy_grid(std::size_t side) {
    Mesh m{side * side, wave::grid_triangles(side, side), {}};
    for (std::size_t j = 0; j < side; ++j)
        for (std::size_t i = 0; i < side; ++i) {
            const float x = static_cast<float>(i), y = static_cast<float>(j);
            m.p.insert(m.p.end(), {x, y, 0.3f * std::sin(0.2f * x) * std::cos(0.15f * y)});
        }
    return m;
}

wave::RefineOptions options(benchmark::State& s) {
    return {s.range(0) == 0 ? wave::RefineScheme::loop : wave::RefineScheme::catmull_clark, 2};
}

std::size_t side(benchmark::State& s) { return s.range(0) == 0 ? 251 : 177; }

// Per frame: the stencils only (what a run does).
void BM_refine_apply_stencils(benchmark::State& state) {
    const Mesh m = wavy_grid(side(state));
    const wave::Refinement r = wave::plan_refinement(m.n, m.tris, options(state));
    std::vector<float> fine(3 * r.fine_vertices);
    for (auto _ : state) {
        wave::apply_refinement(r, m.p, 3, fine);
        benchmark::DoNotOptimize(fine.data());
    }
    state.counters["fine_vertices"] = static_cast<double>(r.fine_vertices);
}
BENCHMARK(BM_refine_apply_stencils)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The alternative: refine the topology (and build the stencils) again for every frame.
void BM_refine_topology_every_frame(benchmark::State& state) {
    const Mesh m = wavy_grid(side(state));
    std::vector<float> fine;
    for (auto _ : state) {
        const wave::Refinement r = wave::plan_refinement(m.n, m.tris, options(state));
        fine.resize(3 * r.fine_vertices);
        wave::apply_refinement(r, m.p, 3, fine);
        benchmark::DoNotOptimize(fine.data());
    }
}
BENCHMARK(BM_refine_topology_every_frame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
