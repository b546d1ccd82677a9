// Internal to the physics and shade stages: the Fresnel reflectivity inline, so that the
// per-vertex passes (fresnel_weights) see its constants (n_i = 1 folds away, η is
// hoisted). physics.h's fresnel_reflectivity is this function: the same bits.
#pragma once

#include <algorithm>
#include <cmath>

namespace wave::detail {

/// Unpolarised reflectivity for cos θ_i (clamped to [0, 1]) from index n_i into n_t:
/// ½ (r_s² + r_p²), 1 past the critical angle.
inline double fresnel_reflectivity(double cos_incidence, double n_i, double n_t) noexcept {
    // Tessendorf eq. 44 written with the s- and p-amplitude coefficients, which is
    // the same expression but finite at normal incidence (where eq. 44 is 0/0).
    const double cos_i = std::clamp(cos_incidence, 0.0, 1.0);
    const double sin_i2 = 1.0 - cos_i * cos_i;
    const double eta = n_i / n_t;
    const double sin_t2 = eta * eta * sin_i2;  // Snell, Tessendorf eq. 40
    if (sin_t2 >= 1.0) return 1.0;             // total internal reflection
    const double cos_t = std::sqrt(1.0 - sin_t2);
    const double rs = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    const double rp = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace wave::detail
