// Gonzato's ray strips: adaptive fronts traced over the seafloor, tessellated into strips
// and moved by the plunging profile, or by Jeschke's breakers (optionally resampled on
// Hinsinger's camera grid). One wave train.
#include "strip_motion.h"

#include "libwave/field.h"
#include "libwave/physics.h"

#include <algorithm>
#include <array>
#include <numbers>

namespace wave::detail {

extern const StripMotion kJeschkeStripMotion, kGonzatoStripMotion;

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
// depth's resolution up to the shore; graded further as the strips' motion needs
// (Jeschke's breakers: down to /surface/water_mesh/surf_zone × H where crests break).
WaterMesh plan_water_mesh(const Scene& scene, const ScenePlan& p, const StripMotion& motion) {
    EdgeSize size =
        wavelength_edge_size(p.seafloor, scene.waves[0], *scene.water_mesh_per_wavelength, scene.trace.breaker_index);
    if (motion.mesh_size) size = motion.mesh_size(scene, p, std::move(size));
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
    // The motion on the traced strips (which the water mesh may grade to), then on the
    // strips it moves.
    const StripMotion& motion = strip_motion(scene);
    if (motion.plan_traced) motion.plan_traced(scene, p);
    if (scene.water_mesh_per_wavelength) {
        p.water_mesh = plan_water_mesh(scene, p, motion);
        p.water_strips = resample_ray_strips(p.strips, p.seafloor, p.water_mesh.x, p.water_mesh.y, p.water_mesh.triangles);
        // Where the rays left gaps (the sides, shadows), the field's wave.
        if (!p.wave_fields.empty()) fill_strip_gaps(p.wave_fields[0], p.seafloor, p.water_strips);
    }
    const RayStrips& moved = moved_strips(p);
    motion.plan(scene, p, moved);
    const bool on_grid = p.camera_grid.vertex_count() > 0;
    p.rest_x = on_grid ? p.camera_grid.x : moved.x;
    p.rest_y = on_grid ? p.camera_grid.y : moved.y;
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
    strip_motion(scene).move(p, t, frame.positions);
    if (state) keep_waterline(static_cast<const State*>(state)->waterline, frame.positions);
    return false;
}

bool overturns(const Scene& scene) { return strip_motion(scene).overturns(scene); }

bool lips(const Scene& scene, const ScenePlan& p, double t, std::span<float> weight) {
    const StripMotion& motion = strip_motion(scene);
    return motion.lips && motion.lips(scene, p, t, weight);
}

SkirtSize skirt_size(const Scene& scene, const ScenePlan& p, SkirtSize size) {
    const StripMotion& motion = strip_motion(scene);
    return motion.skirt_size ? motion.skirt_size(scene, p, std::move(size)) : size;
}

void plan_skirt(const Scene& scene, ScenePlan& p) {
    if (const auto own = strip_motion(scene).plan_skirt) own(scene, p);
}

// The strips' motions, in the order they are chosen: the first whose scene key is set,
// else Gonzato's profile.
const std::array<const StripMotion*, 2> kStripMotions{&kJeschkeStripMotion, &kGonzatoStripMotion};

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
    .triangles = strip_triangles,
    .start = start,
    .move = move,
    .foam = [](const Scene& s, const ScenePlan& p, double t, ModelState*, std::span<float> out) { strip_motion(s).foam(s, p, t, out); },
    .lips = lips,
    .draws_overturned = [](const Scene& s, const ScenePlan& p, double t, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        const StripMotion& motion = strip_motion(s);
        return !motion.draws_overturned || motion.draws_overturned(p, t, a, b, c);
    },
    .skirt_size = skirt_size,
    .plan_skirt = plan_skirt,
    .foam_of_time_alone = true,  // jeschke_foam, breaking_foam and jeschke_drawn_lips: of t and the plan
    .wind_sea_patch = false,
    // The traced strips themselves (no water mesh, no camera grid) end where their rays do.
    .holds_boundary = [](const Scene& s) { return s.water_mesh_per_wavelength.has_value() || s.camera_grid.has_value(); },
    .whitewater = [](const Scene& s, const ScenePlan& p) { return strip_motion(s).whitewater(s, p); },
    .whitewater_source = [](const Scene& s) { return strip_motion(s).whitewater_source; },
    .long_shot_keys = kWindSeaLoopKeys,
};

const StripMotion& strip_motion(const Scene& s) {
    for (const StripMotion* m : kStripMotions)
        if (m->chosen(s)) return *m;
    throw InternalError("no strip motion chosen (the last is every scene's)");
}

const RayStrips& moved_strips(const ScenePlan& p) { return p.water_strips.vertex_count() > 0 ? p.water_strips : p.strips; }

const std::vector<std::uint32_t>& strip_triangles(const ScenePlan& p) {
    if (p.camera_grid.vertex_count() > 0) return p.camera_grid.triangles;
    return p.water_mesh.vertex_count() > 0 ? p.water_mesh.triangles : p.strips.triangles;
}

}  // namespace wave::detail

namespace wave {

std::string_view strip_motion_name(const Scene& scene) {
    return scene.surface_kind == SurfaceKind::ray_strips ? detail::strip_motion(scene).title : std::string_view{};
}

}  // namespace wave
