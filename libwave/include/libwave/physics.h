/// \file
/// libwave — physics: pure formulas of linear wave theory and optics used by every
/// stage. No dependencies, no allocation, no global state.
///
/// Units: SI (m, s, rad). Depth h is positive under water (h = −z_b); h <= 0 is dry
/// land. Gravity g = 9.81 m/s². Fresnel directions are unit 3-vectors, z up.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace wave {

/// Gravitational acceleration (m/s²), docs/conventions.md.
inline constexpr double kGravity = 9.81;
/// Refractive index of sea water used by Ts'o–Barsky (§4.2.2) and by default here.
inline constexpr double kWaterRefractiveIndex = 1.33;
/// Breaker index γ of depth-limited breaking H >= γ h (McCowan's solitary-wave limit).
inline constexpr double kBreakerIndex = 0.78;

// ---------------------------------------------------------------------------------
// Dispersion
// ---------------------------------------------------------------------------------

/// Options of the dispersion relation ω² = g k (1 + k² L²) tanh(k h)
/// (Tessendorf eqs. 15–16; Ts'o eq. 3.3 for L = 0).
struct DispersionOptions {
    /// Capillary length L (m) of Tessendorf eq. 16; 0 = gravity waves only. For clean
    /// water sqrt(σ/(ρ g)) ≈ 2.7e-3 m. Must be >= 0.
    double capillary_length = 0.0;
    /// Relative tolerance on k at which Newton's iteration stops.
    double relative_tolerance = 1e-14;
};

/// What solve_dispersion found. Produced for every input: no NaN escapes.
struct DispersionSolution {
    double k = 0.0;     ///< wavenumber (rad/m); 0 when dry
    int iterations = 0; ///< Newton steps taken (0 for the exact deep-water shortcut or dry)
    bool dry = false;   ///< depth <= 0: no wave; k, celerity and group velocity are 0
};

/// Deep-water wavenumber k∞ = ω²/g (rad/m), gravity waves.
double deep_water_wavenumber(double omega) noexcept;

/// Deep-water wavelength L∞ = g T² / (2π) of a period T (s), in metres.
double deep_water_wavelength(double period) noexcept;

/// Solves ω² = g k (1 + k²L²) tanh(k h) for k by Newton's method (safeguarded by a
/// bracket) from the Fenton–McKee (1990) explicit approximation, which is within 2 %
/// everywhere, so 2–4 steps reach 1e-14. Deep water (k∞ h > 20) with L = 0 returns
/// k∞ exactly; the shallow limit is the same relation (no switch, no jump).
/// Preconditions: omega > 0 and finite; depth finite (depth <= 0 gives `dry`).
/// Throws InputError for omega <= 0, non-finite arguments or L < 0.
DispersionSolution solve_dispersion(double omega, double depth,
                                    const DispersionOptions& options = {});

/// Convenience: k (rad/m) for period T (s) and depth h (m); 0 when dry.
double wavenumber_for_period(double period, double depth,
                             const DispersionOptions& options = {});

/// Everything linear theory says about a wave of angular frequency ω in depth h.
struct LinearWave {
    double omega = 0.0;          ///< angular frequency (rad/s)
    double depth = 0.0;          ///< water depth h (m)
    double k = 0.0;              ///< wavenumber (rad/m)
    double wavelength = 0.0;     ///< L = 2π/k (m); 0 when dry
    double celerity = 0.0;       ///< phase speed C = ω/k (m/s)
    double group_velocity = 0.0; ///< C_g = C/2 · (1 + 2kh / sinh 2kh) (m/s), with capillary
                                 ///< correction when L > 0 (dω/dk)
    double shoaling = 0.0;       ///< K_s = sqrt(C_g∞ / C_g) (Gonzato eq. 3); 0 when dry
    bool dry = false;            ///< h <= 0: no wave
};

/// Linear wave quantities for (ω, h). Dry (h <= 0) gives all zeros and dry = true.
LinearWave linear_wave(double omega, double depth, const DispersionOptions& options = {});

/// Group velocity over phase speed, n = ½ (1 + 2kh / sinh 2kh), for kh >= 0; exact
/// limits 1 (kh → 0) and ½ (kh → ∞) without overflow.
double group_velocity_ratio(double kh) noexcept;

/// Shoaling coefficient K_s = sqrt(C_g∞ / C_g) for gravity waves of frequency ω in
/// depth h (Gonzato eq. 3: (A/A∞)² = 1 / (tanh Kh (1 + 2Kh / sinh 2Kh))).
/// Returns 0 when dry.
double shoaling_coefficient(double omega, double depth);

