// Isobath benchmarks: slicing a seafloor, and exact crossing queries at the size of
// Ts'o–Barsky's animation (400 orthogonals over 341 contour segments; 16 CPU minutes
// of tracing on a VAX-11/750) and 100× more rays.
#include "libwave/isobath.h"

#include <benchmark/benchmark.h>

#include <cmath>

namespace {

void BM_slice_gonzato_bay(benchmark::State& state) {
    const wave::Seafloor bay = wave::make_gonzato_bay();
    wave::IsobathOptions o;
    o.spacing = 0.5;
    for (auto _ : state) benchmark::DoNotOptimize(wave::extract_isobaths(bay, o).xy.data());
}
BENCHMARK(BM_slice_gonzato_bay)->Unit(benchmark::kMillisecond);

// Ts'o's figure-5 contours resampled to 341 segments in all.
wave::DepthContours tso_341_segments() {
    const wave::Seafloor tso = wave::make_tso_contours();
    wave::DepthContours c;
    c.offsets.push_back(0);
    const std::size_t lines = tso.contours.size();
    for (std::size_t p = 0; p < lines; ++p) {
        const std::size_t begin = tso.contours.offsets[p], end = tso.contours.offsets[p + 1];
        constexpr std::size_t keep = 35;  // 10 lines × 34 segments = 340 ≈ 341
        for (std::size_t k = 0; k < keep; ++k) {
            const std::size_t src = begin + k * (end - begin - 1) / (keep - 1);
            c.xy.push_back(tso.contours.xy[2 * src]);
            c.xy.push_back(tso.contours.xy[2 * src + 1]);
        }
        c.depth.push_back(tso.contours.depth[p]);
        c.closed.push_back(0);
        c.offsets.push_back(c.xy.size() / 2);
    }
    return c;
}

// Each ray walks from the top of the domain to the bottom, crossing every isobath
// (Ts'o's isobath mode without the Snell turn, which the trace stage adds).
void BM_crossings_tso_scene(benchmark::State& state) {
    const wave::DepthContours c = tso_341_segments();
    const wave::IsobathIndex index(c);
    const auto rays = static_cast<std::size_t>(state.range(0));
    std::size_t crossings = 0;
    for (auto _ : state) {
        for (std::size_t r = 0; r < rays; ++r) {
            wave::CrossingQuery q;
            q.x = 50.0 * (static_cast<double>(r) + 0.5) / static_cast<double>(rays);
            q.y = 50.0;
            q.dx = 0.05;
            q.dy = -1.0;
            while (auto hit = index.first_crossing(q)) {
                ++crossings;
                q.x = hit->x;
                q.y = hit->y;
                q.skip_segment = hit->segment;
            }
        }
    }
    state.counters["crossings_per_s"] = benchmark::Counter(static_cast<double>(crossings), benchmark::Counter::kIsRate);
    state.counters["segments"] = static_cast<double>(index.segment_count());
}
BENCHMARK(BM_crossings_tso_scene)->Arg(400)->Arg(40000)->Unit(benchmark::kMillisecond);

}  // namespace
