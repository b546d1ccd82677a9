// Whitewater (whitewater.h): advancing about a million particles to a frame — each a
// closed form of its event and age — beside writing them (the frame's POINTS .glb), and
// riding a surface (point location in the rest triangles, barycentric displacement).
// Events: an 880 m breaking beach of 44 000 points a crest passes, 8 s period, 3 crests
// in the loop, every kind at full strength: ~1 M particles alive at a frame.
#include <benchmark/benchmark.h>

#include "libwave/surface.h"
#include "libwave/whitewater.h"

#include <cmath>
#include <vector>

namespace {

wave::WhitewaterEvents beach_events() {
    wave::WhitewaterEvents e;
    e.period = 24.0;
    for (int crest = 0; crest < 3; ++crest)
        for (int i = 0; i < 440; ++i)      // along the beach, 2 m apart
            for (int j = 0; j < 100; ++j)  // across the surf zone, 0.5 m apart: the crest passes j later
                e.add(static_cast<float>(2 * i), static_cast<float>(0.5 * j), 0.6f, 0.0f, 1.0f, 5.0f, 0.8f, 1.2f,
                      8.0 * crest + 0.1 * j, 1.0f, 1.0f, 1.0f, static_cast<std::uint64_t>((crest * 440 + i) * 100 + j),
                      static_cast<std::uint32_t>(crest));
    return e;
}

void BM_whitewater_advance(benchmark::State& state) {
    const wave::WhitewaterEvents e = beach_events();
    const wave::WhitewaterOptions o;
    wave::WhitewaterPoints p;
    wave::WhitewaterWorkspace work;  // as a run of frames holds it
    double t = 10.0;
    for (auto _ : state) {
        wave::evaluate_whitewater(e, o, t, p, work);
        t += 1.0 / 24.0;
        benchmark::DoNotOptimize(p.positions.data());
    }
    state.counters["particles"] = static_cast<double>(p.count());
}
BENCHMARK(BM_whitewater_advance)->Unit(benchmark::kMillisecond)->UseRealTime();

// The peer: the same frames without a workspace (every frame allocates and faults in its
// blocks' buffers again).
void BM_whitewater_advance_no_workspace(benchmark::State& state) {
    const wave::WhitewaterEvents e = beach_events();
    const wave::WhitewaterOptions o;
    wave::WhitewaterPoints p;
    double t = 10.0;
    for (auto _ : state) {
        wave::evaluate_whitewater(e, o, t, p);
        t += 1.0 / 24.0;
        benchmark::DoNotOptimize(p.positions.data());
    }
    state.counters["particles"] = static_cast<double>(p.count());
}
BENCHMARK(BM_whitewater_advance_no_workspace)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_whitewater_write(benchmark::State& state) {
    const wave::WhitewaterEvents e = beach_events();
    wave::WhitewaterPoints p;
    wave::evaluate_whitewater(e, wave::WhitewaterOptions{}, 10.0, p);
    for (auto _ : state) {
        std::string glb = wave::whitewater_glb(p, 240, 24.0);
        benchmark::DoNotOptimize(glb.data());
    }
    state.counters["particles"] = static_cast<double>(p.count());
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(p.count()) * 36);
}
BENCHMARK(BM_whitewater_write)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_whitewater_ride(benchmark::State& state) {
    // A 0.5 m grid under the beach (1761 × 201 vertices), moved by a swell.
    const std::size_t nx = 1761, ny = 201;
    std::vector<double> x, y;
    std::vector<float> moved;
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
            x.push_back(0.5 * static_cast<double>(i) - 1.0), y.push_back(0.5 * static_cast<double>(j) - 25.0);
            const double phase = 0.25 * y.back();
            moved.insert(moved.end(), {static_cast<float>(x.back()), static_cast<float>(y.back() + 0.3 * std::sin(phase)),
                                       static_cast<float>(0.4 * std::cos(phase))});
        }
    const std::vector<std::uint32_t> triangles = wave::grid_triangles(nx, ny);
    const wave::WhitewaterRide ride = wave::plan_whitewater_ride(x, y, triangles);
    const wave::WhitewaterEvents e = beach_events();
    wave::WhitewaterPoints fresh, p;
    wave::evaluate_whitewater(e, wave::WhitewaterOptions{}, 10.0, fresh);
    for (auto _ : state) {
        state.PauseTiming();
        p = fresh;
        state.ResumeTiming();
        wave::ride_whitewater(ride, moved, p);
        benchmark::DoNotOptimize(p.positions.data());
    }
    state.counters["particles"] = static_cast<double>(fresh.count());
}
BENCHMARK(BM_whitewater_ride)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
