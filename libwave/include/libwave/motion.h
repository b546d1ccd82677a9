// libwave — motion: where the water surface is at time t.
//
// Gonzato & Le Saëc's vertical-section profile (§2.3–2.5, eq. 7): every surface point
// turns on a tilted ellipse (Fournier–Reeves / Biesel) whose major axis is limited to
// the disc of radius 1/k, plus three shaping terms — Stretch (the crest runs ahead),
// Orientation and Displacement (gravity pulls the lip forward and down) — so that
// waves plunge near the shore. The horizontal motion is along the local ray
// direction: lips overhang, the surface is a mesh, not a height field.
//
// Units: SI. Phase φ in rad; the profile's horizontal axis points along the ray, z up.
#pragma once

#include "libwave/surface.h"

#include <cstddef>
#include <span>
#include <vector>

namespace wave {

/// The user parameters of Gonzato's profile. K_0, K_x, K_z are the paper's fixed
/// constants (§2.3: "0.1, 0.11 and 0.09 seem to be the best values"); the others are
/// the "intuitive parameters" the paper leaves to the user.
struct GonzatoProfileOptions {
    double k0 = 0.1;   ///< tilt decay: sin α = sin β e^{−K_0 h} (1/m)
    double kx = 0.11;  ///< S_x = 1 / (1 − e^{−K_x h}) (1/m)
    double kz = 0.09;  ///< S_z = S_x (1 − e^{−K_z h}) (1/m)
    /// St_max, the largest crest stretch, as a multiple of the local wave height
    /// H = 2R (the paper gives it in metres; relative to H, flat water stays flat
    /// and one value suits a whole scene).
    double stretch_max = 1.0;
    double stretch_depth_factor = 0.4;       ///< K_s: stretch fades as e^{−K_s h} (1/m)
    double displacement_depth_factor = 0.4;  ///< K_d: displacement fades as e^{−K_d h} (1/m)
    bool limit_to_disc = true;  ///< major semi-axis R S_x <= 1/k (§2.3; off = Fournier–Reeves)
};

/// The per-point constants of eq. 7 (everything that does not depend on φ).
struct ProfileShape {
    double major = 0.0, minor = 0.0;          ///< semi-axes R S_x (limited to 1/k) and R S_z (m)
    double tilt_sin = 0.0, tilt_cos = 1.0;    ///< τ_β = sin α, τ'_β = cos α of the major axis
    double trough_phase = 0.0;                ///< Φ_min: the phase of the lowest point of the ellipse
    double stretch = 0.0;                     ///< St_max · H · e^{−K_s h} (m)
    double displacement = 0.0;                ///< A = H, times e^{−K_d h} (m)
    double bottom_angle = 0.0;                ///< β (rad), >= 0 (§2.4)
};

/// Shape of the profile at a point: R the local orbit radius (half the wave height,
/// the tracer's amplitude), k the wavenumber, h the depth, `rise` = tan of the bottom
/// slope rising along the ray (negative slopes are clamped to 0 as §2.4 does). Dry
/// points (h <= 0) or R <= 0 give a point that does not move.
ProfileShape gonzato_shape(double R, double k, double depth, double rise, const GonzatoProfileOptions& options);

/// Offset of a surface point from its rest position by eq. 7, at phase φ (any real;
/// wrapped into [Φ_min − π, Φ_min + π)): `forward` along the ray, `up` vertically.
struct ProfileOffset {
    double forward = 0.0, up = 0.0;
};
ProfileOffset gonzato_offset(const ProfileShape& shape, double phi) noexcept;

/// Gonzato's profile on a ray-strip surface, planned once per scene: a shape per
/// vertex (flat arrays) so that a frame costs only the φ-dependent terms.
struct GonzatoMotionPlan {
    std::vector<ProfileShape> shape;
    std::vector<double> x, y, dir_x, dir_y, phase;
    double omega = 0.0;

    std::size_t vertex_count() const noexcept { return x.size(); }
};
GonzatoMotionPlan plan_gonzato_motion(const RayStrips& strips, const GonzatoProfileOptions& options = {});

/// Vertex positions at time t (Φ = −ωt + Σ k Δs) into `positions` (3 floats per
/// vertex, z up). Parallel over vertices; each vertex is computed alone, so the result
/// does not depend on the thread count. Allocates nothing; throws InputError if
/// `positions` is not 3 · vertex_count() floats.
void evaluate_gonzato_motion(const GonzatoMotionPlan& plan, double t, std::span<float> positions);

}  // namespace wave
