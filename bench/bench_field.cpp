// The refraction–diffraction field (docs/wave-field.md) beside the fronts it gives its
// amplitudes to, on the same scenes in the same run: Berkhoff's shoal, the default bay,
// Okushiri at full scale (examples/coast-with-wind-waves.json).
#include "libwave/field.h"
#include "libwave/scene.h"
#include "libwave/surface.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

wave::Scene scene_named(int which) {
    if (which == 0) return wave::default_scene();
    const char* file = which == 1 ? "/berkhoff-shoal.json" : which == 2 ? "/coast-with-wind-waves.json" : "/gonzato-island.json";
    return wave::read_scene(std::string(LIBWAVE_EXAMPLES_DIR) + file);
}

const char* label(int which) {
    return which == 0 ? "bay" : which == 1 ? "berkhoff" : which == 2 ? "okushiri-full-scale" : "island";
}

void BM_field(benchmark::State& state) {
    const wave::Scene scene = scene_named(static_cast<int>(state.range(0)));
    const wave::Seafloor sea = wave::scene_seafloor(scene);
    std::size_t nodes = 0;
    for (auto _ : state) {
        const wave::WaveField f = wave::solve_wave_field(sea, scene.waves[0], scene.field);
        nodes = f.nx * f.ny;
        benchmark::DoNotOptimize(f.envelope.data());
    }
    state.SetLabel(label(static_cast<int>(state.range(0))));
    state.counters["nodes"] = static_cast<double>(nodes);
    state.counters["nodes_per_s"] = benchmark::Counter(static_cast<double>(nodes), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_field)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The peer in the same run: Gonzato's fronts over the same seafloor and train.
void BM_fronts(benchmark::State& state) {
    wave::Scene scene = scene_named(static_cast<int>(state.range(0)));
    const wave::Seafloor sea = wave::scene_seafloor(scene);
    const wave::DepthContours iso = wave::extract_isobaths(sea, scene.isobaths);
    wave::FrontOptions o = scene.fronts;
    o.ray_spacing = scene.surface_kind == wave::SurfaceKind::ray_strips ? scene.trace.ray_spacing : 0.05;
    if (scene.surface_kind != wave::SurfaceKind::ray_strips) o.step = 0.05;  // Berkhoff: as in the measurement
    o.max_rays = scene.trace.max_rays;
    std::size_t points = 0;
    for (auto _ : state) {
        const wave::FrontSet f = wave::trace_fronts(sea, scene.waves[0], o, &iso);
        points = f.x.size();
    }
    state.SetLabel(label(static_cast<int>(state.range(0))));
    state.counters["points"] = static_cast<double>(points);
}
BENCHMARK(BM_fronts)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// Where the rays leave off (docs/wave-field.md): the field's wave over the water mesh's
// gaps and tears, the offset and direction continued by one sparse Cholesky solve.
// Beside it in the same run, the resampling it follows (BM_resample_strips): both on
// the scene's own plan (the bay, Okushiri at full scale, the island).
void resample_or_fill(benchmark::State& state, bool fill) {
    const wave::Scene scene = scene_named(static_cast<int>(state.range(0)));
    const wave::ScenePlan p = wave::plan_scene(scene);
    std::size_t filled = 0;
    for (auto _ : state) {
        wave::RayStrips s = wave::resample_ray_strips(p.strips, p.seafloor, p.water_mesh.x, p.water_mesh.y, p.water_mesh.triangles);
        if (fill) filled = wave::fill_strip_gaps(p.wave_fields.at(0), p.seafloor, s);
        benchmark::DoNotOptimize(s.phase.data());
    }
    state.SetLabel(label(static_cast<int>(state.range(0))));
    state.counters["vertices"] = static_cast<double>(p.water_mesh.x.size());
    if (fill) state.counters["filled"] = static_cast<double>(filled);
}
void BM_resample_strips(benchmark::State& state) { resample_or_fill(state, false); }
void BM_resample_and_fill_gaps(benchmark::State& state) { resample_or_fill(state, true); }
BENCHMARK(BM_resample_strips)->Arg(0)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_resample_and_fill_gaps)->Arg(0)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

}  // namespace
