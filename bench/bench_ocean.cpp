// Tessendorf's FFT ocean per frame, against the raw FFTW cost of the same transforms
// (the floor) and, in bench/peers/blender_ocean.py, Blender 3.4's Ocean modifier on the
// same grids. Range arguments: N (the grid is N²).
#include "libwave/motion.h"
#include "libwave/scene.h"
#include "libwave/shade.h"

#include <benchmark/benchmark.h>
#include <fftw3.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <span>
#include <vector>

namespace {

// The floor: the eight inverse real N² transforms a frame with chop and foam needs
// (h, ∇h, D, ∂D), one sequential plan, the eight in parallel on the machine's cores —
// the transforms a frame computed before libwave packed them in pairs, without filling
// the spectra. The plan: FFTW's patient planner's, from the wisdom in
// bench/fftw_floor_wisdom.inc (range 1: 1), or FFTW_ESTIMATE (range 1: 0, the floor of
// the twenty-ninth session and before).
void BM_fftw_floor(benchmark::State& state) {
    const auto n = static_cast<int>(state.range(0));
    const std::size_t half = static_cast<std::size_t>(n / 2 + 1), count = static_cast<std::size_t>(n) * half;
    std::vector<fftwf_complex*> in(8);
    std::vector<float*> out(8);
    for (int f = 0; f < 8; ++f) {
        in[f] = fftwf_alloc_complex(count);
        out[f] = fftwf_alloc_real(static_cast<std::size_t>(n) * n);
    }
    const bool patient = state.range(1) != 0 && fftwf_import_wisdom_from_string(
#include "fftw_floor_wisdom.inc"
                                                     ) != 0;
    fftwf_plan plan = patient ? fftwf_plan_dft_c2r_2d(n, n, in[0], out[0], FFTW_MEASURE | FFTW_WISDOM_ONLY) : nullptr;
    if (state.range(1) && !plan) state.SkipWithError("no wisdom for this size");
    if (!plan) plan = fftwf_plan_dft_c2r_2d(n, n, in[0], out[0], FFTW_ESTIMATE);
    for (auto _ : state) {
        state.PauseTiming();  // c2r destroys its input: refill outside the timing
        for (int f = 0; f < 8; ++f)
            for (std::size_t i = 0; i < count; ++i) in[f][i][0] = in[f][i][1] = 1e-3f * static_cast<float>(i % 7);
        state.ResumeTiming();
        tbb::parallel_for(0, 8, [&](int f) { fftwf_execute_dft_c2r(plan, in[f], out[f]); });
        benchmark::DoNotOptimize(out[7]);
    }
    fftwf_destroy_plan(plan);
    for (int f = 0; f < 8; ++f) fftwf_free(in[f]), fftwf_free(out[f]);
}
BENCHMARK(BM_fftw_floor)->ArgsProduct({{256, 512, 1024}, {1, 0}})->Unit(benchmark::kMillisecond)->UseRealTime();

// The transforms a frame computes now: the same eight fields as four in-place complex
// N² transforms (two real fields each), libwave's plan from the wisdom it ships (range
// 1: 1), or FFTW_ESTIMATE's (range 1: 0).
void BM_fftw_packed_floor(benchmark::State& state) {
    const wave::OceanWorkspace libwave_plan(static_cast<std::size_t>(state.range(0)));  // imports libwave's wisdom
    const auto n = static_cast<int>(state.range(0));
    const std::size_t count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    std::vector<fftwf_complex*> data(4);
    for (auto& d : data) d = fftwf_alloc_complex(count);
    const unsigned rigour = state.range(1) ? FFTW_MEASURE | FFTW_WISDOM_ONLY : FFTW_ESTIMATE;
    fftwf_plan plan = fftwf_plan_dft_2d(n, n, data[0], data[0], FFTW_BACKWARD, rigour);
    if (!plan) state.SkipWithError("no wisdom for this size");
    for (auto _ : state) {
        state.PauseTiming();
        for (auto* d : data)
            for (std::size_t i = 0; i < count; ++i) d[i][0] = d[i][1] = 1e-3f * static_cast<float>(i % 7);
        state.ResumeTiming();
        if (plan) tbb::parallel_for(0, 4, [&](int f) { fftwf_execute_dft(plan, data[f], data[f]); });
        benchmark::DoNotOptimize(data[3]);
    }
    if (plan) fftwf_destroy_plan(plan);
    for (auto* d : data) fftwf_free(d);
}
BENCHMARK(BM_fftw_packed_floor)->ArgsProduct({{256, 512, 1024}, {1, 0}})->Unit(benchmark::kMillisecond)->UseRealTime();

wave::OceanOptions gale(std::int64_t n) {
    wave::OceanOptions o;
    o.resolution = static_cast<std::size_t>(n);
    o.size = 1000.0;
    o.spectrum.wind_speed = 31.0;
    o.spectrum.small_wave_cutoff = 0.5;
    o.choppiness = 1.6;
    o.repeat_time = 20.0;
    return o;
}

// evaluate_ocean: spectra at t (eq. 26, phase table) + the eight transforms.
void BM_ocean_fields(benchmark::State& state) {
    const wave::OceanPlan plan = wave::plan_ocean(gale(state.range(0)));
    wave::OceanWorkspace ws(plan.n);
    double t = 0.0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(wave::evaluate_ocean(plan, t, ws).height.data);
        t += 1.0 / 24.0;
    }
}
BENCHMARK(BM_ocean_fields)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();

