// Scene files: JSON → validated Scene, with JSON-pointer error messages; and the
// wiring of the static stages.
#include "libwave/scene.h"

#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/io.h"
#include "libwave/shade.h"
#include "core/files.h"
#include "core/json_input.h"
#include "core/limits.h"
#include "core/memory.h"
#include "surface_model.h"

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <set>
#include <sstream>

namespace wave {

using detail::fmt;

PreviewOptions scene_preview(const Scene& scene, const Seafloor& seafloor) {
    PreviewOptions o = scene.preview;
    o.camera = scene_camera(scene, seafloor);
    if (!scene.preview_look_at_set) {
        // Towards the domain's centre, but pitched down no more than keeps the horizon
        // 12 % of the picture below its top: the sea (and with a far field, the skirt)
        // meets the sky in view.
        const ElevationGrid& g = seafloor.grid;
        const std::array<double, 3> centre{0.5 * (g.x0 + g.x_max()), 0.5 * (g.y0 + g.y_max()), 0.0};
        const double dx = centre[0] - o.camera[0], dy = centre[1] - o.camera[1], dz = centre[2] - o.camera[2];
        const double across = std::hypot(dx, dy), reach = std::hypot(across, dz);
        const double most = (0.5 - 0.12) * o.vertical_fov_degrees * std::numbers::pi / 180.0;
        o.look_at = centre;
        if (across > 0.0 && std::atan2(-dz, across) > most)
            o.look_at = {o.camera[0] + reach * std::cos(most) * dx / across, o.camera[1] + reach * std::cos(most) * dy / across,
                         o.camera[2] - reach * std::sin(most)};
    }
    return o;
}

std::array<double, 3> scene_camera(const Scene& scene, const Seafloor& seafloor) {
    const ElevationGrid& g = seafloor.grid;
    if (scene.camera) {
        const auto& c = *scene.camera;
        if (c[0] >= g.x0 && c[0] <= g.x_max() && c[1] >= g.y0 && c[1] <= g.y_max() &&
            c[2] <= -depth_at(g, c[0], c[1]))
            throw InputError("scene: /camera/position [" + fmt(c[0]) + ", " + fmt(c[1]) + ", " + fmt(c[2]) +
                             "] is inside the seafloor (its elevation there is " + fmt(-depth_at(g, c[0], c[1])) + " m)");
        return c;
    }
    const double w = g.x_max() - g.x0, h = g.y_max() - g.y0, size = std::max(w, h);
    double dx = 0.0, dy = 1.0;
    if (!scene.waves.empty()) {
        const double len = std::hypot(scene.waves[0].direction_x, scene.waves[0].direction_y);
        dx = scene.waves[0].direction_x / len;
        dy = scene.waves[0].direction_y / len;
    }
    // From the open sea towards the shore, as a viewer on a boat would see the waves arrive.
    const double cx = g.x0 + 0.5 * w, cy = g.y0 + 0.5 * h;
    return {cx - dx * 1.1 * size, cy - dy * 1.1 * size, 0.4 * size};
}

CausticOptions scene_caustic_options(const Scene& scene, const ScenePlan& plan) {
    const Seafloor& seafloor = plan.seafloor;
    CausticOptions o;
    o.flat_water_beyond = plan.skirt.vertex_count() == 0;
    const double az = scene.preview.sun_azimuth_degrees * std::numbers::pi / 180.0;
    const double el = scene.preview.sun_elevation_degrees * std::numbers::pi / 180.0;
    o.sun = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
    const UnderwaterOptions u = scene.underwater.value_or(UnderwaterOptions{});
    o.attenuation = u.attenuation;
    const ElevationGrid& g = seafloor.grid;
    const double w = g.x_max() - g.x0, h = g.y_max() - g.y0, side = static_cast<double>(u.map_size);
    o.width = w >= h ? u.map_size : std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(side * w / h)));
    o.height = h >= w ? u.map_size : std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(side * h / w)));
    return o;
}

TraceOptions scene_trace_options(const Scene& scene, const Seafloor& seafloor) {
    TraceOptions trace = scene.trace;
    if (scene.orthogonals_per_grid_line > 0.0 && scene.surface.nx >= 2 && scene.surface.ny >= 2) {
        const ElevationGrid& g = seafloor.grid;
        const double cell = std::min((g.x_max() - g.x0) / static_cast<double>(scene.surface.nx - 1),
                                     (g.y_max() - g.y0) / static_cast<double>(scene.surface.ny - 1));
        trace.ray_spacing = cell / scene.orthogonals_per_grid_line;  // Ts'o §3.2.3
    }
    return trace;
}

Seafloor scene_seafloor(const Scene& scene) { return detail::surface_model(scene.surface_kind).seafloor(scene); }

namespace detail {

void plan_wind_sea(const OceanOptions& o, ScenePlan& p) {
    p.ocean = plan_ocean(o);
    if (o.spectrum.wind_speed * o.spectrum.wind_speed / kGravity < 2.0 * p.ocean.spacing())
        p.warnings.push_back("the ocean's largest waves (V²/g = " +
                             fmt(o.spectrum.wind_speed * o.spectrum.wind_speed / kGravity) +
                             " m) are shorter than two cells (" + fmt(p.ocean.spacing()) +
                             " m): raise /ocean/resolution or lower /ocean/size (Tessendorf §3.4)");
}

}  // namespace detail

namespace {

// The triangles of the surface's own vertices (before any refinement): the model's,
// and the skirt's when the far field continues it.
const std::vector<std::uint32_t>& surface_triangles(const Scene& scene, const ScenePlan& p) {
    return p.skirted_triangles.empty() ? detail::surface_model(scene.surface_kind).triangles(p) : p.skirted_triangles;
}

// A wind sea superposed on a coastal surface: its loop a whole multiple of the swell's.
void plan_superposed_wind_sea(const OceanOptions& options, ScenePlan& p) {
    OceanOptions o = options;
    const double base = p.loop_period;
    if (o.repeat_time == 0.0) {
        o.repeat_time = base * std::max(1.0, std::round(20.0 / base));  // the multiple nearest 20 s
    } else {
        const double r = o.repeat_time / base;
        if (std::round(r) < 1.0 || std::abs(r - std::round(r)) > 1e-6 * r)
            throw InputError("scene: /ocean/repeat_time " + fmt(o.repeat_time) +
                             " s is not a whole multiple of the swell's loop (" + fmt(base) +
                             " s), so the animation could not loop; use e.g. " +
                             fmt(base * std::max(1.0, std::round(r))) + " s");
    }
    detail::plan_wind_sea(o, p);
    p.loop_period = o.repeat_time;
}

// A loop shorter than one frame cannot be animated.
void refuse_short_loop(const Scene& scene, double loop_period) {
    if (loop_period * scene.fps >= 1.0) return;
    throw InputError("scene: the loop (" + fmt(loop_period) + " s) is shorter than one frame at " + fmt(scene.fps) +
                     " fps; lengthen " +
                     std::string(scene.ocean ? "/ocean/repeat_time" : detail::surface_model(scene.surface_kind).loop_keys) +
                     " or raise /animation/fps");
}

// The components every surface kind can carry, after the model planned its surface: a
// superposed FFT wind sea, Gerstner waves, and the depths of the rest vertices.
void plan_components(const Scene& scene, ScenePlan& p) {
    const bool own_ocean = p.ocean.n > 0;  // the surface is the FFT patch itself
    if (scene.ocean && !own_ocean) plan_superposed_wind_sea(*scene.ocean, p);
    refuse_short_loop(scene, p.loop_period);
    const ElevationGrid& g = p.seafloor.grid;
    p.rest_depth.resize(p.rest_x.size());
    for (std::size_t v = 0; v < p.rest_x.size(); ++v)
        p.rest_depth[v] = static_cast<float>(std::max(0.0, depth_at(g, p.rest_x[v], p.rest_y[v])));
    if (scene.ocean && !own_ocean) {
        // Wind waves calm down over the shelf (Kitaigorodskii's depth function at the peak).
        p.wind_sea_scale.resize(p.rest_x.size());
        for (std::size_t v = 0; v < p.rest_x.size(); ++v)
            p.wind_sea_scale[v] = static_cast<float>(wind_sea_depth_factor(p.ocean.peak_omega, p.rest_depth[v]));
    }
    // Gerstner waves disperse in the open ocean's depth over its patch, else in deep water.
    const double depth = own_ocean ? scene.ocean.value_or(OceanOptions{}).spectrum.depth : std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < scene.gerstner.size(); ++i) {
        const GerstnerSpec& s = scene.gerstner[i];
        const double k = 2.0 * std::numbers::pi / s.wavelength, len = std::hypot(s.direction_x, s.direction_y);
        GerstnerWave w{.kx = k * s.direction_x / len, .ky = k * s.direction_y / len, .amplitude = s.amplitude,
                       .omega = quantize_frequency(dispersion_omega(k, depth), p.loop_period), .phase = s.phase};
        p.gerstner.push_back(w);
    }
    if (gerstner_steepness(p.gerstner) >= 1.0)
        p.warnings.push_back("the Gerstner waves' Σ k A = " + fmt(gerstner_steepness(p.gerstner)) +
                             " >= 1: crests may loop over themselves (Tessendorf §3.1); lower the amplitudes");
}

double shortest_period(const Scene& scene) {
    double period = std::numeric_limits<double>::infinity();
    for (const WaveTrain& w : scene.waves) period = std::min(period, w.period);
    return period;
}

// The depth where the highest train breaks (H/γ): no wave shallower is unbroken.
double breaking_depth(const Scene& scene) {
    double depth = 1e-3;
    for (const WaveTrain& w : scene.waves) depth = std::max(depth, 2.0 * w.amplitude / scene.trace.breaker_index);
    return depth;
}

// How far the skirt reaches: the scene's distance, or far enough that its edge is
// within 1/2000 rad of the horizon from the scene's camera, and never less than
// kWorldReach: the sea and the land beyond reach 5 km from the domain in every
// direction, however small the domain or low the camera (a laboratory basin's camera
// a metre up gave a skirt of 55 m).
constexpr double kWorldReach = 5000.0;  // m

double skirt_distance(const Scene& scene, const ScenePlan& p) {
    if (scene.far_field->distance > 0.0) return scene.far_field->distance;
    const ElevationGrid& g = p.seafloor.grid;
    const double size = std::max(g.x_max() - g.x0, g.y_max() - g.y0);
    return std::max({2000.0 * std::max(0.0, scene_camera(scene, p.seafloor)[2]), 10.0 * size, kWorldReach});
}

// The far field's periodic components: each train's harmonics the model holds, each
// Gerstner wave.
std::vector<FarFieldWave> far_field_components(const Scene& scene, const ScenePlan& p, int harmonics) {
    std::vector<FarFieldWave> waves;
    for (const WaveTrain& w : scene.waves)
        for (int h = 1; h <= harmonics; ++h)
            waves.push_back({.omega = quantize_frequency(2.0 * std::numbers::pi / w.period, p.loop_period), .harmonic = h,
                             .direction_x = w.direction_x, .direction_y = w.direction_y});
    for (const GerstnerWave& w : p.gerstner)
        waves.push_back({.omega = w.omega, .direction_x = w.kx, .direction_y = w.ky, .k = std::hypot(w.kx, w.ky)});
    return waves;
}

// The model's own surface (with the Gerstner waves) at `times`, one frame after another.
std::vector<float> sample_model(const Scene& scene, const ScenePlan& p, const detail::SurfaceModel& model,
                                std::span<const double> times) {
    const std::size_t n = p.rest_x.size();
    std::vector<float> positions(3 * n * times.size()), normals(3 * n);
    std::unique_ptr<detail::ModelState> state = model.start(scene, p, false);
    detail::WindSeaState unused;
    for (std::size_t s = 0; s < times.size(); ++s) {
        const std::span<float> frame(&positions[3 * n * s], 3 * n);
        detail::ModelFrame f{.positions = frame, .normals = normals, .wind_sea = unused};
        model.move(scene, p, times[s], state.get(), f);
        if (!p.gerstner.empty()) add_gerstner_waves(p.gerstner, p.rest_x, p.rest_y, p.rest_depth, times[s], frame);
    }
    return positions;
}

