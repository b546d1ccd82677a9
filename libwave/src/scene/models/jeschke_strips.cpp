// Jeschke's breakers on the ray strips (/breakers): planned on the traced strips, where
// the water mesh grades down to the surf zone; resampled onto the water mesh or
// Hinsinger's camera grid; their lips drawn where the surf-zone mesh resolves the tube.
#include "strip_motion.h"

#include "libwave/physics.h"

namespace wave::detail {
namespace {

void plan_traced(const Scene& scene, ScenePlan& p) {
    JeschkeBreakerOptions o = *scene.breakers;
    o.breaker_index = scene.trace.breaker_index;
    o.stable_index = scene.field.stable_index;  // where the field's heights re-form
    const WaveTrain& w = scene.waves[0];
    p.breakers = plan_jeschke_breakers(p.strips, 2.0 * w.amplitude, deep_water_wavelength(w.period), o);
}

// Graded down to /surface/water_mesh/surf_zone × H over the band where crests break.
EdgeSize mesh_size(const Scene& scene, const ScenePlan& p, EdgeSize size) {
    if (!(scene.surf_zone_mesh > 0.0)) return size;
    SurfZoneMesh z;
    z.height_fraction = scene.surf_zone_mesh;
    return surf_zone_edge_size(std::move(size), p.breakers, p.seafloor.grid, z);
}

void plan(const Scene& scene, ScenePlan& p, const RayStrips&) {
    if (scene.camera_grid) {
        GridCamera c = *scene.camera_grid;
        c.position = scene_camera(scene, p.seafloor);
        p.camera_grid = camera_grid(c);
        // (No gap filling: the grid covers land too, which must stay at rest.)
        p.breakers = resample_jeschke_breakers(p.breakers, p.strips.triangles, p.camera_grid.x, p.camera_grid.y);
    }
    if (p.water_mesh.vertex_count() > 0) {
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

// Jeschke's tube, or the walls and curls the surf-zone mesh resolves, turn over; the
// bounded outer envelope alone does not.
bool overturns(const Scene& scene) { return scene.breakers->lip != BreakerLip::outer || scene.surf_zone_mesh > 0.0; }

// The breakers' drawn walls and lips where the surf-zone mesh resolves them.
bool lips(const Scene& scene, const ScenePlan& p, double t, std::span<float> weight) {
    if (!(scene.surf_zone_mesh > 0.0) || p.water_mesh.vertex_count() == 0) return false;
    jeschke_drawn_lips(p.breakers, t, weight);
    return true;
}

// The breakers carry on beyond the border where its water breaks, on a skirt as fine
// as the border there (docs/far-field.md "Breakers beyond the border").
double breaker_band(const Scene& scene) { return scene.far_field ? scene.far_field->breaker_wavelengths : 0.0; }

}  // namespace

extern const StripMotion kJeschkeStripMotion{
    .title = "Jeschke's breakers",
    .chosen = [](const Scene& s) { return s.breakers.has_value(); },
    .plan_traced = plan_traced,
    .mesh_size = mesh_size,
    .plan = plan,
    .move = [](const ScenePlan& p, double t, std::span<float> positions) { evaluate_jeschke_breakers(p.breakers, t, positions); },
    .foam = [](const Scene&, const ScenePlan& p, double t, std::span<float> out) { jeschke_foam(p.breakers, t, out); },
    .overturns = overturns,
    .lips = lips,
    .draws_overturned = [](const ScenePlan& p, double t, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        return jeschke_draws_overturned(p.breakers, t, a, b, c);
    },
    .skirt_size = [](const Scene& s, const ScenePlan& p, SkirtSize size) {
        return breaker_skirt_size(std::move(size), p.breakers, p.seafloor.grid, breaker_band(s));
    },
    .plan_skirt = [](const Scene& s, ScenePlan& p) {
        if (breaker_band(s) > 0.0) p.skirt_breakers = continue_jeschke_breakers(p.breakers, p.skirt, p.seafloor.grid, breaker_band(s));
    },
    // The breakers' whitewater over the loop, on the surface the breakers move.
    .whitewater = [](const Scene&, const ScenePlan& p) { return jeschke_whitewater_events(p.breakers, strip_triangles(p)); },
    .whitewater_source = "breakers",
};

}  // namespace wave::detail