// The surface of one frame: fields + (N+1)² positions, exact normals, J₋, Fresnel
// weights and the fold foam of this frame (the past lattice times are amortised in a
// run: see BM_ocean_scene_frames).
void BM_ocean_surface_frame(benchmark::State& state) {
    const wave::OceanPlan plan = wave::plan_ocean(gale(state.range(0)));
    wave::OceanWorkspace ws(plan.n);
    const std::size_t side = plan.n + 1, count = side * side;
    std::vector<float> p(3 * count), nr(3 * count), jm(count), r(count), tr(count), foam(count);
    wave::FresnelOptions fresnel;
    fresnel.camera = {500.0, -600.0, 250.0};
    double t = 0.0;
    const std::size_t block = 8;  // rows: each block's Fresnel weights while it is in cache, as `wave run` does
    const auto span = [](std::vector<float>& a, std::size_t first, std::size_t size) {
        return std::span<float>(a).subspan(first, size);
    };
    for (auto _ : state) {
        const wave::OceanFields fields = wave::evaluate_ocean(plan, t, ws);
        tbb::parallel_for(std::size_t{0}, (side + block - 1) / block, [&](std::size_t b) {
            const std::size_t first = b * block, rows = std::min(block, side - first), v = first * side, size = rows * side;
            wave::ocean_patch_rows(plan, fields, first, rows, span(p, 3 * v, 3 * size), span(nr, 3 * v, 3 * size),
                                   span(jm, v, size));
            wave::fresnel_weights(span(p, 3 * v, 3 * size), span(nr, 3 * v, 3 * size), fresnel, span(r, v, size),
                                  span(tr, v, size));
        });
        std::fill(foam.begin(), foam.end(), 0.0f);
        wave::accumulate_fold_foam(jm, 0.0, {}, foam);
        benchmark::DoNotOptimize(foam.data());
        t += 1.0 / 24.0;
    }
    state.counters["vertices"] = static_cast<double>(count);
}
BENCHMARK(BM_ocean_surface_frame)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();

// What `wave run` does per frame for the open-ocean surface (animate_scene: surface,
// normals, Fresnel, fold foam with its faded past, the per-frame arrays), over a run of
// 1 and 25 (13) frames at 24 fps: the first frame also computes the 18 past lattice
// times, so the steady cost per frame is the difference over 24 (12) frames.
// The open-ocean scene of a gale on an N² patch, seen from the example's camera.
wave::Scene gale_scene(std::int64_t n) {
    wave::Scene scene;
    scene.surface_kind = wave::SurfaceKind::ocean;
    scene.ocean = gale(n);
    scene.camera = std::array<double, 3>{500.0, -600.0, 250.0};
    return scene;
}

void BM_ocean_scene_frames(benchmark::State& state) {
    const wave::Scene scene = gale_scene(state.range(0));
    const wave::ScenePlan plan = wave::plan_scene(scene);
    const std::size_t frames = static_cast<std::size_t>(state.range(1));
    for (auto _ : state) benchmark::DoNotOptimize(wave::animate_scene(scene, plan, 4e9, {0, frames}).foam.data());
    state.counters["frames"] = static_cast<double>(frames);
}
BENCHMARK(BM_ocean_scene_frames)->Args({256, 1})->Args({256, 25})->Args({1024, 1})->Args({1024, 13})->Unit(benchmark::kMillisecond)->UseRealTime();

// What a run pays before its first frame: the plan — the spectrum, and the fold foam's
// threshold calibrated on frame 0's past lattice times, whose samples at the vertices
// the plan keeps for a run from frame 0 (the first streamed frame below starts with them).
void BM_ocean_plan(benchmark::State& state) {
    const wave::Scene scene = gale_scene(state.range(0));
    double kept = 0.0;
    for (auto _ : state) {
        const wave::ScenePlan plan = wave::plan_scene(scene);
        kept = 0.0;
        for (const auto& [j, sample] : plan.fold_past) kept += static_cast<double>(sample.vertex.size() * 8);
    }
    state.counters["fold_past_MB"] = kept / 1e6;
}
BENCHMARK(BM_ocean_plan)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same frames as `wave run` now evaluates them (AnimationStream, docs/export.md
// "Streamed output"): 4 frames at a time into arrays reused from chunk to chunk, so
// only the first chunk meets fresh pages. Steady cost per frame: the difference of
// the runs of 25 (13) and 1 frames over 24 (12).
void BM_ocean_stream_frames(benchmark::State& state) {
    const wave::Scene scene = gale_scene(state.range(0));
    const wave::ScenePlan plan = wave::plan_scene(scene);
    const std::size_t frames = static_cast<std::size_t>(state.range(1));
    wave::SceneAnimation chunk;
    {  // a run's chunk arrays meet fresh pages once (151 MB at 1024²), not once a repetition
        wave::AnimationStream warm(scene, plan, {0, frames});
        while (warm.next(chunk, 4) > 0) {
        }
    }
    for (auto _ : state) {
        wave::AnimationStream stream(scene, plan, {0, frames});
        while (stream.next(chunk, 4) > 0) benchmark::DoNotOptimize(chunk.foam.data());
    }
    state.counters["frames"] = static_cast<double>(frames);
}
BENCHMARK(BM_ocean_stream_frames)->Args({256, 1})->Args({256, 25})->Args({1024, 1})->Args({1024, 13})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