// The skirt's vertices after the model's: rest positions, the depth of the seafloor
// continued outwards, and the wind sea as far as the skirt resolves its peak wavelength.
void append_skirt(ScenePlan& p) {
    p.model_vertices = p.rest_x.size();
    p.skirted_triangles.insert(p.skirted_triangles.end(), p.skirt.triangles.begin(), p.skirt.triangles.end());
    p.rest_x.insert(p.rest_x.end(), p.skirt.x.begin(), p.skirt.x.end());
    p.rest_y.insert(p.rest_y.end(), p.skirt.y.begin(), p.skirt.y.end());
    const double peak_wavelength = p.ocean.n > 0 ? 2.0 * std::numbers::pi * kGravity / (p.ocean.peak_omega * p.ocean.peak_omega) : 0.0;
    for (std::size_t v = 0; v < p.skirt.vertex_count(); ++v) {
        const auto depth = static_cast<float>(std::max(0.0, depth_at(p.seafloor.grid, p.skirt.x[v], p.skirt.y[v])));
        p.rest_depth.push_back(depth);
        if (!p.wind_sea_scale.empty())
            p.wind_sea_scale.push_back(static_cast<float>(wind_sea_depth_factor(p.ocean.peak_omega, depth) *
                                                          far_field_share(peak_wavelength, p.skirt.size[v])));
    }
}

// The skirt's edge (m) that keeps a wind sea of peak `wavelength` (m) resolved: the
// border's spacing growing by 0.3 d to a sixth of the wavelength, held over two
// wavelengths beyond the border, then growing as swell_skirt_size's beyond its band.
double wind_sea_skirt_size(const SkirtSite& site, double wavelength) {
    const double held = std::max(site.border_edge, wavelength / 6.0), band = 2.0 * wavelength;
    if (site.d <= band) return std::min(site.border_edge + 0.3 * site.d, held);
    const double past = site.d - band;
    return held + 0.08 * past + 0.3 * past * past / (past + 2.0 * wavelength);
}

// The far field (/surface/far_field): the skirt around the model's surface, its motion
// fitted on the model's border at spread times, the skirt's vertices appended.
void plan_far_field_stage(const Scene& scene, ScenePlan& p) {
    const detail::SurfaceModel& model = detail::surface_model(scene.surface_kind);
    if (!scene.far_field || model.far_field_harmonics == 0 || p.camera_grid.vertex_count() > 0) return;
    const std::vector<std::uint32_t>& triangles = model.triangles(p);
    SeaSkirtOptions o;
    o.distance = skirt_distance(scene, p);
    o.size = swell_skirt_size(p.seafloor, shortest_period(scene), scene.far_field->swell_wavelengths, breaking_depth(scene));
    // A wind sea on the coast runs on over the skirt as far as the skirt resolves it: its
    // peak wavelength held over two of them. Sized for the swell alone, the skirt's
    // edges outgrew a third of the wind sea's peak within a few metres of the border, its
    // fade (far_field_share) fell to 0 there, and the whitecaps stopped at the domain's
    // sides.
    if (p.ocean.n > 0) {
        const double wind = 2.0 * std::numbers::pi * kGravity / (p.ocean.peak_omega * p.ocean.peak_omega);
        o.size = [swell = std::move(o.size), wind](const SkirtSite& site) { return std::min(swell(site), wind_sea_skirt_size(site, wind)); };
    }
    if (model.skirt_size) o.size = model.skirt_size(scene, p, std::move(o.size));
    o.max_vertices = scene.surface.max_vertices;
    o.seafloor = &p.seafloor.grid;
    try {
        p.skirt = plan_sea_skirt(p.rest_x, p.rest_y, triangles, o);
    } catch (const LimitError& e) {
        throw LimitError("scene: " + std::string(e.what()) +
                         " (/surface/max_vertices); lower /surface/far_field/swell_wavelengths or its distance, or set "
                         "\"far_field\": false");
    }
    if (p.skirt.vertex_count() == 0) return;
    const std::vector<FarFieldWave> waves = far_field_components(scene, p, model.far_field_harmonics);
    const std::vector<double> times = far_field_sample_times(p.loop_period, waves.size());
    p.far_field = plan_far_field(p.skirt, p.seafloor.grid, waves, p.rest_x, p.rest_y, times, sample_model(scene, p, model, times));
    if (model.plan_skirt) model.plan_skirt(scene, p);
    p.skirted_triangles = triangles;
    append_skirt(p);
}

// The open ocean carried to the horizon: its patch tiles (the FFT is periodic), so a
// skirt round it samples the same fields wherever it lies, the patch's own waves and
// none other, and meets the patch's border vertices with the same values — no tile
// edge. The skirt holds the wind sea's peak wavelength at a sixth of it over two peak
// wavelengths (as a swell's band, swell_skirt_size), then grows by about a third of the
// distance; the wind sea fades as the skirt stops resolving its peak (far_field_share),
// as on a coastal scene's skirt. It reaches as far as a far field would (2000 camera
// heights, 10 patches, kWorldReach). The patch's vertices stay the model's; the skirt's
// take the wind sea through wind_sea_scale (0 on the patch: the model moved it).
void plan_ocean_skirt(const Scene& scene, ScenePlan& p) {
    if (scene.surface_kind != SurfaceKind::ocean || p.ocean.n == 0 || p.camera_grid.vertex_count() > 0) return;
    const double wavelength = 2.0 * std::numbers::pi * kGravity / (p.ocean.peak_omega * p.ocean.peak_omega);
    SeaSkirtOptions o;
    o.distance = std::max({2000.0 * std::max(0.0, scene_camera(scene, p.seafloor)[2]), 10.0 * p.ocean.size, kWorldReach});
    o.size = [wavelength](const SkirtSite& site) { return wind_sea_skirt_size(site, wavelength); };
    o.max_vertices = scene.surface.max_vertices;
    const std::vector<std::uint32_t>& triangles = p.patch_triangles;
    p.skirt = plan_sea_skirt(p.rest_x, p.rest_y, triangles, o);
    if (p.skirt.vertex_count() == 0) return;
    p.skirted_triangles = triangles;
    const std::size_t own = p.rest_x.size();
    p.rest_depth.resize(own);
    p.wind_sea_scale.assign(own, 0.0f);
    append_skirt(p);
    for (std::size_t v = own; v < p.rest_x.size(); ++v)
        p.wind_sea_scale[v] = static_cast<float>(far_field_share(wavelength, p.skirt.size[v - own]));
}

// lattice J₋ → J₋ per coarse vertex.
void fold_at_vertices(const ScenePlan& plan, bool patch, std::span<const float> lattice_j, std::span<float> out) {
    std::size_t first = 0;  // the first vertex sampled off the lattice
    if (patch) {  // the patch: (N+1)² vertices repeat the first row and column
        const std::size_t N = plan.ocean.n, side = N + 1;
        for (std::size_t row = 0; row < side; ++row) {
            const float* src = &lattice_j[(row == N ? 0 : row) * N];
            std::copy(src, src + N, &out[row * side]);
            out[row * side + N] = src[0];
        }
        first = side * side;  // then its skirt's, if any
    }
    if (first < plan.rest_x.size())
        sample_ocean_field(plan.ocean, lattice_j, std::span<const double>(plan.rest_x).subspan(first),
                           std::span<const double>(plan.rest_y).subspan(first),
                           std::span<const float>(plan.wind_sea_scale).subspan(first), out.subspan(first));
}

// The fold foam's threshold: the scene's /shade/fold_threshold when it gives one; else the
// J₋ at which the wind sea's foam covers the whitecap share (/shade/whitecap_coverage, or
// the wind's by Callaghan et al.), found on the lattice as frame 0 sees it (its fade
// window of past lattice times, every 4th point). Those past times' samples at the
// vertices are kept: a run from frame 0 starts with them (they were computed twice).
void plan_fold_foam(const Scene& scene, ScenePlan& p) {
    p.fold_foam = scene.fold_foam;
    if (p.ocean.n == 0 || !scene.ocean || scene.fold_threshold_set) return;
    const double target = scene.whitecap_coverage ? *scene.whitecap_coverage : whitecap_coverage(scene.ocean->spectrum.wind_speed);
    double step = 0.0;
    const std::vector<long long> lattice = fold_lattice(0.0, p.fold_foam, p.loop_period, step);  // newest first
    OceanWorkspace workspace(p.ocean.n);
    std::vector<std::vector<float>> past(lattice.size());
    for (std::size_t i = 0; i < lattice.size(); ++i) {
        detail::size_for_overwrite(past[lattice.size() - 1 - i], p.ocean.n * p.ocean.n);
        evaluate_ocean_jacobian(p.ocean, static_cast<double>(lattice[i]) * step, workspace, past[lattice.size() - 1 - i]);
    }
    p.fold_foam.threshold = fold_threshold_for_coverage(past, step, p.fold_foam, target, 4);
    p.whitecap_coverage = target;
    std::vector<float> at_vertices(p.rest_x.size());
    for (std::size_t i = 0; i < lattice.size(); ++i) {
        fold_at_vertices(p, scene.surface_kind == SurfaceKind::ocean, past[lattice.size() - 1 - i], at_vertices);
        p.fold_past.emplace_back(lattice[i], fold_sample(at_vertices, p.fold_foam));
    }
}

}  // namespace

// A seafloor without water gives every traced surface nothing to move: said once, for
// every kind (the height field said its isobath set was empty; the wave field, that
// the seafloor had no water).
void refuse_all_land(const Scene& scene, const Seafloor& seafloor) {
    if (surface_kind_traces(scene.surface_kind) == Traced::nothing) return;
    const SeafloorStats st = seafloor_stats(seafloor);
    if (st.depth_max > 0.0) return;
    throw InputError("scene: no water surface to animate over " + seafloor.source +
                     ": the seafloor is all land (no node below the water level" +
                     (st.nodata_count > 0 ? std::string("; NODATA read as land: /seafloor/nodata_policy") : std::string()) +
                     "); check /seafloor/sign and /seafloor/vertical_offset");
}

static ScenePlan plan_on(const Scene& scene, Seafloor seafloor, PlanStages stages);

ScenePlan plan_scene(const Scene& scene, PlanStages stages) { return plan_on(scene, scene_seafloor(scene), stages); }

ScenePlan plan_scene(const Scene& scene, Seafloor seafloor, PlanStages stages) {
    if (scene.surface_kind == SurfaceKind::ocean)
        throw InputError("plan_scene: the open ocean stands on its own flat bottom (/ocean/depth), not on a given seafloor");
    return plan_on(scene, std::move(seafloor), stages);
}

static ScenePlan plan_on(const Scene& scene, Seafloor seafloor, PlanStages stages) {
    ScenePlan p;
    p.seafloor = std::move(seafloor);
    refuse_all_land(scene, p.seafloor);
    scene_camera(scene, p.seafloor);  // a camera inside the seafloor is an input error, found before the work
    // Without a wind sea (whose loop is its own, ~20 s) every loop holds at least the
    // first train's period: a too-short one is refused before the work.
    if (!scene.waves.empty() && !scene.ocean && stages != PlanStages::trace) refuse_short_loop(scene, scene.waves[0].period);
    detail::surface_model(scene.surface_kind).plan(scene, p, stages);
    if (stages == PlanStages::trace) return p;
    plan_components(scene, p);
    plan_far_field_stage(scene, p);
    plan_ocean_skirt(scene, p);
    plan_fold_foam(scene, p);
    // The breakers' whitewater over the loop, on the surface the breakers move.
    if (scene.whitewater && scene.breakers)
        p.whitewater = jeschke_whitewater_events(p.breakers, detail::surface_model(scene.surface_kind).triangles(p));
    else if (scene.whitewater && scene.surface_kind == SurfaceKind::ray_strips && !scene.camera_grid) {
        // Gonzato's profile: where its breaking foam comes from (the same strips and options).
        const RayStrips& strips = p.water_strips.vertex_count() > 0 ? p.water_strips : p.strips;
        p.whitewater = gonzato_whitewater_events(strips, p.motion, scene.foam, detail::surface_model(scene.surface_kind).triangles(p));
    }
    // A run's particles are refused before any frame is made (the wind sea's, which come
    // with each frame's folds, as each frame makes them).
    if (scene.whitewater) check_whitewater_bound(p.whitewater, *scene.whitewater);
    if (stages == PlanStages::all) refine_scene_plan(scene, p);
    return p;
}

std::size_t scene_loop_frames(const Scene& scene, const ScenePlan& plan) {
    const double frames = std::round(plan.loop_period * scene.fps);
    if (!(frames < 1e18)) return std::numeric_limits<std::size_t>::max();  // refused by max_frames, never cast
    return std::max<std::size_t>(1, static_cast<std::size_t>(frames));
}

