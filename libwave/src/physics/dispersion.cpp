// Linear dispersion, group velocity, shoaling and refraction coefficients.
#include "libwave/physics.h"

#include "core/format.h"
#include "libwave/errors.h"

#include <cmath>
#include <numbers>

namespace wave {
namespace {

// k∞ h above which tanh(k h) == 1 in double precision (tanh(20) = 1 − 8e-18).
constexpr double kDeepWaterKh = 20.0;
constexpr int kMaxNewtonSteps = 60;

// f(k) = g k (1 + k²L²) tanh(k h) − ω² and its derivative (Tessendorf eq. 16 with
// the finite-depth factor of eq. 15).
struct Residual {
    double f;
    double df;
};

Residual dispersion_residual(double k, double omega, double h, double L) {
    const double t = std::tanh(k * h);
    const double c = 1.0 / std::cosh(k * h);
    const double kl2 = k * k * L * L;
    return {kGravity * k * (1.0 + kl2) * t - omega * omega,
            kGravity * ((1.0 + 3.0 * kl2) * t + k * (1.0 + kl2) * h * c * c)};
}

std::string describe(double v) { return detail::format_number(v); }

}  // namespace

double deep_water_wavenumber(double omega) noexcept { return omega * omega / kGravity; }

double deep_water_wavelength(double period) noexcept { return kGravity * period * period / (2.0 * std::numbers::pi); }

DispersionSolution solve_dispersion(double omega, double depth, const DispersionOptions& options) {
    if (!std::isfinite(omega) || omega <= 0.0)
        throw InputError("dispersion: angular frequency must be finite and > 0 rad/s, got " +
                         describe(omega));
    if (!std::isfinite(depth))
        throw InputError("dispersion: depth must be finite, got " + describe(depth));
    const double L = options.capillary_length;
    if (!std::isfinite(L) || L < 0.0)
        throw InputError("dispersion: capillary_length must be finite and >= 0 m, got " +
                         describe(L));

    DispersionSolution out;
    if (depth <= 0.0) {
        out.dry = true;
        return out;
    }
    const double k_deep = deep_water_wavenumber(omega);
    if (L == 0.0 && k_deep * depth > kDeepWaterKh) {
        out.k = k_deep;  // tanh(k h) == 1 exactly in double: k∞ is the root
        return out;
    }

    // Fenton & McKee (1990): k h ≈ k∞h / tanh((k∞h)^{3/4})^{2/3}, within 1.7 % of the
    // gravity root for every depth; a capillary term only lowers the root.
    const double kh0 = k_deep * depth;
    double k = k_deep / std::pow(std::tanh(std::pow(kh0, 0.75)), 2.0 / 3.0);

    // Bracket [lo, hi] with f(lo) < 0 < f(hi): f is increasing in k.
    double lo = 0.0;
    double hi = k;
    while (dispersion_residual(hi, omega, depth, L).f <= 0.0) {
        lo = hi;
        hi *= 2.0;
    }
    for (int step = 1; step <= kMaxNewtonSteps; ++step) {
        out.iterations = step;
        const Residual r = dispersion_residual(k, omega, depth, L);
        const double next = k - r.f / r.df;
        if (std::abs(next - k) <= options.relative_tolerance * k) {
            k = next;
            break;
        }
        if (r.f > 0.0) hi = k;
        else lo = k;
        // Newton inside the bracket; bisection when it would leave it.
        k = (next > lo && next < hi) ? next : 0.5 * (lo + hi);
    }
    out.k = k;
    return out;
}

double wavenumber_for_period(double period, double depth, const DispersionOptions& options) {
    if (!std::isfinite(period) || period <= 0.0)
        throw InputError("dispersion: period must be finite and > 0 s, got " + describe(period));
    return solve_dispersion(2.0 * std::numbers::pi / period, depth, options).k;
}

double group_velocity_ratio(double kh) noexcept {
    if (kh <= 0.0) return 1.0;
    if (kh < 1e-4) return 1.0 - kh * kh / 3.0;  // series of 2x/sinh 2x keeps full precision
    const double two_kh = 2.0 * kh;
    if (two_kh > 700.0) return 0.5;  // sinh overflows; the term is < 1e-300
    return 0.5 * (1.0 + two_kh / std::sinh(two_kh));
}

LinearWave linear_wave(double omega, double depth, const DispersionOptions& options) {
    const DispersionSolution s = solve_dispersion(omega, depth, options);
    LinearWave w;
    w.omega = omega;
    w.depth = depth;
    if (s.dry) {
        w.dry = true;
        return w;
    }
    w.k = s.k;
    w.wavelength = 2.0 * std::numbers::pi / s.k;
    w.celerity = omega / s.k;
    if (options.capillary_length == 0.0) {
        w.group_velocity = group_velocity_ratio(s.k * depth) * w.celerity;
    } else {
        // C_g = dω/dk = f'(k) / (2ω) for ω² = f(k).
        w.group_velocity =
            dispersion_residual(s.k, omega, depth, options.capillary_length).df / (2.0 * omega);
    }
    const double cg_deep = 0.5 * kGravity / omega;
    w.shoaling = std::sqrt(cg_deep / w.group_velocity);
    return w;
}

double shoaling_coefficient(double omega, double depth) {
    return linear_wave(omega, depth).shoaling;
}

double refraction_coefficient(double spacing_deep, double spacing_here) noexcept {
    return std::sqrt(spacing_deep / spacing_here);
}

}  // namespace wave
