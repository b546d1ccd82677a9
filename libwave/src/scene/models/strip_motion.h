// The motions of the ray strips, behind one interface: Gonzato's plunging profile and
// Jeschke's breakers. The ray-strips model (ray_strips.cpp) plans, moves, foams and
// skirts its strips through the scene's motion, never asking which one it is.
//
// Adding a motion on the strips: its file in scene/models/ (a StripMotion constant), its
// line in kStripMotions (ray_strips.cpp), and its scene key's reading (read_scene.cpp).
#pragma once

#include "../surface_model.h"

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace wave::detail {

struct StripMotion {
    std::string_view title;  ///< what the run summary calls it ("Jeschke's breakers")
    /// Whether the scene chooses it (kStripMotions holds them in order; the last,
    /// Gonzato's profile, is every scene's that chooses no other).
    bool (*chosen)(const Scene& s);

    /// Its plan on the traced strips (plan.strips), before the water mesh is made;
    /// nullptr: none.
    void (*plan_traced)(const Scene& s, ScenePlan& plan);
    /// The water mesh's edge sizes it needs, given the wavelength's (nullptr: those).
    EdgeSize (*mesh_size)(const Scene& s, const ScenePlan& plan, EdgeSize size);
    /// Its plan on the strips it moves (`moved`: plan.water_strips on a water mesh,
    /// else plan.strips); it may lengthen plan.loop_period and sample a camera grid.
    void (*plan)(const Scene& s, ScenePlan& plan, const RayStrips& moved);

    /// The strips at time t (positions of the surface's own vertices).
    void (*move)(const ScenePlan& plan, double t, std::span<float> positions);
    /// Its foam at time t (zeros on entry).
    void (*foam)(const Scene& s, const ScenePlan& plan, double t, std::span<float> out);
    /// SurfaceModel::overturns, lips and draws_overturned (nullptr: none drawn).
    bool (*overturns)(const Scene& s);
    bool (*lips)(const Scene& s, const ScenePlan& plan, double t, std::span<float> weight);
    bool (*draws_overturned)(const ScenePlan& plan, double t, std::uint32_t a, std::uint32_t b, std::uint32_t c);
    /// SurfaceModel::skirt_size and plan_skirt (nullptr: nothing beyond the fit).
    SkirtSize (*skirt_size)(const Scene& s, const ScenePlan& plan, SkirtSize size);
    void (*plan_skirt)(const Scene& s, ScenePlan& plan);
    /// The whitewater its breaking makes, and its name in the run's report.
    WhitewaterEvents (*whitewater)(const Scene& s, const ScenePlan& plan);
    std::string_view whitewater_source;
};

/// The motion the scene chooses for its strips.
const StripMotion& strip_motion(const Scene& s);

/// The strips the motion moves: the water mesh's resampled strips, else the traced ones.
const RayStrips& moved_strips(const ScenePlan& plan);

/// The triangles the strips' motion moves: the camera grid's, the water mesh's or the
/// traced strips' own (SurfaceModel::triangles of the ray strips).
const std::vector<std::uint32_t>& strip_triangles(const ScenePlan& plan);

}  // namespace wave::detail