void refine_scene_plan(const Scene& scene, ScenePlan& p) {
    // Subdivision: the surface's topology refined once; frames apply the stencils.
    if (scene.refine) {
        const std::vector<std::uint32_t>& coarse = surface_triangles(scene, p);
        if (!scene.refine->adaptive) {
            p.refinement = plan_refinement(p.rest_x.size(), coarse, *scene.refine, scene.max_refined_vertices);
        } else {
            // Where the surface bends: its normals at 8 times spread over the loop (the
            // crests move, so one frame would not do), and the camera for nearness.
            Scene probe = scene;
            probe.refine.reset();
            probe.attributes = Scene::Attributes::none;
            probe.color = false;
            const std::size_t loop_frames = scene_loop_frames(scene, p);
            std::vector<float> normals;
            for (std::size_t k = 0; k < 8; ++k) {
                const std::size_t f = k * loop_frames / 8;
                const SceneAnimation a = animate_scene(probe, p, 2e9, FrameRange{f, f + 1});
                normals.insert(normals.end(), a.normals.begin(), a.normals.end());
            }
            const AdaptiveCriteria criteria{normals, p.rest_x, p.rest_y, scene_camera(scene, p.seafloor)};
            p.refinement = plan_refinement(p.rest_x.size(), coarse, *scene.refine, scene.max_refined_vertices, &criteria);
        }
    }
}

namespace {

// A frame's file of an underwater sequence (kCausticImages, kSunbeamVolumes).
std::string underwater_file_name(const char* pattern, std::size_t frame) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, pattern, static_cast<int>(frame));
    return buffer;
}

// Frame k of a chunk's underwater files beside the animation, named by loop frame: its
// caustic map, then its sunbeam volume (each list empty or one per frame of the chunk).
void for_underwater_files(std::size_t first_frame, std::size_t k, std::span<const std::string> caustics,
                          std::span<const std::string> sunbeams, std::span<const std::string> whitewater,
                          const std::function<void(std::string, const std::string&)>& file) {
    if (!caustics.empty()) file(underwater_file_name(kCausticImages, first_frame + k), caustics[k]);
    if (!sunbeams.empty()) file(underwater_file_name(kSunbeamVolumes, first_frame + k), sunbeams[k]);
    if (!whitewater.empty()) file(underwater_file_name(kWhitewaterPoints, first_frame + k), whitewater[k]);
}

// The caustic maps and sunbeam volumes beside the animation: in the files form after
// each frame's own files (a frame's entry lists them together), else after the file.
void add_underwater_files(const MorphAnimationView& view, std::span<const std::string> caustics, std::span<const std::string> sunbeams,
                          std::span<const std::string> whitewater, Scene::Form form, EncodedFiles& files) {
    if (caustics.empty() && sunbeams.empty() && whitewater.empty()) return;
    const std::size_t per_frame = form == Scene::Form::files ? files.size() / view.frame_count : 0;
    EncodedFiles grouped;
    if (per_frame == 0) grouped.swap(files);  // the animation's files first, whole
    for (std::size_t k = 0; k < view.frame_count; ++k) {
        for (std::size_t i = 0; i < per_frame; ++i) grouped.push_back(std::move(files[k * per_frame + i]));
        for_underwater_files(view.first_frame, k, caustics, sunbeams, whitewater,
                             [&](std::string name, const std::string& bytes) { grouped.emplace_back(std::move(name), bytes); });
    }
    files.swap(grouped);
}

// animation.glb, or animation-frames-A-B.glb for a slice.
std::string animation_file_name(std::size_t first_frame, std::size_t frame_count, bool whole) {
    char slice_name[64];
    std::snprintf(slice_name, sizeof slice_name, "animation-frames-%zu-%zu.glb", first_frame, first_frame + frame_count);
    return whole ? "animation.glb" : slice_name;
}

// The pc2 form's base mesh (frame 0 of the view) as .glb and .obj beside the caches.
void add_pc2_base(const MorphAnimationView& view, const std::string& base, EncodedFiles& files) {
    files.emplace_back(base + ".glb", gltf_frame_glb(view, 0));
    files.emplace_back(base + ".obj", mesh_to_obj(view.positions.first(3 * view.vertex_count), view.triangles,
                                                  "libwave: base mesh of " + base + ".pc2, z up"));
}

// The pc2 form's shading "points" of frames: (reflect, refract, foam) per vertex.
std::vector<float> pc2_shading(const MorphAnimationView& view) {
    std::vector<float> shading(3 * view.vertex_count * view.frame_count);
    for (std::size_t i = 0; i < view.vertex_count * view.frame_count; ++i) {
        shading[3 * i] = view.reflect[i];
        shading[3 * i + 1] = view.refract[i];
        shading[3 * i + 2] = view.foam[i];
    }
    return shading;
}

// Each .glb becomes name.gltf + name.bin (the .bin named relative to the .gltf).
void split_gltf_container(EncodedFiles& files) {
    EncodedFiles split;
    for (auto& [name, bytes] : files) {
        if (!name.ends_with(".glb")) {
            split.emplace_back(std::move(name), std::move(bytes));
            continue;
        }
        const std::string base = name.substr(0, name.size() - 4);  // without ".glb"
        const std::string bin = base + ".bin";
        GltfFiles g = glb_to_gltf(bytes, std::filesystem::path(bin).filename().string());
        split.emplace_back(base + ".gltf", std::move(g.json));
        split.emplace_back(bin, std::move(g.bin));
    }
    files.swap(split);
}

}  // namespace

EncodedFiles encode_animation(const MorphAnimationView& view, Scene::Form form, Scene::Container container, bool whole,
                              std::span<const std::string> caustics, std::span<const std::string> sunbeams,
                              std::span<const std::string> whitewater) {
    EncodedFiles files;
    const std::string animation_name = animation_file_name(view.first_frame, view.frame_count, whole);
    if (form == Scene::Form::morph) files.emplace_back(animation_name, gltf_morph_glb(view));
    if (form == Scene::Form::nodes) files.emplace_back(animation_name, gltf_nodes_glb(view));
    if (form == Scene::Form::pc2) {
        // Point caches beside a base mesh (frame 0 of the range) as .glb and .obj, z up as
        // written; the shading as a second cache of (reflect, refract, foam) "points".
        const std::string base = whole ? "animation" : animation_name.substr(0, animation_name.size() - 4);
        const std::size_t n = view.vertex_count;
        add_pc2_base(view, base, files);
        const auto start = static_cast<float>(view.first_frame);
        files.emplace_back(base + ".pc2", pc2_bytes(view.positions, n, view.frame_count, start));
        if (!view.foam.empty()) files.emplace_back(base + "-shading.pc2", pc2_bytes(pc2_shading(view), n, view.frame_count, start));
    }
    if (form == Scene::Form::files)
        for (std::size_t k = 0; k < view.frame_count; ++k) {
            char name[48];
            std::snprintf(name, sizeof name, "frames/frame-%04zu.glb", view.first_frame + k);
            files.emplace_back(name, gltf_frame_glb(view, k));
        }
    if (container == Scene::Container::gltf) split_gltf_container(files);
    add_underwater_files(view, caustics, sunbeams, whitewater, form, files);
    return files;
}

bool streamed_form(const Scene& scene) { return streamed_form(scene.form, scene.quantize); }

namespace {

// A file written as the frames come, removed unless it was finished.
struct PartialFile {
    std::string path;
    std::FILE* file = nullptr;
    explicit PartialFile(std::string p) : path(std::move(p)), file(std::fopen(path.c_str(), "wb")) {
        if (!file) throw RuntimeError(path + ": cannot create: " + std::strerror(errno));
    }
    ~PartialFile() {
        if (file) {
            std::fclose(file);
            std::remove(path.c_str());
        }
    }
    void write(const void* data, std::size_t n) {
        if (n > 0 && std::fwrite(data, 1, n, file) != n) throw RuntimeError(path + ": cannot write: " + std::strerror(errno));
    }
    void close() {
        if (std::fclose(std::exchange(file, nullptr)) != 0) {
            std::remove(path.c_str());
            throw RuntimeError(path + ": cannot write: " + std::strerror(errno));
        }
    }
};

// The pc2 form streamed: the base mesh from the first chunk, then the caches' samples.
struct Pc2Stream {
    std::string folder, base;
    std::optional<PartialFile> positions{}, shading{};

    void start(const MorphAnimationView& first, std::size_t frames, Scene::Container container, EncodedFiles& files) {
        add_pc2_base(first, base, files);
        if (container == Scene::Container::gltf) split_gltf_container(files);
        const std::string header = pc2_header(first.vertex_count, frames, static_cast<float>(first.first_frame));
        positions.emplace(folder + "/" + base + ".pc2");
        positions->write(header.data(), header.size());
        if (first.foam.empty()) return;
        shading.emplace(folder + "/" + base + "-shading.pc2");
        shading->write(header.data(), header.size());
    }
    void add(const MorphAnimationView& chunk) {
        positions->write(chunk.positions.data(), chunk.positions.size_bytes());
        if (!shading) return;
        const std::vector<float> s = pc2_shading(chunk);
        shading->write(s.data(), s.size() * sizeof(float));
    }
    void finish(std::vector<std::pair<std::string, std::size_t>>& written) {
        for (std::optional<PartialFile>* f : {&positions, &shading}) {
            if (!*f) continue;
            const auto bytes = static_cast<std::size_t>(std::ftell((*f)->file));
            (*f)->close();
            written.emplace_back(std::filesystem::path((*f)->path).filename().string(), bytes);
        }
    }
};

}  // namespace

bool streamed_form(Scene::Form form, bool quantize) noexcept {
    return form != Scene::Form::files && (!quantize || form == Scene::Form::morph);
}

struct StreamedWriter::State {
    std::optional<AnimationFileWriter> glb;
    Pc2Stream pc2;
    EncodedFiles small;  // the pc2 form's base mesh
    std::string folder;
};

StreamedWriter::StreamedWriter(const std::string& folder, Scene::Form form, Scene::Container container, bool whole,
                               const MorphAnimationView& first, std::size_t frame_count)
    : state_(std::make_unique<State>()) {
    if (!streamed_form(form, first.quantize))
        throw InputError("export: the files form and quantised nodes or pc2 files are not streamed");
    const std::string name = animation_file_name(first.first_frame, frame_count, whole);
    state_->folder = folder;
    if (form == Scene::Form::pc2) {
        state_->pc2.folder = folder;
        state_->pc2.base = whole ? "animation" : name.substr(0, name.size() - 4);
        state_->pc2.start(first, frame_count, container, state_->small);
        return;
    }
    const bool gltf = container == Scene::Container::gltf;
    const std::string path = folder + "/" + (gltf ? name.substr(0, name.size() - 4) + ".gltf" : name);
    state_->glb.emplace(path, form == Scene::Form::morph ? AnimationFileWriter::Form::morph : AnimationFileWriter::Form::nodes,
                        gltf, first, frame_count);
}

StreamedWriter::~StreamedWriter() = default;

void StreamedWriter::append(const MorphAnimationView& chunk) {
    if (state_->glb) state_->glb->append(chunk);
    else state_->pc2.add(chunk);
}

std::vector<std::pair<std::string, std::size_t>> StreamedWriter::finish() {
    if (state_->glb) return state_->glb->finish();
    std::vector<std::pair<std::string, std::size_t>> written;
    for (const auto& [file, bytes] : state_->small) {
        write_file_atomic(state_->folder + "/" + file, bytes);
        written.emplace_back(file, bytes.size());
    }
    state_->pc2.finish(written);
    return written;
}

StreamedAnimation stream_animation(AnimationStream& stream, const Scene& scene, const std::string& folder, bool whole,
                                   std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& progress) {
    if (!streamed_form(scene))
        throw InputError("scene: the files form and quantised nodes or pc2 files are not streamed by stream_animation");
    StreamedAnimation out;
    out.z_min = std::numeric_limits<float>::infinity();
    out.z_max = -std::numeric_limits<float>::infinity();
    const std::size_t frames = stream.frame_count();
    std::optional<StreamedWriter> writer;
    std::vector<std::string> maps;  // caustic maps and sunbeam volumes written, in order
    SceneAnimation a;
    // Quantised morph targets need their delta range before the first target: a pass
    // over the frames' positions alone finds it.
    const std::optional<double> quantize_range =
        scene.quantize ? std::optional<double>(stream.position_delta_range(chunk)) : std::nullopt;
    try {
        // The range's first frame alone first (the file's settings, and the frame kept
        // for the caller), then `chunk` frames at a time.
        while (stream.next(a, stream.frames_left() == frames ? 1 : std::max<std::size_t>(1, chunk), progress) > 0) {
            MorphAnimationView view = a.view();
            view.quantize_range = quantize_range;
            if (a.first_frame == stream.first_frame()) {
                writer.emplace(folder, scene.form, scene.container, whole, view, frames);
                out.first = a;
            }
            writer->append(view);
            for (std::size_t k = 0; k < a.frame_count; ++k)
                for_underwater_files(a.first_frame, k, a.caustics, a.sunbeams, a.whitewater, [&](std::string name, const std::string& bytes) {
                    maps.push_back(std::move(name));
                    std::filesystem::create_directories((std::filesystem::path(folder) / maps.back()).parent_path());
                    write_file_atomic(folder + "/" + maps.back(), bytes);
                });
            out.z_min = std::min(out.z_min, a.z_min);
            out.z_max = std::max(out.z_max, a.z_max);
        }
    } catch (...) {
        for (const std::string& m : maps) std::remove((folder + "/" + m).c_str());
        throw;
    }
    out.files = writer->finish();
    for (const std::string& m : maps) out.files.emplace_back(m, std::filesystem::file_size(std::filesystem::path(folder) / m));
    return out;
}