/// Refraction coefficient K_r = sqrt(b∞ / b) from the spacing of neighbouring rays
/// in deep water b∞ and here b (both > 0, m). Energy flux between two rays is
/// conserved, so the amplitude scales with 1/sqrt(b) (Gonzato eq. 9 printed inverted).
double refraction_coefficient(double spacing_deep, double spacing_here) noexcept;

/// Angular frequency of a wave of wavenumber k (rad/m) by ω² = g k (1 + k²L²) tanh(k h)
/// (Tessendorf eqs. 14–16): depth h = +inf (or >= 20/k) is deep water, L the capillary
/// length (0 = gravity waves only). Returns 0 for k <= 0 or h <= 0.
double dispersion_omega(double k, double depth = std::numeric_limits<double>::infinity(),
                        double capillary_length = 0.0) noexcept;

/// Tessendorf eq. 18: ω quantised to a whole multiple of ω0 = 2π / repeat_time, so that
/// every wave repeats after repeat_time. The multiple is the nearest one, at least 1
/// (the printed integer part would freeze waves slower than ω0); ω <= 0 gives 0.
/// repeat_time <= 0 returns ω unchanged.
double quantize_frequency(double omega, double repeat_time) noexcept;

// ---------------------------------------------------------------------------------
// Wind-wave spectra (frequency spectra S(ω) in m²·s: ∫ S dω is the elevation variance)
// ---------------------------------------------------------------------------------

/// Pierson & Moskowitz (1964): S(ω) = α g² ω⁻⁵ exp(−β (g / (U ω))⁴), α = 8.1e-3,
/// β = 0.74, U the wind speed at 19.5 m. Variance α U⁴ / (4 β g²), H_s = 0.21 U²/g.
double pierson_moskowitz_spectrum(double omega, double wind_speed) noexcept;

/// JONSWAP (Hasselmann et al. 1973) for a wind U10 blowing over a fetch F:
/// α = 0.076 (U10² / (F g))^0.22, ω_p = 22 (g² / (U10 F))^{1/3}, peak enhancement γ.
struct JonswapParameters {
    double alpha = 0.0;       ///< Phillips' constant α
    double peak_omega = 0.0;  ///< rad/s
    double gamma = 3.3;       ///< peak enhancement γ
};
/// α and ω_p of the wind `wind_speed` (U10, m/s) over the fetch `fetch` (m).
JonswapParameters jonswap_parameters(double wind_speed, double fetch, double peak_enhancement = 3.3) noexcept;

/// The share of the sea surface covered by whitecaps for a wind U10 (m/s): Callaghan,
/// Deane & Stokes (2008, Geophys. Res. Lett. 35, L23609) from 11 years of photographs,
/// W = 3.18·10⁻³ (U − 3.70)³ % up to 9.25 m/s and 4.82·10⁻⁴ (U + 1.98)³ % from 11.25
/// (blended linearly where the two fits overlap, so W is continuous), 0 below 3.70 m/s,
/// extrapolated past their 23 m/s and capped at 1. A fraction in [0, 1]: 0.54 % at
/// 9.25 m/s, 7.5 % at 23, 17 % at 31 (a storm).
double whitecap_coverage(double wind_speed) noexcept;

/// S(ω) = α g² ω⁻⁵ exp(−5/4 (ω_p/ω)⁴) γ^r, r = exp(−(ω − ω_p)² / (2 σ² ω_p²)),
/// σ = 0.07 below the peak and 0.09 above.
double jonswap_spectrum(double omega, const JonswapParameters& p) noexcept;

/// Kitaigorodskii's depth function φ(ω_h), ω_h = ω sqrt(h/g), in the piecewise form of
/// Thompson & Vincent (1983) used by the TMA spectrum: ½ω_h² (ω_h <= 1),
/// 1 − ½(2 − ω_h)² (<= 2), 1 beyond. The share of deep-water energy a wind sea keeps in
/// depth h; 0 when dry, 1 for h = +inf.
double kitaigorodskii_depth_factor(double omega, double depth) noexcept;

// ---------------------------------------------------------------------------------
// Breaking
// ---------------------------------------------------------------------------------

/// Depth-limited breaking: a wave of height H (m, crest to trough) breaks in depth h
/// when H >= γ h. Dry points (h <= 0) count as broken.
bool is_depth_limited_breaking(double wave_height, double depth,
                               double breaker_index = kBreakerIndex) noexcept;

/// Iribarren number (surf similarity) ξ0 = tan β / sqrt(H0 / L0) with the deep-water
/// height H0 and wavelength L0 (Battjes 1974). slope = tan β >= 0.
double iribarren_number(double slope, double deep_height, double deep_wavelength) noexcept;

