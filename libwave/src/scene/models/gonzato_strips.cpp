// Gonzato's plunging profile on the ray strips (/motion; every ray-strips scene without
// another motion): the traced strips, or the water mesh's resampled strips, moved by
// the profile, foaming where it breaks.
#include "strip_motion.h"

namespace wave::detail {
namespace {

// Gonzato's profile: where its breaking foam comes from (the same strips and options);
// on a camera grid none.
WhitewaterEvents whitewater(const Scene& scene, const ScenePlan& p) {
    if (scene.camera_grid) return {};
    return gonzato_whitewater_events(moved_strips(p), p.motion, scene.foam, strip_triangles(p));
}

}  // namespace

extern const StripMotion kGonzatoStripMotion{
    .title = "Gonzato's plunging profile",
    .chosen = [](const Scene&) { return true; },
    .plan_traced = nullptr,
    .mesh_size = nullptr,
    .plan = [](const Scene& s, ScenePlan& p, const RayStrips& moved) { p.motion = plan_gonzato_motion(moved, s.profile); },
    .move = [](const ScenePlan& p, double t, std::span<float> positions) { evaluate_gonzato_motion(p.motion, t, positions); },
    .foam = [](const Scene& s, const ScenePlan& p, double t, std::span<float> out) {
        breaking_foam(moved_strips(p), p.motion, t, s.foam, out);
    },
    // Gonzato's eq. 7 with no packing bound turns over; the bounded sections (the
    // defaults) never do.
    .overturns = [](const Scene& s) { return s.profile.min_packing == 0.0; },
    .lips = nullptr,
    .draws_overturned = nullptr,
    .skirt_size = nullptr,
    .plan_skirt = nullptr,
    .whitewater = whitewater,
    .whitewater_source = "gonzato breaking",
};

}  // namespace wave::detail
