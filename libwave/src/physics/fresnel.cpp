// Fresnel reflectivity and the reflected / transmitted directions.
#include "libwave/physics.h"

#include "physics/fresnel_formula.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wave {
namespace {

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

double fresnel_reflectivity(double cos_incidence, double n_i, double n_t) noexcept {
    return detail::fresnel_reflectivity(cos_incidence, n_i, n_t);
}

double fresnel_transmissivity(double cos_incidence, double n_i, double n_t) noexcept {
    return 1.0 - fresnel_reflectivity(cos_incidence, n_i, n_t);
}

double fresnel_reflectivity_tso(double i) noexcept {
    // Ts'o–Barsky §4.2.3: flat at the normal-incidence value 0.02 up to 45°, then a
    // parabola with its vertex at (π/4, 0.02) through (π/2, 1).
    constexpr double kQuarterPi = std::numbers::pi / 4.0;
    if (i < kQuarterPi) return 0.02;
    const double d = i - kQuarterPi;
    return 392.0 / (25.0 * std::numbers::pi * std::numbers::pi) * d * d + 0.02;
}

Vec3 reflect(const Vec3& incident, const Vec3& normal) noexcept {
    const double d = 2.0 * dot(normal, incident);  // Tessendorf eq. 37
    return {incident[0] - d * normal[0], incident[1] - d * normal[1], incident[2] - d * normal[2]};
}

Refraction refract(const Vec3& incident, const Vec3& normal, double n_i, double n_t) noexcept {
    // Tessendorf eqs. 41–42: n_t = (n_i/n_t) n_i + Γ n̂. Orient the normal against the
    // incident ray so that cos θ_i = −n̂·n_i > 0; then Γ = η cos θ_i − sqrt(1 − η² sin² θ_i)
    // (the printed ± rule depends on the paper's orientation of n_i).
    Vec3 n = normal;
    double cos_i = -dot(n, incident);
    if (cos_i < 0.0) {
        n = {-n[0], -n[1], -n[2]};
        cos_i = -cos_i;
    }
    const double eta = n_i / n_t;
    const double k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    Refraction r;
    if (k < 0.0) {
        r.total_internal_reflection = true;
        return r;
    }
    const double gamma = eta * cos_i - std::sqrt(k);
    r.direction = {eta * incident[0] + gamma * n[0], eta * incident[1] + gamma * n[1],
                   eta * incident[2] + gamma * n[2]};
    return r;
}

}  // namespace wave