MorphAnimationView SceneAnimation::view() const {
    MorphAnimationView v = animation_view(*this);
    v.draco = draco;
    v.quantize = quantize;
    v.meshopt = meshopt;
    return v;
}

namespace {

// The sunbeam volumes: a VDB per frame, ~1 byte a voxel (measured 0.87 on
// examples/sunbeams-cove.json: half floats, compressed, the ground and air inactive);
// while a frame is computed, two volumes in turn (4 bytes a voxel each) and the VDB tree
// of the one being encoded with its file (~8).
constexpr double kSunbeamFileBytesPerVoxel = 1.0, kSunbeamWorkBytesPerVoxel = 16.0;

double sunbeam_voxels(const Scene& scene) {
    if (!scene.underwater || !scene.underwater->sunbeams) return 0.0;
    const SunVolumeOptions& o = *scene.underwater->sunbeams;
    return static_cast<double>(o.nx) * static_cast<double>(o.ny) * static_cast<double>(o.nz);
}

// Frames side by side (docs/motion.md "Frames side by side"). A frame's passes each
// share their vertices out among the cores and wait for the slowest: at 66 k vertices
// (a 256² ocean) a frame is ten such joins of 50–100 µs, and on a shared machine each
// waits for its slowest core. Below kLaneVertices whole frames run at once instead,
// each on a run of its own (its model state, workspace and fold-foam samples), and a
// frame's own passes run inside it. A frame computes the same bits on any run, so the
// output does not depend on how many run side by side. Not with underwater maps or
// volumes (each frame's map is long and parallel by itself).
constexpr std::size_t kLaneVertices = std::size_t{1} << 18;
constexpr std::size_t kMaxLanes = 8;

std::size_t frame_lanes(const Scene& scene, std::size_t vertices, std::size_t frames) {
    const bool underwater = scene.underwater && (scene.underwater->caustics || scene.underwater->sunbeams);
    if (underwater || vertices > kLaneVertices || frames < 2) return 1;
    const auto cores = std::min(static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()),
                                tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    return std::clamp<std::size_t>(std::min(cores, frames), 1, kMaxLanes);
}

}  // namespace

Scene resolve_codec(Scene scene, const RunEstimate& plain) {
    if (scene.codec_auto && !scene.draco && !scene.quantize && !scene.meshopt)
        scene.meshopt = scene.form != Scene::Form::pc2 && plain.output_bytes > kAutoCodecBytes;
    scene.codec_auto = false;
    return scene;
}

RunEstimate estimate_run(const Scene& scene, const ScenePlan& plan, double planned_resident_bytes, std::size_t run_frames) {
    RunEstimate e;
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    const std::size_t coarse_triangles = surface_triangles(scene, plan).size() / 3;
    if (refined) {
        e.vertices = refined->fine_vertices;
        e.triangles = refined->triangles.size() / 3;
    } else if (scene.refine) {  // not planned yet (PlanStages::surface): predicted
        const double t = refined_triangle_estimate(coarse_triangles, *scene.refine);
        e.triangles = t < 1e18 ? static_cast<std::size_t>(t) : std::numeric_limits<std::size_t>::max();
        e.vertices = e.triangles / 2;
    } else {
        e.vertices = plan.rest_x.size();
        e.triangles = coarse_triangles;
    }
    const bool fine = scene.refine.has_value();
    e.frames = scene_loop_frames(scene, plan);
    const double n = static_cast<double>(e.vertices), loop = static_cast<double>(e.frames);
    // The frames the run writes: its files and, for a file written whole, the arrays it holds.
    const double frames = run_frames > 0 ? std::min(loop, static_cast<double>(run_frames)) : loop;
    const bool shaded = scene.attributes != Scene::Attributes::none;
    // animate_scene: positions + normals, reflect/refract/foam, colour (floats).
    const double arrays_per_vertex = 24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0);
    e.frame_array_bytes = loop * n * arrays_per_vertex;
    const double run_arrays = frames * n * arrays_per_vertex;
    // The writer: POSITION + NORMAL, TEXCOORD_0, shading (UV maps 2 × vec2, or 3 floats), COLOR_0.
    const double shading = scene.attributes == Scene::Attributes::uv_maps ? 16.0 : scene.attributes == Scene::Attributes::named ? 12.0 : 0.0;
    const double per_frame_vertex = 24.0 + shading + (scene.color ? 12.0 : 0.0);
    const double indices = 12.0 * static_cast<double>(e.triangles), uv0 = 8.0 * n;
    constexpr double kMeshoptShare = 0.5;  // EXT_meshopt_compression's bytes over the floats' (measured: docs/export.md)
    const double draco_frame = 9.2 * n;  // measured: default scene (the water mesh), 14-bit positions (see RunEstimate)
    switch (scene.form) {
        case Scene::Form::morph:
            e.output_bytes = (scene.draco ? draco_frame : n * per_frame_vertex + uv0 + indices) +
                             frames * n * per_frame_vertex * (scene.quantize ? 0.6 : scene.meshopt ? kMeshoptShare : 1.0);
            break;
        case Scene::Form::nodes:  // meshes share the indices and TEXCOORD_0
            e.output_bytes = scene.draco ? frames * draco_frame
                                         : indices + uv0 + frames * n * per_frame_vertex * (scene.quantize ? 0.7 : scene.meshopt ? kMeshoptShare : 1.0);
            break;
        case Scene::Form::files:
            e.output_bytes = frames * (scene.draco ? draco_frame : indices + uv0 + n * per_frame_vertex * (scene.quantize ? 0.7 : scene.meshopt ? kMeshoptShare : 1.0));
            break;
        case Scene::Form::pc2:  // positions and the shading as float triples per frame, the base mesh twice
            e.output_bytes = frames * n * (12.0 + (shaded ? 12.0 : 0.0)) + 2.0 * (n * per_frame_vertex + uv0 + indices);
            break;
    }
    // The seafloor beside the water (morph and nodes files; the files form's frame 0):
    // float positions and colours and the triangles of a grid of at most 256 a side.
    const ElevationGrid& g = plan.seafloor.grid;
    if (scene.dress_seafloor && surface_kind_traces(scene.surface_kind) != Traced::nothing && g.nx >= 2 && g.ny >= 2) {
        const double step = static_cast<double>(std::max<std::size_t>(1, (std::max(g.nx, g.ny) + 255) / 256));
        const double cols = std::floor(static_cast<double>(g.nx - 1) / step) + 1.0, rows = std::floor(static_cast<double>(g.ny - 1) / step) + 1.0;
        e.output_bytes += 24.0 * cols * rows + 24.0 * (cols - 1.0) * (rows - 1.0);
    }
    // The caustic maps (/underwater): a PNG per frame, ~1.2 bytes a pixel (measured on a
    // 1024² map of a breeze-driven sea: 1.17 MB); while a frame is computed, its map
    // (4 bytes a pixel) and the PNG's 16-bit pixels (2).
    double caustic_work = 0.0;
    if (scene.underwater && scene.underwater->caustics && g.nx >= 2 && g.ny >= 2) {
        const CausticOptions o = scene_caustic_options(scene, plan);
        const double pixels = static_cast<double>(o.width) * static_cast<double>(o.height);
        e.output_bytes += frames * 1.2 * pixels;
        caustic_work = 6.0 * pixels;
    }
    if (g.nx >= 2 && g.ny >= 2) {  // the sunbeam volumes (kSunbeam…BytesPerVoxel)
        e.output_bytes += frames * kSunbeamFileBytesPerVoxel * sunbeam_voxels(scene);
        caustic_work += kSunbeamWorkBytesPerVoxel * sunbeam_voxels(scene);
    }
    // Without a measured plan: ~30 MB of process and libraries, ~1.5 kB per surface
    // vertex of plan (isobaths, fronts, the OpenMesh strips, motion fields), measured on
    // the default scene. Refinement stencils ~12 weights per fine vertex; a quantised
    // single file holds its bytes twice at the end (the buffer and the file's string),
    // the files form one chunk of frames, a streamed form one chunk and one frame.
    const double planned = planned_resident_bytes > 0.0 ? planned_resident_bytes : 30e6 + 1500.0 * static_cast<double>(plan.rest_x.size());
    // While frames run, ~12 MB more than a process that has only planned: the export's
    // and Draco's code and buffers, the worker threads' stacks (measured over the
    // examples, bench/memory_estimate.py).
    // Draco's encoder holds ~650 B a vertex while it compresses a frame (measured: the
    // open ocean, the Okushiri coast).
    // A run's own state beside the plan: the normals' vertex–face adjacency (~32 B a
    // vertex) and, with an FFT ocean, its transform buffers (4 pairs' complex N² and
    // the frame's h̃: ~40 B a lattice cell).
    const double lattice = static_cast<double>(plan.ocean.n) * static_cast<double>(plan.ocean.n);
    // Frames side by side below kLaneVertices: a run's state per lane.
    const double lanes = static_cast<double>(frame_lanes(scene, e.vertices, static_cast<std::size_t>(frames)));
    const double run_state = lanes * (32.0 * n + 40.0 * lattice);
    const double base = planned + 12e6 + run_state + (fine ? 96.0 * n : 0.0) + caustic_work + (scene.draco ? 650.0 * n : 0.0);
    // The ray strips' PLY, written when the frames are done: their OpenMesh TriMesh and
    // the file's bytes (~400 B a strip vertex, measured on Gonzato's island).
    const double ply = 400.0 * static_cast<double>(plan.strips.vertex_count());
    const double chunk = std::min(frames, static_cast<double>(files_form_chunk(e)));
    if (scene.form == Scene::Form::files) {  // one chunk of frames at a time, each frame encoded and written alone
        e.peak_memory_bytes = base + std::max(ply, run_arrays * chunk / frames + 2.0 * e.output_bytes / frames);
    } else if (streamed_form(scene)) {
        // One chunk of frames, one frame's attributes being encoded (twice: glTF axes and
        // deltas), the one-hot weights or scales (frames² floats) and the glTF JSON's
        // model (~6 kB a frame while tinygltf and nlohmann serialise it at the end).
        const double frame_out = (e.output_bytes - (scene.form == Scene::Form::pc2 ? 2.0 * (n * per_frame_vertex + uv0 + indices) : 0.0)) / frames;
        e.peak_memory_bytes = base + std::max(ply, run_arrays * chunk / frames + 2.0 * frame_out + 4.0 * frames * frames + 6e3 * frames);
    } else {  // every frame's arrays, and the encoded files held until they are published
        e.peak_memory_bytes = base + run_arrays + 2.0 * e.output_bytes + ply;
    }
    return e;
}

namespace {

// What lowers a run's memory, or raises its limit: the end of both memory refusals.
std::string memory_advice(const Scene& scene) {
    return (scene.refine ? std::string("lower /refine/level, or ") : std::string()) +
           (scene.camera_grid ? std::string("raise /surface/camera_grid/pixel_step or lower /surface/camera_grid/image, or ")
                              : std::string()) +
           (scene.quantize && scene.form != Scene::Form::morph
                ? std::string("use the morph form or drop /outputs/quantize (quantised nodes files are written whole), or ")
                : std::string()) +
           std::string(detail::surface_model(scene.surface_kind).size_keys) + ", or raise the limit (wave run --max-memory-gb)";
}

}  // namespace

double planned_memory_floor_bytes(const Scene& scene) {
    if (!scene.ocean) return 0.0;
    // The lattice: h̃0, conj h̃0(−k) (complex float), ω (double), ω̄ steps (int32); the
    // workspace: eight half spectra (complex float) and eight real fields (float).
    const double n = static_cast<double>(scene.ocean->resolution), lattice = (8.0 + 8.0 + 8.0 + 4.0) * n * n,
                 workspace = 8.0 * 8.0 * n * (n / 2.0 + 1.0) + 8.0 * 4.0 * n * n;
    const bool shaded = scene.attributes != Scene::Attributes::none;
    const double frame = scene.surface_kind == SurfaceKind::ocean
                             ? (n + 1.0) * (n + 1.0) * (24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0))
                             : 0.0;
    return lattice + workspace + frame;
}

