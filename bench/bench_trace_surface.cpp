// Tracing and per-frame surface benchmarks at the size of Ts'o & Barsky's scene.
#include "libwave/scene.h"
#include "libwave/shade.h"

#include <benchmark/benchmark.h>

#include <tbb/global_control.h>

#include <vector>

namespace {

wave::Scene tso_scene(double ray_spacing) {
    wave::Scene s;
    s.surface_kind = wave::SurfaceKind::height_field;
    s.seafloor.source = "tso-contours";
    s.isobaths.levels = {0.1, 0.2, 0.3, 0.5, 0.75, 1.25};
    s.waves = {{.period = 6.0, .amplitude = 0.2, .direction_x = 0.5, .direction_y = -0.7},
               {.period = 1.0, .amplitude = 0.1, .direction_x = -0.5, .direction_y = -0.7}};
    s.trace.ray_spacing = ray_spacing;
    s.surface.nx = s.surface.ny = 50;
    s.surface.samples_per_span = 8;
    return s;
}

// Ts'o traced 400 orthogonals (two trains) in 16 CPU minutes on a VAX-11/750.
void BM_trace_tso(benchmark::State& state) {
    const wave::Scene scene = tso_scene(50.0 * 1.2207 * 2 / static_cast<double>(state.range(0)));
    const wave::Seafloor sea = wave::load_seafloor(scene.seafloor);
    const wave::DepthContours iso = wave::extract_isobaths(sea, scene.isobaths);
    std::size_t rays = 0, crossings = 0;
    for (auto _ : state) {
        const wave::RaySet r = wave::trace_rays(sea, iso, scene.waves, scene.trace);
        rays += r.ray_count();
        for (auto e : r.event) crossings += e == wave::RayEvent::refracted || e == wave::RayEvent::reflected;
    }
    state.counters["rays"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kAvgIterations);
    state.counters["crossings"] = benchmark::Counter(static_cast<double>(crossings), benchmark::Counter::kAvgIterations);
    state.counters["crossings_per_s"] = benchmark::Counter(static_cast<double>(crossings), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_trace_tso)->Arg(400)->Arg(40000)->Unit(benchmark::kMillisecond);

// One frame of the 50 × 50 Beta2-spline surface at 8 samples per span (154 449 vertices).
void BM_height_field_frame(benchmark::State& state) {
    const wave::ScenePlan plan = wave::plan_scene(tso_scene(0.5));
    std::vector<float> h(plan.surface.control_count()), p(3 * plan.surface.vertex_count());
    double t = 0.0;
    for (auto _ : state) {
        wave::evaluate_height_field(plan.surface, t, h, p);
        t += 1.0 / 24.0;
        benchmark::DoNotOptimize(p.data());
    }
    state.counters["vertices_per_s"] = benchmark::Counter(static_cast<double>(plan.surface.vertex_count()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_height_field_frame)->Unit(benchmark::kMillisecond);

}  // namespace

namespace {

// Gonzato's bay: 100 rays, step 0.4 m, split at 1.2 m — the paper: 2 s on an R10000
// for tracing and tessellation together.
const wave::WaveTrain bay_swell{.period = 5.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0};

void BM_fronts_gonzato_bay(benchmark::State& state) {
    const wave::Seafloor bay = wave::make_gonzato_bay();
    wave::FrontOptions o;
    o.refraction = state.range(0) ? wave::FrontRefraction::isobath : wave::FrontRefraction::gradient;
    const wave::DepthContours isobaths = wave::extract_isobaths(bay, wave::IsobathOptions{.levels = {}, .spacing = 0.25});
    std::size_t inserted = 0;
    for (auto _ : state) {
        const wave::FrontSet f = wave::trace_fronts(bay, bay_swell, o, &isobaths);
        inserted = f.inserted_rays;
    }
    state.counters["inserted_rays"] = static_cast<double>(inserted);
    state.SetLabel(state.range(0) ? "isobath refraction" : "gradient refraction");
}
BENCHMARK(BM_fronts_gonzato_bay)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Tessellation of those fronts into the OpenMesh ray strips plus the flat arrays.
void BM_ray_strips_gonzato_bay(benchmark::State& state) {
    const wave::FrontSet f = wave::trace_fronts(wave::make_gonzato_bay(), bay_swell);
    std::size_t facets = 0;
    for (auto _ : state) facets = wave::build_ray_strips(f).triangle_count();
    state.counters["facets"] = static_cast<double>(facets);
}
BENCHMARK(BM_ray_strips_gonzato_bay)->Unit(benchmark::kMillisecond);

// One frame of Gonzato's profile plus area-weighted normals on a strip mesh of about a
// million vertices (the bay at 0.13 m rays and 0.065 m steps); target: tens of ms on 2 cores.
void BM_gonzato_frame_1M(benchmark::State& state) {
    wave::FrontOptions o;
    o.ray_spacing = 0.13;
    o.step = 0.065;
    o.split_distance = 0.16;
    const wave::RayStrips strips = wave::build_ray_strips(wave::trace_fronts(wave::make_gonzato_bay(), bay_swell, o));
    const wave::GonzatoMotionPlan plan = wave::plan_gonzato_motion(strips);
    std::vector<float> p(3 * plan.vertex_count()), n(p.size());
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
    double t = 0.0;
    for (auto _ : state) {
        wave::evaluate_gonzato_motion(plan, t, p);
        wave::vertex_normals(p, strips.triangles, n);
        t += 1.0 / 24.0;
    }
    state.counters["vertices"] = static_cast<double>(plan.vertex_count());
}
BENCHMARK(BM_gonzato_frame_1M)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();



}  // namespace
