// Caustics per frame (libwave/underwater.h) beside the frame's own surface: a 512²
// FFT sea (a 40 m patch in a 6 m/s breeze, the waves that net a shallow floor with
// light) over a flat floor 4 m down (and a sloping, rippled one), caustic maps of 512²
// and 1024²; the sunbeam volume of 128² voxels a level over a floor 8 m down.
#include "libwave/export.h"
#include "libwave/motion.h"
#include "libwave/shade.h"
#include "libwave/surface.h"
#include "libwave/underwater.h"

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace {

wave::OceanOptions breeze() {
    wave::OceanOptions o;
    o.resolution = 512;
    o.size = 40.0;
    o.spectrum.wind_speed = 6.0;
    o.spectrum.small_wave_cutoff = 0.05;
    o.choppiness = 1.0;
    o.repeat_time = 20.0;
    return o;
}

struct Sea {
    wave::OceanPlan plan = wave::plan_ocean(breeze());
    wave::OceanWorkspace workspace{plan.n};
    std::size_t count = (plan.n + 1) * (plan.n + 1);
    std::vector<float> positions = std::vector<float>(3 * count), normals = std::vector<float>(3 * count),
                       j_minus = std::vector<float>(count);
    std::vector<std::uint32_t> triangles = wave::grid_triangles(plan.n + 1, plan.n + 1);
    void frame(double t) { wave::ocean_patch_frame(plan, wave::evaluate_ocean(plan, t, workspace), positions, normals, j_minus); }
};

wave::ElevationGrid floor_under(double size, double depth) {
    wave::ElevationGrid g;
    g.nx = g.ny = 65;
    g.dx = g.dy = size / 64.0;
    g.z.assign(65 * 65, -depth);
    return g;
}

// A floor sloping from 2 m to 6 m deep across the patch, with a 0.5 m swell of sand
// ripples on it (the search's general case: no closed form).
wave::ElevationGrid sloping_floor_under(double size) {
    wave::ElevationGrid g = floor_under(size, 4.0);
    for (std::size_t j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < g.nx; ++i)
            g.z[j * g.nx + i] = -2.0 - 4.0 * static_cast<double>(i) / 64.0 - 0.25 * std::sin(0.7 * static_cast<double>(j));
    return g;
}

// The surface of one frame: the FFT fields, positions, exact normals and J₋.
void BM_caustics_surface_frame(benchmark::State& state) {
    Sea sea;
    double t = 0.0;
    for (auto _ : state) {
        sea.frame(t);
        benchmark::DoNotOptimize(sea.positions.data());
        t += 1.0 / 24.0;
    }
    state.counters["vertices"] = static_cast<double>(sea.count);
}
BENCHMARK(BM_caustics_surface_frame)->Unit(benchmark::kMillisecond)->UseRealTime();

// The caustic map of one frame under that surface (its surface computed outside the
// timing; the mesh's edges planned once, as a run does). Arguments: the map's side, and
// 1 for the sloping, rippled floor instead of the flat one.
void BM_caustics_map(benchmark::State& state) {
    Sea sea;
    wave::CausticOptions o;
    o.sun = {0.3, 0.2, 0.93};
    o.attenuation = 0.08;
    o.width = o.height = static_cast<std::size_t>(state.range(0));
    const double size = breeze().size;
    const wave::CausticPlan plan = wave::plan_caustics(state.range(1) ? sloping_floor_under(size) : floor_under(size, 4.0), o);
    const wave::CausticMesh mesh = wave::plan_caustic_mesh(sea.triangles, sea.count);
    wave::CausticWorkspace workspace;
    std::vector<float> map(o.width * o.height);
    double t = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        sea.frame(t);
        state.ResumeTiming();
        wave::evaluate_caustics(plan, mesh, sea.positions, sea.normals, map, &workspace);
        benchmark::DoNotOptimize(map.data());
        t += 1.0 / 24.0;
    }
}
BENCHMARK(BM_caustics_map)->Args({512, 0})->Args({1024, 0})->Args({1024, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

// The floor under any method that projects the surface's triangles onto the seafloor,
// beside BM_caustics_map: each vertex's refracted ray to the flat floor in closed form
// (Snell; no Fresnel, no attenuation) and each triangle's flux into the one map pixel
// under its corners' mean, on two halves of the triangles into two maps that are then
// summed. No footprint area, no coverage: a map of speckle, only the work every such
// method must do at least. Argument: the map's side.
void BM_caustics_splat_bound(benchmark::State& state) {
    Sea sea;
    const std::size_t side = static_cast<std::size_t>(state.range(0));
    const double size = breeze().size, depth = 4.0, eta = 1.0 / 1.333;
    const double sun_norm = std::hypot(0.3, 0.2, 0.93);
    const std::array<double, 3> down{-0.3 / sun_norm, -0.2 / sun_norm, -0.93 / sun_norm};
    std::vector<float> u(sea.count), v(sea.count);
    std::array<std::vector<float>, 2> maps{std::vector<float>(side * side), std::vector<float>(side * side)};
    const std::size_t triangles = sea.triangles.size() / 3;
    double t = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        sea.frame(t);
        state.ResumeTiming();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sea.count, 8192), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                const double nx = sea.normals[3 * i], ny = sea.normals[3 * i + 1], nz = sea.normals[3 * i + 2];
                const double ci = -(down[0] * nx + down[1] * ny + down[2] * nz);
                const double k = eta * ci - std::sqrt(std::max(0.0, 1.0 - eta * eta * (1.0 - ci * ci)));
                const double tx = eta * down[0] + k * nx, ty = eta * down[1] + k * ny, tz = eta * down[2] + k * nz;
                const double run = (-depth - sea.positions[3 * i + 2]) / tz;
                u[i] = static_cast<float>((sea.positions[3 * i] + run * tx) / size * static_cast<double>(side));
                v[i] = static_cast<float>((sea.positions[3 * i + 1] + run * ty) / size * static_cast<double>(side));
            }
        });
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, 2, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t half = r.begin(); half != r.end(); ++half) {
                std::vector<float>& map = maps[half];
                std::fill(map.begin(), map.end(), 0.0f);
                for (std::size_t f = half * triangles / 2; f < (half + 1) * triangles / 2; ++f) {
                    const std::uint32_t* c = &sea.triangles[3 * f];
                    const float cu = (u[c[0]] + u[c[1]] + u[c[2]]) / 3.0f, cv = (v[c[0]] + v[c[1]] + v[c[2]]) / 3.0f;
                    const auto wrap = [side](float w) {
                        const auto k = static_cast<long>(std::floor(w)) % static_cast<long>(side);
                        return static_cast<std::size_t>(k < 0 ? k + static_cast<long>(side) : k);
                    };
                    map[wrap(cv) * side + wrap(cu)] += 1.0f;
                }
            }
        });
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, side * side, 65536), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) maps[0][i] += maps[1][i];
        });
        benchmark::DoNotOptimize(maps[0].data());
        t += 1.0 / 24.0;
    }
}
BENCHMARK(BM_caustics_splat_bound)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();