void check_plan_limits(const Scene& scene, double max_bytes) {
    // A camera grid's vertices, from the scene alone: every pixel_step-th pixel of every
    // row (rows that miss the water are dropped later; a bound, not a guess), at what a
    // run of one holds a vertex at its peak (the plan's arrays, the breakers resampled on
    // it, one frame and its file: estimate_run has 4 GB for 16 M vertices; 260 bytes, a margin over it).
    // At the schema's 10⁸ pixels and step 1, validate built 13 GB of plan before a limit
    // named other keys; at 16 M vertices it planned 2.2 GB before refusing the run's 4 GB.
    if (scene.camera_grid && scene.camera_grid->pixel_step > 0) {
        const GridCamera& c = *scene.camera_grid;
        const double columns = std::ceil(static_cast<double>(c.image_width) / static_cast<double>(c.pixel_step)),
                     rows = std::ceil(static_cast<double>(c.image_height) / static_cast<double>(c.pixel_step));
        const double per_vertex = 260.0;
        if (const double bytes = columns * rows * per_vertex; bytes > max_bytes)
            throw LimitError("scene: /surface/camera_grid/image [" + std::to_string(c.image_width) + ", " + std::to_string(c.image_height) +
                             "] at /surface/camera_grid/pixel_step " + std::to_string(c.pixel_step) + " samples up to " +
                             detail::format_count(static_cast<std::size_t>(columns * rows)) + " vertices, about " +
                             fmt(std::ceil(bytes / 1e7) / 100.0) + " GB at a run's peak (" + fmt(per_vertex) +
                             " bytes a vertex), over the limit of " + fmt(max_bytes / 1e9) +
                             " GB; raise /surface/camera_grid/pixel_step or lower /surface/camera_grid/image, or raise the limit "
                             "(wave run --max-memory-gb)");
    }
    if (const double volume = kSunbeamWorkBytesPerVoxel * sunbeam_voxels(scene); volume > max_bytes) {
        const SunVolumeOptions& o = *scene.underwater->sunbeams;
        throw LimitError("scene: /underwater/sunbeams/voxels [" + std::to_string(o.nx) + ", " + std::to_string(o.ny) + ", " +
                         std::to_string(o.nz) + "] need about " + fmt(std::ceil(volume / 1e7) / 100.0) +
                         " GB while a frame is computed (16 bytes a voxel), over the limit of " + fmt(max_bytes / 1e9) +
                         " GB; give fewer voxels, or raise the limit (wave run --max-memory-gb)");
    }
    const double floor = planned_memory_floor_bytes(scene);
    if (floor > max_bytes)
        throw LimitError("scene: /ocean/resolution " + std::to_string(scene.ocean->resolution) + " needs at least " +
                         fmt(std::ceil(floor / 1e7) / 100.0) + " GB before its first frame is written (its lattice, transforms" +
                         (scene.surface_kind == SurfaceKind::ocean ? " and one frame" : "") + "), over the limit of " +
                         fmt(max_bytes / 1e9) + " GB; lower /ocean/resolution, or raise the limit (wave run --max-memory-gb)");
}

void check_run_limits(const Scene& scene, const RunEstimate& e, std::size_t frames, double max_bytes) {
    if (e.frames > scene.max_frames)
        throw LimitError("scene: the loop holds " + detail::format_count(e.frames) + " frames (at " + fmt(scene.fps) +
                         " fps), more than the limit of " + detail::format_count(scene.max_frames) +
                         "; lower /animation/fps, or raise /animation/max_frames");
    const bool shaded = scene.attributes != Scene::Attributes::none;
    const double bytes_per_vertex = 24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0);
    if (static_cast<double>(frames) * static_cast<double>(e.vertices) * bytes_per_vertex > max_bytes)
        throw LimitError("scene: the animation would hold " + detail::format_count(frames) + " frames of " +
                         detail::format_count(e.vertices) + " vertices (over " + fmt(max_bytes / 1e9) +
                         " GB of per-frame arrays); " + memory_advice(scene));
    // The whole run's peak (a streamed run holds a chunk of frames, but its plan, e.g. a
    // subdivision's stencils, can still outgrow the machine).
    if (e.peak_memory_bytes > max_bytes)
        throw LimitError("scene: a run would need about " + fmt(std::ceil(e.peak_memory_bytes / 1e7) / 100.0) +
                         " GB of memory at its peak (" + detail::format_count(e.vertices) + " vertices: the plan, " +
                         detail::format_count(frames) + (frames == 1 ? " frame" : " frames") +
                         " at a time and the files), over the limit of " + fmt(max_bytes / 1e9) + " GB; " + memory_advice(scene));
}

std::size_t files_form_chunk(const RunEstimate& e, double max_bytes) {
    if (e.frames == 0) return 1;
    const double per_frame = e.frame_array_bytes / static_cast<double>(e.frames);
    const double by_memory = per_frame > 0.0 ? std::floor(std::min(max_bytes, 256e6) / per_frame) : static_cast<double>(e.frames);
    const std::size_t spread = std::max<std::size_t>(8, (e.frames + 63) / 64);
    const std::size_t chunk = by_memory < static_cast<double>(spread) ? static_cast<std::size_t>(std::max(1.0, by_memory)) : spread;
    return std::min(chunk, e.frames);
}

namespace {

// The range of a chunk's heights (min and max are exact in any order).
struct HeightRange {
    float low = std::numeric_limits<float>::infinity(), high = -std::numeric_limits<float>::infinity();
    HeightRange& add(float z) {
        low = std::min(low, z), high = std::max(high, z);
        return *this;
    }
    HeightRange& add(const HeightRange& o) {
        low = std::min(low, o.low), high = std::max(high, o.high);
        return *this;
    }
};

// What a run of frames reuses: the model's buffers, the wind sea's, the fold foam's past
// samples, and with /refine the coarse frame the stencils carry to the refined surface.
struct FrameRun {
    const Scene& scene;
    const ScenePlan& plan;
    const detail::SurfaceModel& model;
    const Refinement* refined;  // nullptr without /refine
    bool shaded, creased;
    std::unique_ptr<detail::ModelState> state{};
    detail::WindSeaState wind_sea{};
    // J₋ at the vertices for past lattice times of the fold-foam fade (FoldFoamOptions),
    // kept while they are inside the window: each is computed once for a run of frames,
    // and equals what a frame computed alone would compute.
    std::map<long long, FoldSample> fold_past{};
    std::vector<float> fold_scratch{};  // a new past lattice time's J₋ at the vertices (reused: no fresh pages a frame)
    Refinement frame_refinement{};  // crest sharpness: creases follow each frame's heights
    std::vector<float> coarse_p{}, coarse_nr{}, coarse_foam{}, fine_depth{};
    std::vector<float> lip_weight{};  // the model's drawn walls and lips (SurfaceModel::lips)
    std::optional<UntanglePlan> untangle{};  // when the coarse vertices move sideways
    UntangleWorkspace untangle_scratch{};
    std::vector<float> far_field_scratch{};  // the skirt's anchors' residuals, then its breakers
    VertexFaces adjacency{};
    FresnelOptions fresnel{};
    std::optional<CausticPlan> caustics{};    // /underwater/caustics: a map per frame
    std::optional<SunVolumePlan> sunbeams{};  // /underwater/sunbeams: a volume per frame (its levels' caustic plans)
    CausticMesh caustic_mesh{};             // the surface's edges, walked once a frame
    CausticWorkspace caustic_scratch{};
    // A map's PNG and a volume's VDB are encoded on a task of their own while the frames
    // go on (the encoding is serial and takes as long as the map): two maps and volumes,
    // each pair with its encoding task.
    std::array<std::vector<float>, 2> caustic_maps{};
    std::array<std::vector<float>, 2> sun_volumes{};
    std::array<std::unique_ptr<tbb::task_group>, 2> underwater_encoders{};
    // /whitewater: the surface the particles ride, a frame's particles, and the wind
    // sea's whitecaps as events (from the fold foam's window of past samples).
    std::optional<WhitewaterRide> ride{};
    WhitewaterPoints points{}, fold_points{};
    WhitewaterEvents fold_events{};
    std::vector<std::pair<long long, const FoldSample*>> fold_window{};
    double fold_step = 0.0;
    double vertex_spacing = 0.0;  // the surface's mean edge (m): what a whitecap event stands for
};

// Waits for the underwater files still being encoded: rethrowing their errors, or,
// `quietly` (a frame's own error is unwinding), dropping them.
void finish_underwater_files(FrameRun& r, bool quietly = false) {
    for (auto& task : r.underwater_encoders) {
        if (!task) continue;
        try {
            task->wait();
        } catch (...) {
            if (!quietly) throw;
        }
    }
}

// The rectangle the untangling borders on: the far field's outer one round a skirt, else
// the seafloor's (the water mesh's domain). A whole side of the water's own rectangle
// that is a straight shore lies inside it, and is held as shore. None (NaN) when it
// does not hold the rest positions (a camera grid reaching the horizon).
std::array<double, 4> border_rectangle(const ScenePlan& p) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    const ElevationGrid& g = p.seafloor.grid;
    std::array<double, 4> r{nan, nan, nan, nan};
    if (p.skirt.vertex_count() > 0)
        r = {p.skirt.x0 - p.skirt.reach, p.skirt.y0 - p.skirt.reach, p.skirt.x1 + p.skirt.reach, p.skirt.y1 + p.skirt.reach};
    else if (g.nx >= 2 && g.ny >= 2)
        r = {g.x0, g.y0, g.x_max(), g.y_max()};
    const auto [x0, x1] = std::minmax_element(p.rest_x.begin(), p.rest_x.end());
    const auto [y0, y1] = std::minmax_element(p.rest_y.begin(), p.rest_y.end());
    const bool holds = !p.rest_x.empty() && r[0] <= *x0 && r[1] <= *y0 && r[2] >= *x1 && r[3] >= *y1;
    return holds ? r : std::array<double, 4>{nan, nan, nan, nan};
}

void start_run(FrameRun& r, const std::vector<std::uint32_t>& triangles, std::size_t n) {
    const ScenePlan& plan = r.plan;
    const std::size_t nc = plan.rest_x.size();
    r.state = r.model.start(r.scene, plan, r.shaded);
    if (plan.ocean.n > 0) {
        r.wind_sea.workspace.emplace(plan.ocean.n);
        detail::size_for_overwrite(r.wind_sea.lattice_j, plan.ocean.n * plan.ocean.n);
        detail::size_for_overwrite(r.wind_sea.vertex_j, nc);
    }
    if (r.refined) {
        r.coarse_p.resize(3 * nc);
        r.coarse_nr.resize(3 * nc);
        r.coarse_foam.resize(nc);
        r.fine_depth.resize(n);
        apply_refinement(*r.refined, std::span<const float>(plan.rest_depth), 1, r.fine_depth);
    }
    // Sideways motion by the model, a superposed wind sea or Gerstner waves: untangled
    // every frame against the coarse surface at rest (breaking crests' lips excepted).
    // The surface's boundary off the domain's sides is the shore and holds still, but
    // for the traced strips themselves, whose boundary is where their rays end.
    // The open ocean's skirt (its wind sea, wind_sea_scale) does not untangle the patch:
    // the patch's folds are its whitecaps (fold foam), and its vertices stay the FFT's.
    const bool patch = r.scene.surface_kind == SurfaceKind::ocean;
    if (r.model.untangle || (!patch && !plan.wind_sea_scale.empty()) || !plan.gerstner.empty()) {
        const bool traced_strips = r.scene.surface_kind == SurfaceKind::ray_strips && !r.scene.water_mesh_per_wavelength &&
                                   !r.scene.camera_grid;
        const bool lips = r.model.overturns && r.model.overturns(r.scene);
        UntangleOptions options{.lips_overturn = lips, .hold_shore = !traced_strips};
        // The traced strips hold slivers at rest, where the rays crowd: bounding their
        // angles only damped them unevenly (the bay's strips 5 → 48 ms a frame, vertices
        // 1.8 → 2.6 m/s).
        if (traced_strips) options.min_angle_degrees = 0.0;
        else options.border_rectangle = border_rectangle(plan);
        r.untangle = plan_untangle(plan.rest_x, plan.rest_y, surface_triangles(r.scene, plan), options);
        if (!r.shaded || r.refined) r.coarse_foam.resize(nc);
    }
    if (r.shaded || r.untangle) r.fold_past.insert(plan.fold_past.begin(), plan.fold_past.end());  // frame 0's foam past
    if (r.scene.whitewater) {
        // The model's own triangles (its vertices come first): a far field's skirt spans
        // kilometres, and a bucket grid over it crowded thousands of the domain's small
        // triangles into each bucket (19 s a frame). Whitewater beyond the domain is dropped.
        const std::vector<std::uint32_t>& coarse = r.model.triangles(plan);
        r.ride = plan_whitewater_ride(plan.rest_x, plan.rest_y, coarse);
        double sum = 0.0;  // the mean edge of the first triangles
        const std::size_t edges = std::min<std::size_t>(coarse.size(), 30000);
        for (std::size_t e = 0; e < edges; ++e) {
            const std::uint32_t a = coarse[e], b = coarse[e % 3 == 2 ? e - 2 : e + 1];
            sum += std::hypot(plan.rest_x[a] - plan.rest_x[b], plan.rest_y[a] - plan.rest_y[b]);
        }
        r.vertex_spacing = edges > 0 ? sum / static_cast<double>(edges) : 1.0;
    }
    r.fresnel.camera = scene_camera(r.scene, plan.seafloor);
    r.fresnel.model = r.scene.fresnel;
    const std::optional<UnderwaterOptions>& u = r.scene.underwater;
    if (u && (u->caustics || u->sunbeams)) {
        CausticPlan caustics = plan_caustics(plan.seafloor.grid, scene_caustic_options(r.scene, plan));
        if (u->sunbeams) r.sunbeams = plan_sun_volume(caustics, *u->sunbeams);
        if (u->caustics) r.caustics = std::move(caustics);  // not a second copy of the seafloor grid
        const std::size_t map_pixels = r.caustics ? r.caustics->options.width * r.caustics->options.height : 0;
        r.caustic_mesh = plan_caustic_mesh(triangles, n);
        for (std::size_t b = 0; b < 2; ++b) {
            r.caustic_maps[b].resize(map_pixels);
            if (r.sunbeams) r.sun_volumes[b].resize(r.sunbeams->nx * r.sunbeams->ny * r.sunbeams->nz);
            r.underwater_encoders[b] = std::make_unique<tbb::task_group>();
        }
    }
}