/// How a wave breaks on a slope (Galvin's types, from the Iribarren number).
enum class BreakerType {
    spilling,    ///< foam spills down the face (gentle slopes; ξ0 below spilling_to_plunging)
    plunging,    ///< the crest curls over and plunges
    collapsing,  ///< the front collapses near the shore
    surging,     ///< the wave surges up the slope, its crest hardly breaking (steep slopes)
};

/// Thresholds on ξ0 between the four breaker types. Battjes (1974) gives 0.5 and
/// 3.3; the collapsing/surging split is usually put near 5 (Galvin's classification
/// has no sharp value).
struct BreakerThresholds {
    double spilling_to_plunging = 0.5;   ///< ξ0 above which a breaker plunges
    double plunging_to_collapsing = 3.3;  ///< ξ0 above which it collapses
    double collapsing_to_surging = 5.0;   ///< ξ0 above which it surges
};

/// The breaker type of the Iribarren number ξ0 `iribarren`.
BreakerType classify_breaker(double iribarren, const BreakerThresholds& thresholds = {}) noexcept;
/// "spilling", "plunging", "collapsing" or "surging".
const char* to_string(BreakerType type) noexcept;

/// A wave shoaling along a depth profile towards the shore (normal incidence, no
/// refraction: the first thing the traced rays refine).
struct ShoalingProfile {
    std::vector<double> height;  ///< H = H∞ K_s at each sample (m); 0 where dry
    std::ptrdiff_t break_index = -1;  ///< first sample with H >= γ h (or dry); −1 if none
    double break_depth = 0.0;    ///< h at break_index (m)
    double break_height = 0.0;   ///< H at break_index (m)
    double iribarren = 0.0;      ///< ξ0 from the mean bottom slope over one local wavelength seaward of the break
    BreakerType type = BreakerType::spilling;  ///< the type ξ0 gives
};

/// Shoals a wave of angular frequency ω and deep-water height H∞ (m, crest to
/// trough) along `depth` samples taken every `spacing` metres from offshore to the
/// shore, and finds where it breaks (H >= γ h). Preconditions: omega > 0,
/// deep_height > 0, spacing > 0.
ShoalingProfile shoal_profile(double omega, double deep_height, std::span<const double> depth,
                              double spacing, double breaker_index = kBreakerIndex,
                              const BreakerThresholds& thresholds = {});

// ---------------------------------------------------------------------------------
// Fresnel optics (Tessendorf §4; Ts'o–Barsky §4.2.2–4.2.3)
// ---------------------------------------------------------------------------------

/// A 3-vector (x, y, z), z up.
using Vec3 = std::array<double, 3>;

/// Exact unpolarised reflectivity R for light going from a medium of index n_i into
/// one of index n_t, at incidence angle θ_i given as cos θ_i in [0, 1] (Tessendorf
/// eq. 44, Ts'o's I). Evaluated from cosines so that normal incidence gives the
/// limit ((n_t − n_i)/(n_t + n_i))² instead of 0/0. Returns 1 beyond the critical
/// angle (total internal reflection, from below when n_i > n_t).
double fresnel_reflectivity(double cos_incidence, double n_incident = 1.0,
                            double n_transmitted = kWaterRefractiveIndex) noexcept;

/// Transmissivity T = 1 − R (Tessendorf eq. 43).
double fresnel_transmissivity(double cos_incidence, double n_incident = 1.0,
                              double n_transmitted = kWaterRefractiveIndex) noexcept;

/// Ts'o–Barsky's approximation (§4.2.3), incidence angle i in radians [0, π/2]:
/// 0.02 for i < π/4, else 392/(25π²) (i − π/4)² + 0.02 (reaches 1 at π/2).
/// Valid for air → water with n = 1.33 only.
double fresnel_reflectivity_tso(double incidence_angle) noexcept;

/// Reflected direction n_r = n_i − 2 n̂ (n̂ · n_i) (Tessendorf eq. 37); incident
/// direction and normal are unit vectors, either side of the surface.
Vec3 reflect(const Vec3& incident, const Vec3& normal) noexcept;

/// A ray through a surface between two media (refract).
struct Refraction {
    Vec3 direction{};                    ///< unit transmitted direction (valid if !total_internal_reflection)
    bool total_internal_reflection = false;  ///< no transmitted ray
};

/// Transmitted direction for a unit incident direction through a surface with unit
/// normal (either orientation), from index n_i into n_t (Tessendorf eqs. 38–42,
/// with the sign of Γ chosen so that the ray crosses the surface). Flags total
/// internal reflection when (n_i/n_t) sin θ_i > 1 (possible only from below).
Refraction refract(const Vec3& incident, const Vec3& normal, double n_incident,
                   double n_transmitted) noexcept;

}  // namespace wave
