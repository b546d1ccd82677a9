// Planning a scene: its seafloor, the model's surface, then the components every kind
// can carry (wind sea, Gerstner waves, far field, fold foam, whitewater events) and the
// refinement; the scene's camera, preview, trace and caustic options.
#include "libwave/scene.h"

#include "core/format.h"
#include "core/memory.h"
#include "libwave/errors.h"
#include "pipeline.h"
#include "surface_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

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

// The triangles of the surface's own vertices (before any refinement): the model's,
// and the skirt's when the far field continues it.
const std::vector<std::uint32_t>& surface_triangles(const Scene& scene, const ScenePlan& p) {
    return p.skirted_triangles.empty() ? surface_model(scene.surface_kind).triangles(p) : p.skirted_triangles;
}

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

}  // namespace detail

namespace {

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
    if (!detail::surface_model(scene.surface_kind).wind_sea_patch || p.ocean.n == 0 || p.camera_grid.vertex_count() > 0) return;
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
        detail::fold_at_vertices(p, detail::surface_model(scene.surface_kind).wind_sea_patch, past[lattice.size() - 1 - i], at_vertices);
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
    if (detail::surface_model(scene.surface_kind).wind_sea_patch)
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
    // The whitewater of the model's own breaking over the loop (the strips' motion's).
    if (const auto own = detail::surface_model(scene.surface_kind).whitewater; scene.whitewater && own) p.whitewater = own(scene, p);
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
        const std::vector<std::uint32_t>& coarse = detail::surface_triangles(scene, p);
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

}  // namespace wave