// The vertices the surface model moves itself: all but a far field's skirt.
std::size_t model_vertex_count(const ScenePlan& plan) {
    return plan.model_vertices > 0 ? plan.model_vertices : plan.rest_x.size();
}

// What move_coarse says of the frame's coarse vertices.
struct CoarseFrame {
    bool normals_done = false;  // their normals are final
    bool weights_done = false;  // and so are their Fresnel weights
};

// Whether the model's own output is the frame's final surface, as far as the run's
// settings tell before the model moves it (move_coarse checks the rest).
bool model_output_final(const FrameRun& r) {
    return r.shaded && !r.refined && !r.untangle && r.plan.gerstner.empty() && r.plan.wind_sea_scale.empty() &&
           model_vertex_count(r.plan) == r.plan.rest_x.size();
}

// The surface's coarse vertices at time t (and their normals when they are exact; and
// their Fresnel weights into refl, refr when the model computes them as it goes and
// nothing moves the vertices after it).
CoarseFrame move_coarse(FrameRun& r, double t, std::span<float> pc, std::span<float> nrc, std::span<float> refl,
                        std::span<float> refr) {
    const ScenePlan& plan = r.plan;
    // With a far field the model moves its own vertices, the skirt follows them.
    const std::size_t own = model_vertex_count(plan);
    detail::ModelFrame frame{.positions = pc.first(3 * own), .normals = nrc.first(3 * own), .wind_sea = r.wind_sea};
    if (model_output_final(r)) frame.fresnel = &r.fresnel, frame.reflect = refl, frame.refract = refr;
    const bool exact_normals = r.model.move(r.scene, plan, t, r.state.get(), frame) && own == plan.rest_x.size();
    if (!plan.gerstner.empty()) {
        const std::span<const double> x(plan.rest_x.data(), own), y(plan.rest_y.data(), own);
        add_gerstner_waves(plan.gerstner, x, y, std::span<const float>(plan.rest_depth.data(), own), t, pc.first(3 * own));
    }
    if (plan.far_field.vertex_count() > 0) evaluate_far_field(plan.far_field, t, pc, r.far_field_scratch);
    else if (plan.skirt.vertex_count() > 0)  // the open ocean's skirt: at rest, then the patch's wind sea below
        for (std::size_t v = own; v < plan.rest_x.size(); ++v) {
            pc[3 * v] = static_cast<float>(plan.rest_x[v]);
            pc[3 * v + 1] = static_cast<float>(plan.rest_y[v]);
            pc[3 * v + 2] = 0.0f;
        }
    if (plan.skirt_breakers.vertex_count() > 0) evaluate_skirt_breakers(plan.skirt_breakers, t, pc, r.far_field_scratch);
    if (!plan.wind_sea_scale.empty()) {  // a wind sea superposed on the model's surface
        const OceanFields fields = evaluate_ocean(plan.ocean, t, *r.wind_sea.workspace);
        add_ocean_samples(plan.ocean, fields, plan.rest_x, plan.rest_y, plan.wind_sea_scale, pc);
        if (r.shaded) {
            ocean_jacobian_field(plan.ocean, fields, r.wind_sea.lattice_j);
            fold_at_vertices(plan, r.scene.surface_kind == SurfaceKind::ocean, r.wind_sea.lattice_j, r.wind_sea.vertex_j);
        }
    }
    const bool normals_done = exact_normals && plan.gerstner.empty() && !r.refined;
    return {normals_done, normals_done && frame.weights_done};
}

// Foam at the coarse vertices: the model's, then the wind sea's folds fading out.
void coarse_foam(FrameRun& r, double t, std::span<float> fc) {
    const ScenePlan& plan = r.plan;
    if (r.model.foam) r.model.foam(r.scene, plan, t, r.state.get(), fc.first(model_vertex_count(plan)));
    // The skirt's foam: Jeschke's breakers carried on beyond the border where they run,
    // otherwise the border's own foam with its residual motion.
    if (plan.skirt_breakers.vertex_count() > 0) skirt_breaker_foam(plan.skirt_breakers, t, fc, r.far_field_scratch);
    else if (plan.far_field.vertex_count() > 0) far_field_foam(plan.far_field, fc);
    if (plan.ocean.n == 0) return;
    const FoldFoamOptions& fold = plan.fold_foam;
    accumulate_fold_foam(r.wind_sea.vertex_j, 0.0, fold, fc);
    r.fold_window.clear();
    double step = 0.0;
    const auto lattice = fold_lattice(t, fold, plan.loop_period, step);
    std::vector<AgedFoldSample> window;
    for (long long j : lattice) {
        auto it = r.fold_past.find(j);
        if (it == r.fold_past.end()) {
            evaluate_ocean_jacobian(plan.ocean, static_cast<double>(j) * step, *r.wind_sea.workspace, r.wind_sea.lattice_j);
            detail::size_for_overwrite(r.fold_scratch, plan.rest_x.size());
            fold_at_vertices(plan, r.scene.surface_kind == SurfaceKind::ocean, r.wind_sea.lattice_j, r.fold_scratch);
            it = r.fold_past.emplace(j, fold_sample(r.fold_scratch, fold)).first;
        }
        window.push_back({&it->second, t - static_cast<double>(j) * step});
        if (r.ride) r.fold_window.emplace_back(j, &it->second);
    }
    r.fold_step = step;
    accumulate_fold_foam(window, fold, fc);
    if (!lattice.empty()) r.fold_past.erase(r.fold_past.begin(), r.fold_past.lower_bound(lattice.back()));
}

// The wind sea's whitecaps as whitewater events: every sample of the fold foam's window
// (its lattice times), the crests running downwind at half the wind's speed (short
// breaking waves, not the peak's), of a tenth of the significant height (4 σ) up to
// half a metre. A whitecap is sampled every lattice step while it lasts: each sample
// stands for that share of a second of breaking, on 0.3 m of crest per metre of the
// surface's spacing (whitecaps are short crests, not lines).
void fold_events(FrameRun& r) {
    const ScenePlan& plan = r.plan;
    r.fold_events = WhitewaterEvents{};
    if (r.fold_window.empty() || !r.scene.ocean) return;
    const OceanOptions& o = *r.scene.ocean;
    const double sigma = std::sqrt(std::max(0.0, plan.ocean.expected_variance));
    const double height = std::clamp(0.4 * sigma, 0.1, 0.5);
    const std::array<double, 2> wind = o.spectrum.wind_direction;
    for (const auto& [j, sample] : r.fold_window)
        fold_whitewater_events(*sample, static_cast<double>(j) * r.fold_step, plan.fold_foam, plan.rest_x, plan.rest_y, wind,
                               0.5 * o.spectrum.wind_speed, height, 0.3 * r.vertex_spacing * r.fold_step, j, r.fold_events);
}

// The frame's whitewater (Scene::whitewater): the breakers' particles and the wind
// sea's, put on the moved coarse surface `pc`; their foam splatted into the coarse
// foam `fc` when shaded (the smooth band takes their patches); the frame's POINTS file.
void whitewater_frame(FrameRun& r, double t, std::span<const float> pc, std::span<float> fc, SceneAnimation& a, std::size_t f) {
    const WhitewaterOptions& o = *r.scene.whitewater;
    evaluate_whitewater(r.plan.whitewater, o, t, r.points);
    ride_whitewater(*r.ride, pc, r.points);
    fold_events(r);
    if (r.fold_events.size() > 0) {
        evaluate_whitewater(r.fold_events, o, t, r.fold_points);
        ride_whitewater(*r.ride, pc, r.fold_points, true);
        const auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
        append(r.points.positions, r.fold_points.positions);
        append(r.points.velocities, r.fold_points.velocities);
        append(r.points.age, r.fold_points.age);
        append(r.points.size, r.fold_points.size);
        append(r.points.kind, r.fold_points.kind);
    }
    if (r.shaded) splat_whitewater_foam(*r.ride, r.points, 40.0, 0.85, fc);
    a.whitewater[f] = whitewater_glb(r.points, a.first_frame + f, r.scene.fps);
}

// Frame f of the animation `a`: positions, normals and, shaded, the Fresnel weights,
// foam and colour.
void evaluate_frame(FrameRun& r, const std::vector<std::uint32_t>& coarse_triangles, std::size_t f, SceneAnimation& a,
                    HeightRange& heights) {
    const std::size_t n = a.vertex_count;
    const std::span<float> p(&a.positions[3 * n * f], 3 * n), nr(&a.normals[3 * n * f], 3 * n);
    const std::span<float> pc = r.refined ? std::span<float>(r.coarse_p) : p, nrc = r.refined ? std::span<float>(r.coarse_nr) : nr;
    const double t = static_cast<double>(a.first_frame + f) / r.scene.fps;
    const std::span<float> refl = r.shaded ? std::span<float>(&a.reflect[n * f], n) : std::span<float>();
    const std::span<float> refr = r.shaded ? std::span<float>(&a.refract[n * f], n) : std::span<float>();
    const CoarseFrame coarse = move_coarse(r, t, pc, nrc, refl, refr);
    bool normals_done = coarse.normals_done;
    // Foam before untangling, which leaves the breaking crests' lips to overturn; foam
    // does not depend on the positions.
    const std::span<float> foam = r.shaded ? std::span<float>(&a.foam[n * f], n) : std::span<float>();
    const std::span<float> fc = (r.refined || !r.shaded) ? std::span<float>(r.coarse_foam) : foam;
    if (r.shaded || r.untangle) {
        std::fill(fc.begin(), fc.end(), 0.0f);
        coarse_foam(r, t, fc);
    }
    if (r.untangle) {
        // The model's drawn walls and lips, where it says where they are; else the foam.
        std::span<const float> lips = fc;
        OverturnTest drawn;
        if (r.model.lips) {
            r.lip_weight.assign(fc.size(), 0.0f);
            if (r.model.lips(r.scene, r.plan, t, std::span<float>(r.lip_weight).first(model_vertex_count(r.plan)))) {
                lips = r.lip_weight;
                if (r.model.draws_overturned)
                    drawn = [&r, t](std::uint32_t i, std::uint32_t j, std::uint32_t k) { return r.model.draws_overturned(r.plan, t, i, j, k); };
            }
        }
        untangle_motion(*r.untangle, lips, pc, &r.untangle_scratch, drawn);
        normals_done = false;
    }
    if (r.ride) whitewater_frame(r, t, pc, fc, a, f);
    const Refinement* fr = r.refined;
    if (r.creased) {
        const RefineOptions& o = *r.scene.refine;
        const Creases c = crest_creases(pc, coarse_triangles, o.crest_sharpness_per_metre, o.max_crest_sharpness);
        r.frame_refinement = plan_refinement(r.plan.rest_x.size(), coarse_triangles, o, r.scene.max_refined_vertices, nullptr, &c);
        fr = &r.frame_refinement;
    }
    if (r.refined) apply_refinement(*fr, pc, 3, p);
    if (!normals_done) {
        // Made when a frame first needs it: the FFT patch's normals are exact, and a
        // million vertices' adjacency took as long as three of its frames.
        if (r.adjacency.offsets.empty()) r.adjacency = vertex_faces(n, a.triangles);
        vertex_normals(p, a.triangles, r.adjacency, nr);
    }
    // The heights' range, in parallel (min and max are exact in any order).
    heights = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, 1 << 14), heights,
        [&](const tbb::blocked_range<std::size_t>& b, HeightRange m) {
            for (std::size_t v = b.begin(); v < b.end(); ++v) m.add(p[3 * v + 2]);
            return m;
        },
        [](HeightRange x, const HeightRange& y) { return x.add(y); });
    if (r.caustics || r.sunbeams) {
        const std::size_t b = f % 2;
        r.underwater_encoders[b]->wait();  // the map and volume two frames back are encoded: their buffers are free
        if (r.caustics) evaluate_caustics(*r.caustics, r.caustic_mesh, p, nr, r.caustic_maps[b], &r.caustic_scratch);
        if (r.sunbeams) evaluate_sun_volume(*r.sunbeams, r.caustic_mesh, p, nr, r.sun_volumes[b], &r.caustic_scratch);
        r.underwater_encoders[b]->run([&r, &a, b, f] {
            if (r.caustics)
                a.caustics[f] = caustic_png(r.caustic_maps[b], r.caustics->options.width, r.caustics->options.height,
                                            r.scene.underwater->full_scale);
            if (r.sunbeams) a.sunbeams[f] = sun_volume_vdb(*r.sunbeams, r.sun_volumes[b]);
        });
    }
    if (!r.shaded) return;
    if (!(coarse.weights_done && normals_done)) fresnel_weights(p, nr, r.fresnel, refl, refr);
    if (r.refined) apply_refinement(*fr, std::span<const float>(fc), 1, foam);
    const std::span<const float> depth = r.refined ? std::span<const float>(r.fine_depth) : std::span<const float>(r.plan.rest_depth);
    if (r.scene.color) water_colour(refl, depth, foam, WaterColours{}, std::span<float>(&a.colors[3 * n * f], 3 * n));
}

