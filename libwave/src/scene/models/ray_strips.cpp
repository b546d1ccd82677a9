// Gonzato's ray strips: adaptive fronts traced over the seafloor, tessellated into strips
// and moved by the plunging profile, or by Jeschke's breakers (optionally resampled on
// Hinsinger's camera grid). One wave train.
#include "../surface_model.h"

#include "libwave/field.h"
#include "libwave/physics.h"

#include <algorithm>
#include <numbers>

namespace wave::detail {
namespace {

void read_before(const Node& root, Scene&) {
    refuse_height_field_options(root, "ray-strips\"");
    if (root.has("trace") && root["trace"].has("orthogonals_per_grid_line"))
        root["trace"]["orthogonals_per_grid_line"].fail("only for the height-field surface");
}

void read_after(const Node& root, Scene& s) {
    if (!root.has("waves")) return;  // refused by the waves' own reading
    if (s.waves.size() != 1)
        root["waves"].fail("the ray-strips surface traces one wave train, got " + std::to_string(s.waves.size()) +
                           " (use \"surface\": {\"kind\": \"height-field\"} to superpose trains)");
}

// The ray strips came out empty: say why, naming the seafloor and the scene key, rather
// than let the exporter find "nothing to export".
[[noreturn]] void refuse_empty_strips(const Scene& scene, const ScenePlan& p) {
    const SeafloorStats st = seafloor_stats(p.seafloor);
    const std::string where = "scene: no water surface to animate over " + p.seafloor.source + ": ";
    if (!(st.depth_max > 0.0))
        throw InputError(where + "the seafloor is all land (no node below the water level" +
                         (st.nodata_count > 0 ? std::string("; NODATA read as land: /seafloor/nodata_policy") : std::string()) +
                         "); check /seafloor/sign and /seafloor/vertical_offset");
    const WaveTrain& w = scene.waves[0];
    // The seafloor's width across the swell, where its rays enter.
    const double len = std::hypot(w.direction_x, w.direction_y);
    const double across = (std::abs(w.direction_y) * (st.x_max - st.x_min) + std::abs(w.direction_x) * (st.y_max - st.y_min)) / len;
    if (across / scene.trace.ray_spacing < 2.0)
        throw InputError(where + "/trace/ray_spacing " + fmt(scene.trace.ray_spacing) + " m leaves fewer than two rays across the " +
                         fmt(across) + " m the swell enters over; a front needs two: lower /trace/ray_spacing");
    throw InputError(where + "no front formed: the swell travels towards [" + fmt(w.direction_x) + ", " +
                     fmt(w.direction_y) + "] (/waves/0/direction), so its rays start on the seafloor's upwave side, and " +
                     (p.fronts.initial_rays == 0 ? "none started in water there"
                                                 : std::to_string(p.fronts.initial_rays) + " ray(s) that started there made no strip") +
                     "; a direction points where the waves go, from the open sea towards the shore");
}

// The water mesh: /surface/water_mesh vertices per local wavelength of the train, the
// depth no shallower than where it breaks (H∞/γ): the surf zone keeps the breaking
// depth's resolution up to the shore.
// With the breakers, graded down to /surface/water_mesh/surf_zone × H over the band
// where crests break (the plan on the strips marks it).
WaterMesh plan_water_mesh(const Scene& scene, const ScenePlan& p, const JeschkeMotionPlan* strip_breakers) {
    EdgeSize size =
        wavelength_edge_size(p.seafloor, scene.waves[0], *scene.water_mesh_per_wavelength, scene.trace.breaker_index);
    if (strip_breakers && scene.surf_zone_mesh > 0.0) {
        SurfZoneMesh z;
        z.height_fraction = scene.surf_zone_mesh;
        size = surf_zone_edge_size(std::move(size), *strip_breakers, p.seafloor.grid, z);
    }
    WaterMeshOptions o;
    o.max_vertices = scene.surface.max_vertices;
    return mesh_water(p.seafloor, size, o);
}

void plan(const Scene& scene, ScenePlan& p, PlanStages stages) {
    if (scene.waves.size() != 1)
        throw InputError("scene: the ray-strips surface traces one wave train, got " + std::to_string(scene.waves.size()));
    FrontOptions fronts = scene.fronts;
    fronts.ray_spacing = scene.trace.ray_spacing;
    fronts.breaker_index = scene.trace.breaker_index;
    fronts.max_rays = scene.trace.max_rays;
    p.isobaths = extract_isobaths(p.seafloor, scene.isobaths);
    p.fronts = trace_fronts(p.seafloor, scene.waves[0], fronts, &p.isobaths);
    if (p.fronts.x.empty() || !(seafloor_stats(p.seafloor).depth_max > 0.0)) refuse_empty_strips(scene, p);
    if (scene.amplitudes_from_field) {  // rays keep direction and phase; the field gives the heights
        p.wave_fields = {solve_wave_field(p.seafloor, scene.waves[0], scene.field)};
        take_field_amplitudes(p.wave_fields[0], p.fronts);
    }
    p.strips = build_ray_strips(p.fronts);
    if (p.strips.triangle_count() == 0) refuse_empty_strips(scene, p);
    p.loop_period = scene.waves[0].period;
    if (stages == PlanStages::trace) return;
    // The breakers on the traced strips (resampled onto the mesh or the grid below).
    JeschkeMotionPlan strip_breakers;
    if (scene.breakers) {
        JeschkeBreakerOptions o = *scene.breakers;
        o.breaker_index = scene.trace.breaker_index;
        o.stable_index = scene.field.stable_index;  // where the field's heights re-form
        const WaveTrain& w = scene.waves[0];
        strip_breakers = plan_jeschke_breakers(p.strips, 2.0 * w.amplitude, deep_water_wavelength(w.period), o);
    }
    if (scene.water_mesh_per_wavelength) {
        p.water_mesh = plan_water_mesh(scene, p, scene.breakers ? &strip_breakers : nullptr);
        p.water_strips = resample_ray_strips(p.strips, p.seafloor, p.water_mesh.x, p.water_mesh.y, p.water_mesh.triangles);
        // Where the rays left gaps (the sides, shadows), the field's wave.
        if (!p.wave_fields.empty()) fill_strip_gaps(p.wave_fields[0], p.seafloor, p.water_strips);
    }
    const bool on_mesh = p.water_mesh.vertex_count() > 0;
    const RayStrips& moved = on_mesh ? p.water_strips : p.strips;
    // Gonzato's profile moves the strips unless the breakers do (/motion is refused with
    // them): not planned for nothing (a twentieth of the breaking beach's run).
    if (!scene.breakers) p.motion = plan_gonzato_motion(moved, scene.profile);
    if (scene.breakers) {
        p.breakers = std::move(strip_breakers);
        if (scene.camera_grid) {
            GridCamera c = *scene.camera_grid;
            c.position = scene_camera(scene, p.seafloor);
            p.camera_grid = camera_grid(c);
            // (No gap filling: the grid covers land too, which must stay at rest.)
            p.breakers = resample_jeschke_breakers(p.breakers, p.strips.triangles, p.camera_grid.x, p.camera_grid.y);
        }
        if (on_mesh) {
            p.breakers = resample_jeschke_breakers(p.breakers, p.strips.triangles, p.water_mesh.x, p.water_mesh.y);
            // Where the rays leave gaps (the downwave sides), the nearest traced breakers.
            fill_jeschke_gaps(p.breakers, p.water_mesh.triangles);
            // "lip": "curl": the overturning lip where the mesh resolves the tube.
            if (scene.surf_zone_mesh > 0.0)
                resolve_jeschke_lips(p.breakers, p.water_mesh.triangles, p.water_mesh.boundary, scene.surf_zone_mesh);
        }
        // Varied crests repeat after m of them: the loop holds m periods.
        p.loop_period *= static_cast<double>(p.breakers.loop_periods());
    }
    const bool on_grid = p.camera_grid.vertex_count() > 0;
    p.rest_x = on_grid ? p.camera_grid.x : moved.x;
    p.rest_y = on_grid ? p.camera_grid.y : moved.y;
}

const std::vector<std::uint32_t>& triangles(const ScenePlan& p) {
    if (p.camera_grid.vertex_count() > 0) return p.camera_grid.triangles;
    return p.water_mesh.vertex_count() > 0 ? p.water_mesh.triangles : p.strips.triangles;
}

// Crests turn over when the motion draws them as the papers do: Jeschke's tube, or
// Gonzato's eq. 7 with no packing bound. The bounded sections (the defaults) never do.
// Where the surf-zone mesh resolves the breakers' sections, their walls and curls too.
bool overturns(const Scene& scene) {
    return scene.breakers ? scene.breakers->lip != BreakerLip::outer || scene.surf_zone_mesh > 0.0
                          : scene.profile.min_packing == 0.0;
}

// The breakers' drawn walls and lips where the surf-zone mesh resolves them.
bool lips(const Scene& scene, const ScenePlan& p, double t, std::span<float> weight) {
    if (!scene.breakers || !(scene.surf_zone_mesh > 0.0) || p.water_mesh.vertex_count() == 0) return false;
    jeschke_drawn_lips(p.breakers, t, weight);
    return true;
}

// The waterline on the water mesh (surface.h, docs/inspect.md "The waterline").
struct State : ModelState {
    WaterlinePlan waterline;
};

std::unique_ptr<ModelState> start(const Scene& scene, const ScenePlan& p, bool) {
    auto s = std::make_unique<State>();
    if (p.water_mesh.vertex_count() > 0 && p.camera_grid.vertex_count() == 0)
        s->waterline = plan_waterline(p.water_mesh, p.seafloor, scene.waves[0].amplitude);
    return s;
}

bool move(const Scene& scene, const ScenePlan& p, double t, ModelState* state, ModelFrame& frame) {
    if (scene.breakers) evaluate_jeschke_breakers(p.breakers, t, frame.positions);
    else evaluate_gonzato_motion(p.motion, t, frame.positions);
    if (state) keep_waterline(static_cast<const State*>(state)->waterline, frame.positions);
    return false;
}

void foam(const Scene& scene, const ScenePlan& p, double t, ModelState*, std::span<float> out) {
    if (scene.breakers) jeschke_foam(p.breakers, t, out);
    else breaking_foam(p.water_strips.vertex_count() > 0 ? p.water_strips : p.strips, p.motion, t, scene.foam, out);
}

// The breakers carry on beyond the border where its water breaks, on a skirt as fine
// as the border there (docs/far-field.md "Breakers beyond the border").
double breaker_band(const Scene& scene) { return scene.breakers && scene.far_field ? scene.far_field->breaker_wavelengths : 0.0; }

SkirtSize skirt_size(const Scene& scene, const ScenePlan& p, SkirtSize size) {
    return breaker_skirt_size(std::move(size), p.breakers, p.seafloor.grid, breaker_band(scene));
}

void plan_skirt(const Scene& scene, ScenePlan& p) {
    if (breaker_band(scene) > 0.0) p.skirt_breakers = continue_jeschke_breakers(p.breakers, p.skirt, p.seafloor.grid, breaker_band(scene));
}

// Gonzato's profile: where its breaking foam comes from (the same strips and options).
// With Jeschke's breakers the breakers' own (plan.cpp); on a camera grid none.
WhitewaterEvents gonzato_whitewater(const Scene& scene, const ScenePlan& p) {
    if (scene.camera_grid) return {};
    const RayStrips& strips = p.water_strips.vertex_count() > 0 ? p.water_strips : p.strips;
    return gonzato_whitewater_events(strips, p.motion, scene.foam, triangles(p));
}

}  // namespace

extern const SurfaceModel kRayStripsModel{
    .kind = SurfaceKind::ray_strips,
    .name = "ray-strips",
    .traced = Traced::fronts,
    .loop_keys = "/waves/0/period",
    .size_keys = "raise /trace/ray_spacing or /fronts/step, or lower /animation/fps",
    .untangle = true,
    .overturns = overturns,
    .far_field_harmonics = 2,
    .read_before = read_before,
    .read_after = read_after,
    .seafloor = [](const Scene& s) { return load_seafloor(s.seafloor); },
    .plan = plan,
    .triangles = triangles,
    .start = start,
    .move = move,
    .foam = foam,
    .lips = lips,
    .draws_overturned = [](const ScenePlan& p, double t, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        return jeschke_draws_overturned(p.breakers, t, a, b, c);
    },
    .skirt_size = skirt_size,
    .plan_skirt = plan_skirt,
    .foam_of_time_alone = true,  // jeschke_foam, breaking_foam and jeschke_drawn_lips: of t and the plan
    .wind_sea_patch = false,
    // The traced strips themselves (no water mesh, no camera grid) end where their rays do.
    .holds_boundary = [](const Scene& s) { return s.water_mesh_per_wavelength.has_value() || s.camera_grid.has_value(); },
    .whitewater = gonzato_whitewater,
    .whitewater_source = "gonzato breaking",
    .long_shot_keys = kWindSeaLoopKeys,
};

}  // namespace wave::detail
