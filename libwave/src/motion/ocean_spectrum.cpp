// Tessendorf §3.3–3.4: the directional wavenumber spectrum and the random Fourier
// amplitudes h̃0 of one ocean realisation (static, once per scene).
#include "core/format.h"
#include "core/splitmix.h"
#include "libwave/errors.h"
#include "libwave/motion.h"
#include "libwave/physics.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>

namespace wave {
namespace {

constexpr double kPi = std::numbers::pi;

std::string fmt(double v) { return detail::format_number(v); }

// dω/dk of ω² = g k (1 + k²L²) tanh(k h): the group velocity.
double dispersion_slope(double k, double depth, double capillary) noexcept {
    const double w = dispersion_omega(k, depth, capillary);
    if (!(w > 0.0)) return 0.0;
    const double L2 = capillary * capillary;
    const double kh = k * depth;
    const double t = kh > 20.0 ? 1.0 : std::tanh(kh);
    // The finite-depth term vanishes in deep water (and depth may be +inf there: no ∞ · 0).
    const double bottom = kh > 20.0 ? 0.0 : k * (1.0 + k * k * L2) * depth / (std::cosh(kh) * std::cosh(kh));
    return kGravity * ((1.0 + 3.0 * k * k * L2) * t + bottom) / (2.0 * w);
}

// ∫_0^{2π} |cos θ|^p dθ = 2 sqrt(π) Γ((p+1)/2) / Γ(p/2 + 1).
double cos_power_integral(double p) noexcept {
    return 2.0 * std::sqrt(kPi) * std::exp(std::lgamma(0.5 * (p + 1.0)) - std::lgamma(0.5 * p + 1.0));
}

// The directional factor D(θ) (unnormalised) for the unit wavevector direction.
double spreading(const OceanSpectrum& s, double ux, double uy) noexcept {
    const double len = std::hypot(s.wind_direction[0], s.wind_direction[1]);
    const double c = (ux * s.wind_direction[0] + uy * s.wind_direction[1]) / len;
    const double d = std::pow(std::abs(c), s.directional_exponent);
    return c < 0.0 ? s.against_wind * d : d;
}

// The radial part R(k): F(k, θ) = R(k) · D(θ).
double radial(const OceanSpectrum& s, double k) noexcept {
    if (!(k > 0.0)) return 0.0;
    const double cutoff = s.small_wave_cutoff > 0.0 ? std::exp(-k * k * s.small_wave_cutoff * s.small_wave_cutoff) : 1.0;  // eq. 24
    if (s.model == OceanSpectrumModel::phillips) {
        const double L = s.wind_speed * s.wind_speed / kGravity;
        const double kl = k * L;
        return s.phillips_constant * std::exp(-1.0 / (kl * kl)) / (k * k * k * k) * cutoff;  // eq. 23
    }
    const double w = dispersion_omega(k, s.depth, s.capillary_length);
    double S = 0.0;
    switch (s.model) {
        case OceanSpectrumModel::pierson_moskowitz: S = pierson_moskowitz_spectrum(w, s.wind_speed); break;
        case OceanSpectrumModel::jonswap:
            S = jonswap_spectrum(w, jonswap_parameters(s.wind_speed, s.fetch, s.peak_enhancement));
            break;
        case OceanSpectrumModel::tma:
            S = jonswap_spectrum(w, jonswap_parameters(s.wind_speed, s.fetch, s.peak_enhancement)) *
                kitaigorodskii_depth_factor(w, s.depth);
            break;
        case OceanSpectrumModel::phillips: break;
    }
    // S(ω) dω = F k dk dθ with ∫ D dθ normalised to 1.
    const double norm = 0.5 * (1.0 + s.against_wind) * cos_power_integral(s.directional_exponent);
    return S * dispersion_slope(k, s.depth, s.capillary_length) / k / norm * cutoff;
}

double angular_integral(const OceanSpectrum& s) noexcept {
    return 0.5 * (1.0 + s.against_wind) * cos_power_integral(s.directional_exponent);
}

// Counter-based random numbers (core/splitmix.h): h̃0 at wave index (n, m) depends on
// (seed, n, m) only, so it is the same whatever the traversal order, the thread count or
// the grid size.
using detail::splitmix64;

std::complex<double> gaussian_pair(std::uint64_t seed, long n, long m) noexcept {
    const std::uint64_t key = splitmix64(seed) ^ ((static_cast<std::uint64_t>(static_cast<std::uint32_t>(n)) << 32) |
                                                  static_cast<std::uint32_t>(m));
    const std::uint64_t a = splitmix64(key), b = splitmix64(a);
    const double u1 = (static_cast<double>(a >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
    const double u2 = static_cast<double>(b >> 11) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));  // Box–Muller
    return {r * std::cos(2.0 * kPi * u2), r * std::sin(2.0 * kPi * u2)};
}

}  // namespace

double ocean_spectrum_density(const OceanSpectrum& s, double kx, double ky) noexcept {
    const double k = std::hypot(kx, ky);
    if (!(k > 0.0)) return 0.0;
    return radial(s, k) * spreading(s, kx / k, ky / k);
}

double ocean_peak_omega(const OceanSpectrum& s) noexcept {
    switch (s.model) {
        case OceanSpectrumModel::phillips: {
            const double L = s.wind_speed * s.wind_speed / kGravity;
            return dispersion_omega(std::sqrt(2.0 / 3.0) / L, s.depth, s.capillary_length);
        }
        case OceanSpectrumModel::pierson_moskowitz: return std::pow(0.8 * 0.74, 0.25) * kGravity / s.wind_speed;
        case OceanSpectrumModel::jonswap:
        case OceanSpectrumModel::tma: return jonswap_parameters(s.wind_speed, s.fetch, s.peak_enhancement).peak_omega;
    }
    return 0.0;
}

double ocean_spectrum_variance(const OceanSpectrum& s) {
    validate_ocean_options(OceanOptions{.spectrum = s, .choppiness = 0.0}, "spectrum");
    // The peak wavenumber, then Simpson's rule in u = ln k over e^-8 … e^18 around it
    // (the integrand falls as k^-2 above the peak and faster than any power below).
    double kp = 0.0;
    if (s.model == OceanSpectrumModel::phillips) {
        const double L = s.wind_speed * s.wind_speed / kGravity;
        kp = std::sqrt(2.0 / 3.0) / L;
    } else {
        kp = deep_water_wavenumber(ocean_peak_omega(s));
    }
    const double u0 = std::log(kp) - 8.0, u1 = std::log(kp) + 18.0;
    const int intervals = 200000;
    const double du = (u1 - u0) / intervals;
    double sum = 0.0;
    for (int i = 0; i <= intervals; ++i) {
        const double k = std::exp(u0 + du * i);
        const double f = radial(s, k) * k * k;  // F k dk = F k² du
        sum += f * (i == 0 || i == intervals ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    return sum * du / 3.0 * angular_integral(s);
}

void validate_ocean_options(const OceanOptions& o, const std::string& where) {
    const auto fail = [&](const std::string& field, const std::string& what) {
        throw InputError(where + "/" + field + ": " + what);
    };
    const OceanSpectrum& s = o.spectrum;
    if (o.resolution < 16 || o.resolution > 4096 || (o.resolution & (o.resolution - 1)) != 0)
        fail("resolution", "expected a power of two from 16 to 4096, got " + std::to_string(o.resolution));
    if (!std::isfinite(o.size) || !(o.size > 0.0)) fail("size", "expected a patch size > 0 m, got " + fmt(o.size));
    if (!std::isfinite(s.wind_speed) || !(s.wind_speed > 0.0))
        fail("wind_speed", "expected a wind speed > 0 m/s, got " + fmt(s.wind_speed));
    if (!std::isfinite(s.wind_direction[0]) || !std::isfinite(s.wind_direction[1]) ||
        std::hypot(s.wind_direction[0], s.wind_direction[1]) == 0.0)
        fail("wind_direction", "expected a non-zero horizontal direction [x, y]");
    if (!std::isfinite(s.directional_exponent) || s.directional_exponent < 0.0)
        fail("directional_exponent", "expected a number >= 0, got " + fmt(s.directional_exponent));
    if (!std::isfinite(s.against_wind) || s.against_wind < 0.0 || s.against_wind > 1.0)
        fail("against_wind", "expected a factor in [0, 1], got " + fmt(s.against_wind));
    if (!std::isfinite(s.phillips_constant) || !(s.phillips_constant > 0.0))
        fail("phillips_constant", "expected a number > 0, got " + fmt(s.phillips_constant));
    if (!std::isfinite(s.small_wave_cutoff) || s.small_wave_cutoff < 0.0)
        fail("small_wave_cutoff", "expected a length >= 0 m, got " + fmt(s.small_wave_cutoff));
    if (s.small_wave_cutoff >= o.size)
        fail("small_wave_cutoff", "the cutoff " + fmt(s.small_wave_cutoff) + " m is not smaller than the patch (" +
                                      fmt(o.size) + " m): every wave of the patch would be suppressed (eq. 24)");
    if (!std::isfinite(s.fetch) || !(s.fetch > 0.0)) fail("fetch", "expected a fetch > 0 m, got " + fmt(s.fetch));
    if (!std::isfinite(s.peak_enhancement) || s.peak_enhancement < 1.0)
        fail("peak_enhancement", "expected γ >= 1, got " + fmt(s.peak_enhancement));
    if (!(s.depth > 0.0)) fail("depth", "expected a depth > 0 m (or none for deep water), got " + fmt(s.depth));
    if (s.model == OceanSpectrumModel::tma && std::isinf(s.depth))
        fail("depth", "the TMA spectrum needs a finite water depth");
    if (!std::isfinite(s.capillary_length) || s.capillary_length < 0.0)
        fail("capillary_length", "expected a length >= 0 m, got " + fmt(s.capillary_length));
    if (!std::isfinite(o.choppiness) || o.choppiness < 0.0)
        fail("choppiness", "expected λ >= 0, got " + fmt(o.choppiness));
    if (!std::isfinite(o.repeat_time) || o.repeat_time < 0.0)
        fail("repeat_time", "expected a time >= 0 s (0 = no loop), got " + fmt(o.repeat_time));
}

OceanPlan plan_ocean(const OceanOptions& o) {
    validate_ocean_options(o);
    OceanPlan p;
    p.n = o.resolution;
    p.size = o.size;
    p.choppiness = o.choppiness;
    p.repeat_time = o.repeat_time;
    p.peak_omega = ocean_peak_omega(o.spectrum);
    const std::size_t n = p.n, half = p.half();
    const long N = static_cast<long>(n);
    const double dk = 2.0 * kPi / o.size;
    p.kx.resize(half);
    p.ky.resize(n);
    for (std::size_t i = 0; i < half; ++i) p.kx[i] = static_cast<float>(dk * static_cast<double>(i));
    for (std::size_t j = 0; j < n; ++j) {
        const long m = static_cast<long>(j) < N / 2 ? static_cast<long>(j) : static_cast<long>(j) - N;
        p.ky[j] = static_cast<float>(dk * static_cast<double>(m));
    }
    // 1/|k| for the displacement's spectra, in float as the frames use it.
    p.inv_k.resize(n * half);
    for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < half; ++i) {
            const float k = std::sqrt(p.kx[i] * p.kx[i] + p.ky[j] * p.ky[j]);
            p.inv_k[j * half + i] = k > 0.0f ? 1.0f / k : 0.0f;
        }
    p.h0.assign(n * half, {0.0f, 0.0f});
    p.h0_minus.assign(n * half, {0.0f, 0.0f});
    p.omega.assign(n * half, 0.0);
    const bool quantised = o.repeat_time > 0.0;
    if (quantised) p.omega_steps.assign(n * half, 0);
    const double omega0 = quantised ? 2.0 * kPi / o.repeat_time : 0.0;
    std::vector<double> row_variance(n, 0.0);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) {
        const long m = static_cast<long>(j) < N / 2 ? static_cast<long>(j) : static_cast<long>(j) - N;
        double var = 0.0;
        for (std::size_t i = 0; i < half; ++i) {
            const long nn = static_cast<long>(i);
            if (nn == N / 2 || m == -N / 2 || (nn == 0 && m == 0)) continue;  // k = 0 and Nyquist stay 0
            const double kx = dk * static_cast<double>(nn), ky = dk * static_cast<double>(m);
            const double f_plus = ocean_spectrum_density(o.spectrum, kx, ky);
            const double f_minus = ocean_spectrum_density(o.spectrum, -kx, -ky);
            // eq. 25, h̃0 = (ξr + iξi) sqrt(P / 2), with P = <|h̃0|²> = F Δk² / 2, so that
            // Σ <|h̃(k,t)|²> = Σ (P(k) + P(−k)) over the lattice is Σ F Δk².
            const auto a = gaussian_pair(o.seed, nn, m) * std::sqrt(0.25 * f_plus * dk * dk);
            const auto b = gaussian_pair(o.seed, -nn, -m) * std::sqrt(0.25 * f_minus * dk * dk);
            const std::size_t e = j * half + i;
            p.h0[e] = std::complex<float>(a);
            p.h0_minus[e] = std::complex<float>(std::conj(b));
            const double w = dispersion_omega(std::hypot(kx, ky), o.spectrum.depth, o.spectrum.capillary_length);
            if (quantised) {
                const double steps = std::round(quantize_frequency(w, o.repeat_time) / omega0);  // eq. 18
                p.omega_steps[e] = static_cast<std::int32_t>(steps);
                p.omega[e] = steps * omega0;
            } else {
                p.omega[e] = w;
            }
            // Both k and −k of the full lattice; the kx = 0 column holds both itself.
            var += (nn == 0 ? 1.0 : 2.0) * 0.5 * (f_plus + f_minus) * dk * dk;
        }
        row_variance[j] = var;
    });
    for (double v : row_variance) p.expected_variance += v;
    return p;
}

}  // namespace wave