// TEXCOORD_0: the rest position over the seafloor's rectangle (the patch for the
// ocean: it tiles), u along +x, v down (glTF's image origin is top-left).
void rest_texcoords(const ScenePlan& plan, const Refinement* refined, SceneAnimation& a) {
    const std::size_t n = a.vertex_count;
    std::vector<double> fine_x, fine_y;
    if (refined) {
        fine_x.resize(n);
        fine_y.resize(n);
        apply_refinement(*refined, std::span<const double>(plan.rest_x), 1, fine_x);
        apply_refinement(*refined, std::span<const double>(plan.rest_y), 1, fine_y);
    }
    detail::size_for_overwrite(a.texcoords, 2 * n);
    domain_texcoords(plan.seafloor.grid, refined ? fine_x : plan.rest_x, refined ? fine_y : plan.rest_y, a.texcoords);
}

// What colours the dressing's seafloor: its greatest depth, and the top of the beach.
struct FloorPalette {
    double depth_max = 1e-9;  // m
    double beach_top = 0.0;   // m above still water: sand below, grass above
};

// The beach's top: the highest wave's height (2 A) above still water, about where its
// swash reaches. The colours are per vertex and blend across a grid cell, so a grass line
// at the waterline itself drew the grid's diagonals into the water's edge: green teeth a
// cell apart in every close-up of the shore. Sand on both sides of the edge keeps it clean.
FloorPalette floor_palette(const Scene& scene, const Seafloor& seafloor) {
    FloorPalette p;
    p.depth_max = std::max(1e-9, seafloor_stats(seafloor).depth_max);
    for (const WaveTrain& t : scene.waves) p.beach_top = std::max(p.beach_top, 2.0 * t.amplitude);
    return p;
}

// A seafloor colour for an elevation z (m): pale sand up to the beach's top, darkening
// with depth below the waterline (the water itself adds the blue), turning to grass over
// as much height again above the beach (a gradient over several cells, not a grass line
// along the grid's diagonals) (linear RGB).
std::array<float, 3> seafloor_colour(double z, const FloorPalette& p) {
    const double wet = std::clamp(-z / p.depth_max, 0.0, 1.0);
    const double grass = p.beach_top > 0.0 ? std::clamp(z / p.beach_top - 1.0, 0.0, 1.0) : (z > 0.0 ? 1.0 : 0.0);
    const auto mix = [&](double sand, double deep, double green) {
        return static_cast<float>((1.0 - grass) * (sand + (deep - sand) * wet) + grass * green);
    };
    return {mix(0.6, 0.25, 0.16), mix(0.5, 0.2, 0.2), mix(0.32, 0.12, 0.08)};
}

// Under the far field's skirt: the terrain beyond the data (terrain_elevation) from the
// grid's border nodes out to the skirt's far rectangle, so that the water beyond the
// domain lies over a bottom and the land goes on to the horizon. The grid's nodes are
// the first cols × rows of `a`'s seafloor vertices. Rings of the grid's rectangle
// offset by d, a cell (`cell`) apart near the border and 1.25 × further out each, up
// to `reach`, their vertices about a quarter of d apart (a cell near the border), so
// that the triangles stay near equilateral and the hills the terrain draws stay
// resolved. Before, two rings extruded each border node's elevation and colour to the
// far rectangle: whatever the border held ran on unchanged to the horizon — behind the
// bay's head, the low sand-coloured land where the bay cuts deepest drew a pale wedge,
// a road from the beach to the horizon.
//
// Rings are zipped by a parameter tau that gives a point beyond a side the place of its
// foot on that side (side + kCorner + (1 − 2 kCorner) · the foot's fraction), and the
// corner's quadrant the kCorner either side of the corner: a line out from the border
// (a side's node, or the skirt's cut where the shoreline meets the border, a vertex on
// every ring) is then a chain of mesh edges, and no triangle of the far rings spans the
// land beside a cut and the sea beyond it (one 1.25 km across, 5 km out, dipped the
// bay's land below still water where no water lies).
void add_seafloor_apron(const ElevationGrid& g, double cell, double reach, std::size_t cols, std::size_t rows,
                        const FloorPalette& palette, SceneAnimation& a) {
    constexpr double kCorner = 0.02;
    const TerrainBeyond terrain = plan_terrain_beyond(g);
    const bool mapped = !a.seafloor_texcoords.empty();
    const double x0 = a.seafloor_positions[0], y0 = a.seafloor_positions[1];
    const double x1 = a.seafloor_positions[3 * (cols * rows - 1)], y1 = a.seafloor_positions[3 * (cols * rows - 1) + 1];
    const double length[4] = {x1 - x0, y1 - y0, x1 - x0, y1 - y0};
    struct Node {
        std::uint32_t index;
        double tau;
    };
    // Ring 0: the grid's border nodes counter-clockwise, each corner once (just before its
    // side's tau, so that the corner's quadrant fans from it).
    std::vector<Node> inner;
    const auto at = [cols](std::size_t c, std::size_t r) { return static_cast<std::uint32_t>(r * cols + c); };
    const double fc = static_cast<double>(cols - 1), fr = static_cast<double>(rows - 1);
    const auto main_tau = [](int side, double fraction) { return side + kCorner + (1.0 - 2.0 * kCorner) * fraction; };
    for (int side = 0; side < 4; ++side) {
        const std::size_t count = side % 2 == 0 ? cols - 1 : rows - 1;
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t v = side == 0 ? at(k, 0) : side == 1 ? at(cols - 1, k) : side == 2 ? at(cols - 1 - k, rows - 1) : at(0, rows - 1 - k);
            inner.push_back({v, k == 0 ? side - 0.5 * kCorner : main_tau(side, static_cast<double>(k) / (side % 2 == 0 ? fc : fr))});
        }
    }
    // Where the shoreline meets each side (the skirt's cuts): a fraction of the side.
    std::array<std::vector<double>, 4> cuts;
    const double side_start[4] = {0.0, length[0], length[0] + length[1], 2.0 * length[0] + length[1]};
    for (const double c : terrain.shore)
        for (int side = 0; side < 4; ++side)
            if (c > side_start[side] && c < side_start[side] + length[side]) cuts[static_cast<std::size_t>(side)].push_back((c - side_start[side]) / length[side]);
    // Inner ring → outer ring, both closed and ordered by tau: advance the one whose
    // next node comes first (triangles counter-clockwise, as the grid's).
    const auto zip = [&](std::vector<Node> in, std::vector<Node> out) {
        in.push_back({in.front().index, in.front().tau + 4.0});
        out.push_back({out.front().index, out.front().tau + 4.0});
        std::size_t i = 0, o = 0;
        while (i + 1 < in.size() || o + 1 < out.size()) {
            if (o + 1 < out.size() && (i + 1 == in.size() || out[o + 1].tau <= in[i + 1].tau)) {
                a.seafloor_triangles.insert(a.seafloor_triangles.end(), {in[i].index, out[o].index, out[o + 1].index});
                ++o;
            } else {
                a.seafloor_triangles.insert(a.seafloor_triangles.end(), {in[i].index, out[o].index, in[i + 1].index});
                ++i;
            }
        }
    };
    double d = 0.0;
    while (d < reach) {
        d = std::min(reach, std::max(1.25 * d, d + cell));
        const double spacing = std::max(cell, 0.25 * d);
        const double corner[5][2] = {{x0 - d, y0 - d}, {x1 + d, y0 - d}, {x1 + d, y1 + d}, {x0 - d, y1 + d}, {x0 - d, y0 - d}};
        std::vector<Node> outer;
        for (int side = 0; side < 4; ++side) {
            // Along the side from its corner: the corner piece [0, d), the foot's piece
            // [d, d + L) and the next corner's piece [d + L, L + 2d), at (a, tau).
            const double L = length[side];
            std::vector<std::pair<double, double>> points;
            const auto corner_pieces = static_cast<std::size_t>(std::ceil(d / spacing));
            const auto main_pieces = static_cast<std::size_t>(std::max(1.0, std::ceil(L / spacing)));
            for (std::size_t j = 0; j < corner_pieces; ++j) {
                const double f = static_cast<double>(j) / static_cast<double>(corner_pieces);
                points.push_back({d * f, side + kCorner * f});
                points.push_back({d + L + d * f, side + 1.0 - kCorner + kCorner * f});
            }
            for (std::size_t j = 0; j < main_pieces; ++j) {
                const double f = static_cast<double>(j) / static_cast<double>(main_pieces);
                points.push_back({d + L * f, main_tau(side, f)});
            }
            for (const double f : cuts[static_cast<std::size_t>(side)]) points.push_back({d + L * f, main_tau(side, f)});
            std::sort(points.begin(), points.end(), [](const auto& p, const auto& q) { return p.second < q.second; });
            points.erase(std::unique(points.begin(), points.end(), [](const auto& p, const auto& q) { return q.second - p.second < 1e-12; }),
                         points.end());
            const double ax = corner[side][0], ay = corner[side][1], bx = corner[side + 1][0], by = corner[side + 1][1];
            const double span = L + 2.0 * d;
            for (const auto& [along, tau] : points) {
                const double x = ax + (bx - ax) * along / span, y = ay + (by - ay) * along / span;
                const double z = terrain_elevation(terrain, x, y, spacing);
                a.seafloor_positions.insert(a.seafloor_positions.end(), {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
                const auto colour = seafloor_colour(z, palette);
                a.seafloor_colors.insert(a.seafloor_colors.end(), colour.begin(), colour.end());
                if (mapped)  // the caustic maps' edge texels stretch outwards
                    a.seafloor_texcoords.insert(a.seafloor_texcoords.end(),
                                                {static_cast<float>(std::clamp((x - g.x0) / (g.x_max() - g.x0), 0.0, 1.0)),
                                                 static_cast<float>(1.0 - std::clamp((y - g.y0) / (g.y_max() - g.y0), 0.0, 1.0))});
                outer.push_back({static_cast<std::uint32_t>(a.seafloor_positions.size() / 3 - 1), tau});
            }
        }
        zip(std::move(inner), outer);
        inner = std::move(outer);
    }
}

// The seafloor mesh (at most 256 nodes a side), camera, sun and material settings the
// single-file forms carry beside the water (/outputs/seafloor, camera, sun, material).
void dress_animation(const Scene& scene, const ScenePlan& plan, SceneAnimation& a) {
    SceneDressing d;
    d.water_material = scene.dress_material;
    const PreviewOptions view = scene_preview(scene, plan.seafloor);
    if (scene.dress_camera) {
        d.camera = true;
        d.camera_position = view.camera;
        d.camera_rotation = gltf_look_rotation(view.camera, view.look_at);
        d.camera_yfov = view.vertical_fov_degrees * std::numbers::pi / 180.0;
        d.camera_aspect = static_cast<double>(view.width) / static_cast<double>(view.height);
    }
    if (scene.dress_sun) {
        const double az = view.sun_azimuth_degrees * std::numbers::pi / 180.0, el = view.sun_elevation_degrees * std::numbers::pi / 180.0;
        d.sun = true;  // shining from the sun's direction towards the origin
        d.sun_rotation = gltf_look_rotation({std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)}, {0.0, 0.0, 0.0});
    }
    const ElevationGrid& g = plan.seafloor.grid;
    if (scene.dress_seafloor && surface_kind_traces(scene.surface_kind) != Traced::nothing && g.nx >= 2 && g.ny >= 2) {
        const std::size_t step = std::max<std::size_t>(1, (std::max(g.nx, g.ny) + 255) / 256);
        const std::size_t cols = (g.nx - 1) / step + 1, rows = (g.ny - 1) / step + 1;
        const FloorPalette palette = floor_palette(scene, plan.seafloor);
        for (std::size_t r = 0; r < rows; ++r)
            for (std::size_t c = 0; c < cols; ++c) {
                const std::size_t i = std::min(g.nx - 1, c * step), j = std::min(g.ny - 1, r * step);
                const double z = g.z[j * g.nx + i];
                a.seafloor_positions.insert(a.seafloor_positions.end(),
                                            {static_cast<float>(g.x0 + static_cast<double>(i) * g.dx),
                                             static_cast<float>(g.y0 + static_cast<double>(j) * g.dy), static_cast<float>(z)});
                const auto colour = seafloor_colour(z, palette);
                a.seafloor_colors.insert(a.seafloor_colors.end(), colour.begin(), colour.end());
            }
        a.seafloor_triangles = grid_triangles(cols, rows);
        if (!a.caustics.empty()) {  // the caustic maps' frame: the grid's rectangle, row 0 at its top
            const std::size_t count = a.seafloor_positions.size() / 3;
            a.seafloor_texcoords.resize(2 * count);
            for (std::size_t v = 0; v < count; ++v) {
                a.seafloor_texcoords[2 * v] = static_cast<float>((a.seafloor_positions[3 * v] - g.x0) / (g.x_max() - g.x0));
                a.seafloor_texcoords[2 * v + 1] = static_cast<float>(1.0 - (a.seafloor_positions[3 * v + 1] - g.y0) / (g.y_max() - g.y0));
            }
            d.caustic_images = kCausticImages;
            d.caustic_frames = a.loop_frames;
            d.caustic_fps = scene.fps;
            d.caustic_full_scale = scene.underwater->full_scale;
        }
        if (!a.sunbeams.empty()) {
            d.sunbeam_volumes = kSunbeamVolumes;
            d.sunbeam_frames = a.loop_frames;
            d.sunbeam_attenuation = scene.underwater->attenuation;
            const CausticOptions o = scene_caustic_options(scene, plan);
            d.sunbeam_direction = refracted_beam(o.sun, o.water_index);
            d.sunbeam_fps = scene.fps;
        }
        if (plan.skirt.vertex_count() > 0)
            add_seafloor_apron(g, static_cast<double>(step) * std::min(g.dx, g.dy), plan.skirt.reach, cols, rows, palette, a);
    }
    a.dressing = d;
}