// The 16-bit PNG of a 1024² map.
void BM_caustics_png(benchmark::State& state) {
    Sea sea;
    sea.frame(0.0);
    wave::CausticOptions o;
    o.width = o.height = 1024;
    const wave::CausticPlan plan = wave::plan_caustics(floor_under(breeze().size, 4.0), o);
    std::vector<float> map(o.width * o.height);
    wave::evaluate_caustics(plan, sea.positions, sea.normals, sea.triangles, map);
    for (auto _ : state) benchmark::DoNotOptimize(wave::caustic_png(map, 1024, 1024, 4.0).size());
}
BENCHMARK(BM_caustics_png)->Unit(benchmark::kMillisecond)->UseRealTime();

// The sunbeam volume of one frame under that surface: 128 × 128 voxels a level, the
// levels (the argument) over a flat floor 8 m down (the surface outside the timing).
void BM_sun_volume(benchmark::State& state) {
    Sea sea;
    wave::CausticOptions o;
    o.sun = {0.3, 0.2, 0.93};
    o.attenuation = 0.08;
    const wave::SunVolumePlan plan = wave::plan_sun_volume(wave::plan_caustics(floor_under(breeze().size, 8.0), o),
                                                           wave::SunVolumeOptions{128, 128, static_cast<std::size_t>(state.range(0)), 1e-3});
    const wave::CausticMesh mesh = wave::plan_caustic_mesh(sea.triangles, sea.count);
    wave::CausticWorkspace workspace;
    std::vector<float> light(plan.nx * plan.ny * plan.nz);
    double t = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        sea.frame(t);
        state.ResumeTiming();
        wave::evaluate_sun_volume(plan, mesh, sea.positions, sea.normals, light, &workspace);
        benchmark::DoNotOptimize(light.data());
        t += 1.0 / 24.0;
    }
}
BENCHMARK(BM_sun_volume)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond)->UseRealTime();

// A 128 × 128 × 32 sunbeam volume as an OpenVDB file (half floats, one core).
void BM_sun_volume_vdb(benchmark::State& state) {
    Sea sea;
    sea.frame(0.0);
    wave::CausticOptions o;
    o.sun = {0.3, 0.2, 0.93};
    const wave::SunVolumePlan plan =
        wave::plan_sun_volume(wave::plan_caustics(floor_under(breeze().size, 8.0), o), wave::SunVolumeOptions{128, 128, 32, 1e-3});
    std::vector<float> light(plan.nx * plan.ny * plan.nz);
    wave::evaluate_sun_volume(plan, wave::plan_caustic_mesh(sea.triangles, sea.count), sea.positions, sea.normals, light);
    for (auto _ : state) benchmark::DoNotOptimize(wave::sun_volume_vdb(plan, light).size());
    state.counters["bytes"] = static_cast<double>(wave::sun_volume_vdb(plan, light).size());
}
BENCHMARK(BM_sun_volume_vdb)->Unit(benchmark::kMillisecond)->UseRealTime();

// Planning the surface's edges once (512² FFT grid: 263 k vertices, 524 k triangles).
void BM_caustics_mesh(benchmark::State& state) {
    Sea sea;
    for (auto _ : state) benchmark::DoNotOptimize(wave::plan_caustic_mesh(sea.triangles, sea.count).edges.size());
}
BENCHMARK(BM_caustics_mesh)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
