// Forward dispersion, Tessendorf's frequency quantisation and the wind-wave spectra
// offered by the ocean tools of DCC packages (Phillips lives with the directional
// spectrum in motion/ocean_spectrum.cpp: it is defined in wavenumber space).
#include "libwave/physics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wave {

double dispersion_omega(double k, double depth, double capillary_length) noexcept {
    if (!(k > 0.0) || !(depth > 0.0)) return 0.0;
    const double kh = k * depth;
    const double t = kh > 20.0 ? 1.0 : std::tanh(kh);  // eq. 15 → eq. 14 when deep
    return std::sqrt(kGravity * k * (1.0 + k * k * capillary_length * capillary_length) * t);
}

double quantize_frequency(double omega, double repeat_time) noexcept {
    if (!(repeat_time > 0.0) || !(omega > 0.0)) return repeat_time > 0.0 ? 0.0 : omega;
    const double omega0 = 2.0 * std::numbers::pi / repeat_time;  // eq. 17
    // eq. 18 with [[·]] read as the nearest whole number, at least 1 (the printed
    // integer part freezes every wave slower than ω0 — the dominant waves of a gale
    // under a 20 s loop — and errs by up to ω0; this errs by ω0/2 at most and every
    // wave still repeats after T).
    return std::max(1.0, std::round(omega / omega0)) * omega0;
}

double pierson_moskowitz_spectrum(double omega, double wind_speed) noexcept {
    if (!(omega > 0.0) || !(wind_speed > 0.0)) return 0.0;
    constexpr double alpha = 8.1e-3, beta = 0.74;
    const double w0 = kGravity / (wind_speed * omega);
    if (beta * w0 * w0 * w0 * w0 > 700.0) return 0.0;  // far below the peak: e^{−700}; also avoids 0 · ∞
    return alpha * kGravity * kGravity / std::pow(omega, 5) * std::exp(-beta * w0 * w0 * w0 * w0);
}

double whitecap_coverage(double wind_speed) noexcept {
    if (!(wind_speed > 3.70)) return 0.0;
    // The two fits overlap on 9.25 … 11.25 m/s: blended linearly there, so W is continuous.
    const double low = 3.18e-3 * std::pow(wind_speed - 3.70, 3.0);
    const double high = 4.82e-4 * std::pow(wind_speed + 1.98, 3.0);
    const double s = std::clamp((wind_speed - 9.25) / 2.0, 0.0, 1.0);
    return std::min(1.0, ((1.0 - s) * low + s * high) / 100.0);
}

JonswapParameters jonswap_parameters(double wind_speed, double fetch, double peak_enhancement) noexcept {
    JonswapParameters p;
    p.alpha = 0.076 * std::pow(wind_speed * wind_speed / (fetch * kGravity), 0.22);
    p.peak_omega = 22.0 * std::cbrt(kGravity * kGravity / (wind_speed * fetch));
    p.gamma = peak_enhancement;
    return p;
}

double jonswap_spectrum(double omega, const JonswapParameters& p) noexcept {
    if (!(omega > 0.0) || !(p.peak_omega > 0.0)) return 0.0;
    const double ratio = p.peak_omega / omega;
    if (1.25 * ratio * ratio * ratio * ratio > 700.0) return 0.0;  // far below the peak (and no 0 · ∞)
    const double sigma = omega <= p.peak_omega ? 0.07 : 0.09;
    const double d = (omega - p.peak_omega) / (sigma * p.peak_omega);
    const double r = std::exp(-0.5 * d * d);
    return p.alpha * kGravity * kGravity / std::pow(omega, 5) * std::exp(-1.25 * ratio * ratio * ratio * ratio) *
           std::pow(p.gamma, r);
}

double kitaigorodskii_depth_factor(double omega, double depth) noexcept {
    if (!(depth > 0.0)) return 0.0;
    if (std::isinf(depth)) return 1.0;
    const double wh = omega * std::sqrt(depth / kGravity);
    if (wh <= 1.0) return 0.5 * wh * wh;
    if (wh <= 2.0) return 1.0 - 0.5 * (2.0 - wh) * (2.0 - wh);
    return 1.0;
}

}  // namespace wave