// A run of frames of the scene, not started.
FrameRun scene_run(const Scene& scene, const ScenePlan& plan, const Refinement* refined) {
    return FrameRun{.scene = scene, .plan = plan, .model = detail::surface_model(scene.surface_kind), .refined = refined,
                    .shaded = scene.attributes != Scene::Attributes::none,
                    .creased = refined && scene.refine->crest_sharpness_per_metre > 0.0};
}

}  // namespace

struct AnimationStream::State {
    const Scene& scene;
    const ScenePlan& plan;
    const Refinement* refined;
    const std::vector<std::uint32_t>& coarse_triangles;
    const std::vector<std::uint32_t>& triangles;  // the exported surface's
    std::size_t loop_frames = 0, first = 0, count = 0, done = 0;
    FrameRun run;
    std::vector<std::unique_ptr<FrameRun>> lanes{};  // runs beside `run` when frames go side by side (frame_lanes)
    // The animation whose static parts this stream set last, and its triangles' storage:
    // a later chunk into it leaves them (24 MB of triangles a chunk at 1024²).
    const SceneAnimation* dressed = nullptr;
    const std::uint32_t* dressed_triangles = nullptr;
    const float* dressed_texcoords = nullptr;
    // Whether `a` still holds the static parts set in it (the same object, its triangles
    // and texture coordinates — two per vertex — neither replaced nor resized since).
    bool holds_static_parts(const SceneAnimation& a) const {
        return dressed == &a && a.triangles.data() == dressed_triangles && a.triangles.size() == triangles.size() &&
               a.texcoords.data() == dressed_texcoords && a.texcoords.size() == 2 * a.vertex_count;
    }

    // Frames 0 … k − 1 of the chunk `a` (sized for them), one after another on `run`, or
    // side by side on frame_lanes runs; returns their heights' range.
    HeightRange evaluate(SceneAnimation& a, std::size_t k, const std::function<void(std::size_t, std::size_t)>& progress) {
        const std::size_t lanes_now = frame_lanes(scene, a.vertex_count, k);
        return lanes_now == 1 ? in_order(a, k, progress) : side_by_side(a, k, lanes_now, progress);
    }

    HeightRange in_order(SceneAnimation& a, std::size_t k, const std::function<void(std::size_t, std::size_t)>& progress) {
        HeightRange heights;
        try {
            for (std::size_t f = 0; f < k; ++f) {
                evaluate_frame(run, coarse_triangles, f, a, heights);
                if (progress) progress(done + f + 1, count);
            }
            finish_underwater_files(run);
        } catch (...) {
            finish_underwater_files(run, true);  // no encoding task may outlive the frames it reads and writes
            throw;
        }
        return heights;
    }

    // Each lane takes the next frame not yet taken; a frame's passes run isolated in it,
    // so a lane waiting for them never picks up another lane's frames meanwhile.
    HeightRange side_by_side(SceneAnimation& a, std::size_t k, std::size_t lane_count,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
        while (lanes.size() + 1 < lane_count) {
            lanes.push_back(std::make_unique<FrameRun>(scene_run(scene, plan, refined)));
            start_run(*lanes.back(), triangles, a.vertex_count);
        }
        std::vector<HeightRange> lane_heights(lane_count);
        std::atomic<std::size_t> next_frame{0};
        std::size_t finished = 0;
        std::mutex progress_lock;
        const auto lane_frames = [&](std::size_t lane) {
            FrameRun& on = lane == 0 ? run : *lanes[lane - 1];
            for (std::size_t f = next_frame++; f < k; f = next_frame++) {
                tbb::this_task_arena::isolate([&] { evaluate_frame(on, coarse_triangles, f, a, lane_heights[lane]); });
                if (!progress) continue;
                const std::lock_guard lock(progress_lock);
                progress(done + ++finished, count);
            }
        };
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, lane_count, 1),
            [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t lane = r.begin(); lane != r.end(); ++lane) lane_frames(lane);
            },
            tbb::simple_partitioner());
        HeightRange heights;
        for (const HeightRange& h : lane_heights) heights.add(h);
        return heights;
    }
};

AnimationStream::AnimationStream(const Scene& scene, const ScenePlan& plan, FrameRange range) {
    // The surface's own vertices (coarse), and with /refine the subdivided ones.
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    const std::vector<std::uint32_t>& coarse = surface_triangles(scene, plan);
    const std::size_t loop_frames = scene_loop_frames(scene, plan), end = std::min(range.end, loop_frames);
    if (range.first >= end)
        throw InputError("scene: the frame range " + std::to_string(range.first) + ":" +
                         (range.end == static_cast<std::size_t>(-1) ? std::string() : std::to_string(range.end)) +
                         " holds no frame of the loop's 0:" + std::to_string(loop_frames));
    state_.reset(new State{.scene = scene, .plan = plan, .refined = refined, .coarse_triangles = coarse,
                           .triangles = refined ? refined->triangles : coarse, .loop_frames = loop_frames,
                           .first = range.first, .count = end - range.first, .run = scene_run(scene, plan, refined)});
    start_run(state_->run, state_->triangles, refined ? refined->fine_vertices : plan.rest_x.size());
}

AnimationStream::~AnimationStream() = default;

double AnimationStream::position_delta_range(std::size_t chunk) const {
    const State& s = *state_;
    Scene positions_only = s.scene;  // no shading, colour or caustics: the positions are the same
    positions_only.attributes = Scene::Attributes::none;
    positions_only.color = false;
    positions_only.underwater.reset();
    AnimationStream pass(positions_only, s.plan, FrameRange{s.first, s.first + s.count});
    SceneAnimation a;
    std::vector<float> base;
    double range = 0.0;
    while (pass.next(a, std::max<std::size_t>(1, chunk)) > 0) {
        if (base.empty()) base.assign(a.positions.begin(), a.positions.begin() + static_cast<std::ptrdiff_t>(3 * a.vertex_count));
        range = wave::position_delta_range(base, a.positions, range);
    }
    return range;
}
std::size_t AnimationStream::first_frame() const noexcept { return state_->first; }
std::size_t AnimationStream::frame_count() const noexcept { return state_->count; }
std::size_t AnimationStream::frames_left() const noexcept { return state_->count - state_->done; }

std::size_t AnimationStream::next(SceneAnimation& a, std::size_t count, const std::function<void(std::size_t, std::size_t)>& progress) {
    State& s = *state_;
    const std::size_t k = std::min(count, frames_left());
    if (k == 0) return 0;
    const Scene& scene = s.scene;
    a.fps = scene.fps;
    a.scene = scene.name;
    a.vertex_count = s.refined ? s.refined->fine_vertices : s.plan.rest_x.size();
    a.loop_frames = s.loop_frames;
    a.first_frame = s.first + s.done;
    a.frame_count = k;
    const bool dressed = s.holds_static_parts(a);
    if (!dressed) a.triangles = s.triangles;
    const std::size_t n = a.vertex_count;
    // Every value is written below (foam is cleared per frame): the first chunk's arrays
    // are fresh memory, advised for huge pages, later chunks reuse them.
    detail::size_for_overwrite(a.positions, 3 * n * k);
    detail::size_for_overwrite(a.normals, 3 * n * k);
    a.layout = scene.attributes == Scene::Attributes::named ? ScalarLayout::custom : ScalarLayout::blender34;
    a.draco = scene.draco;
    a.quantize = scene.quantize;
    a.meshopt = scene.meshopt;
    const bool shaded = scene.attributes != Scene::Attributes::none;
    detail::size_for_overwrite(a.reflect, shaded ? n * k : 0);
    detail::size_for_overwrite(a.refract, shaded ? n * k : 0);
    detail::size_for_overwrite(a.foam, shaded ? n * k : 0);
    detail::size_for_overwrite(a.colors, scene.color ? 3 * n * k : 0);
    a.caustics.assign(scene.underwater && scene.underwater->caustics ? k : 0, std::string());
    a.sunbeams.assign(scene.underwater && scene.underwater->sunbeams ? k : 0, std::string());
    a.whitewater.assign(scene.whitewater ? k : 0, std::string());
    const HeightRange heights = s.evaluate(a, k, progress);
    a.z_min = heights.low, a.z_max = heights.high;
    s.done += k;
    if (!dressed) {
        rest_texcoords(s.plan, s.refined, a);
        a.seafloor_positions.clear();
        a.seafloor_colors.clear();
        a.seafloor_triangles.clear();
        a.seafloor_texcoords.clear();
        dress_animation(scene, s.plan, a);
        s.dressed = &a;
        s.dressed_triangles = a.triangles.data();
        s.dressed_texcoords = a.texcoords.data();
    }
    return k;
}

SceneAnimation animate_scene(const Scene& scene, const ScenePlan& plan, double max_bytes, FrameRange range,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
    AnimationStream stream(scene, plan, range);
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    check_run_limits(scene, RunEstimate{.vertices = refined ? refined->fine_vertices : plan.rest_x.size(), .frames = scene_loop_frames(scene, plan)},
                     stream.frame_count(), max_bytes);
    SceneAnimation a;
    stream.next(a, stream.frame_count(), progress);
    return a;
}

}  // namespace wave
