// Physics: dispersion against its limits and the published table, Newton convergence,
// group velocity, shoaling, breaking, and Fresnel against the exact formula.
#include "libwave/errors.h"
#include "libwave/physics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

using namespace wave;

double deep_wavelength(double period) { return kGravity * period * period / (2.0 * std::numbers::pi); }

TEST(Dispersion, DeepWaterLimitIsExact) {
    for (double T : {1.0, 5.0, 12.0}) {
        const double omega = 2.0 * std::numbers::pi / T;
        const auto s = solve_dispersion(omega, 10.0 * deep_wavelength(T));
        EXPECT_EQ(s.k, deep_water_wavenumber(omega));  // tanh == 1 in double: k∞ exactly
    }
}

TEST(Dispersion, ShallowWaterLimit) {
    // k h -> 0: k = ω/sqrt(g h) · (1 + (k h)²/6 + O((kh)^4)).
    const double T = 10.0, omega = 2.0 * std::numbers::pi / T;
    for (double ratio : {1e-4, 1e-3}) {
        const double h = ratio * deep_wavelength(T);
        const double ks = omega / std::sqrt(kGravity * h);
        const double series = ks * (1.0 + (ks * h) * (ks * h) / 6.0);
        const double k = solve_dispersion(omega, h).k;
        EXPECT_NEAR(k / ks, 1.0, 2.0 * (ks * h) * (ks * h) / 6.0);  // shallow formula to its order
        EXPECT_NEAR(k / series, 1.0, 0.2 * std::pow(ks * h, 4));     // next term of the series
    }
}

TEST(Dispersion, PublishedTableOfLOverL0) {
    // Shore Protection Manual (1984), Table C-1: L/L0 = tanh(2π d/L) against d/L0,
    // tabulated to four decimals (tolerance: half a unit of the last digit + rounding).
    const struct { double d_over_l0, l_over_l0; } table[] = {
        {0.001, 0.0792}, {0.005, 0.1763}, {0.01, 0.2480}, {0.02, 0.3471}, {0.05, 0.5310},
        {0.10, 0.7093},  {0.20, 0.8884},  {0.30, 0.9612}, {0.50, 0.9964}};
    const double T = 8.0, L0 = deep_wavelength(T);
    for (const auto& row : table) {
        const LinearWave w = linear_wave(2.0 * std::numbers::pi / T, row.d_over_l0 * L0);
        EXPECT_NEAR(w.wavelength / L0, row.l_over_l0, 6e-5) << "d/L0 = " << row.d_over_l0;
    }
}

TEST(Dispersion, NewtonConvergesEverywhereInAFewSteps) {
    int worst = 0;
    for (double T : {0.3, 2.0, 8.0, 20.0}) {
        const double omega = 2.0 * std::numbers::pi / T, L0 = deep_wavelength(T);
        for (int n = 0; n <= 400; ++n) {
            const double ratio = std::pow(10.0, -4.0 + 5.0 * n / 400.0);  // 1e-4 … 10
            const double h = ratio * L0;
            const auto s = solve_dispersion(omega, h);
            const double residual = kGravity * s.k * std::tanh(s.k * h) - omega * omega;
            EXPECT_LT(std::abs(residual), 3e-14 * omega * omega) << "h/L0 = " << ratio;
            worst = std::max(worst, s.iterations);
        }
    }
    EXPECT_LE(worst, 5) << "the Fenton–McKee start should need only a few Newton steps";
}

TEST(Dispersion, CapillaryTermMatchesTessendorfEq16) {
    const double L = 2.7e-3, omega = 2.0 * std::numbers::pi / 0.1;  // 10 Hz ripples
    DispersionOptions opt;
    opt.capillary_length = L;
    for (double h : {0.01, 0.1, 5.0}) {
        const auto w = linear_wave(omega, h, opt);
        const double f = kGravity * w.k * (1.0 + w.k * w.k * L * L) * std::tanh(w.k * h);
        EXPECT_NEAR(f / (omega * omega), 1.0, 1e-13);
        EXPECT_LT(w.k, solve_dispersion(omega, h).k);  // surface tension makes waves longer
        // C_g = dω/dk against a central difference of ω(k) = sqrt(g k (1 + k²L²) tanh kh).
        auto om = [&](double k) { return std::sqrt(kGravity * k * (1 + k * k * L * L) * std::tanh(k * h)); };
        const double dk = 1e-6 * w.k;
        EXPECT_NEAR(w.group_velocity, (om(w.k + dk) - om(w.k - dk)) / (2 * dk), 1e-7);
    }
}

TEST(Dispersion, DryAndInvalidInput) {
    const auto s = solve_dispersion(1.0, 0.0);
    EXPECT_TRUE(s.dry);
    EXPECT_EQ(s.k, 0.0);
    const LinearWave w = linear_wave(1.0, -3.0);
    EXPECT_TRUE(w.dry);
    EXPECT_EQ(w.celerity, 0.0);
    EXPECT_EQ(w.shoaling, 0.0);
    EXPECT_THROW(solve_dispersion(0.0, 1.0), InputError);
    EXPECT_THROW(solve_dispersion(NAN, 1.0), InputError);
    EXPECT_THROW(solve_dispersion(1.0, INFINITY), InputError);
    DispersionOptions bad;
    bad.capillary_length = -1.0;
    EXPECT_THROW(solve_dispersion(1.0, 1.0, bad), InputError);
    try {
        wavenumber_for_period(-2.0, 1.0);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("-2"), std::string::npos) << e.what();
    }
}

TEST(GroupVelocity, Limits) {
    EXPECT_DOUBLE_EQ(group_velocity_ratio(0.0), 1.0);
    EXPECT_NEAR(group_velocity_ratio(1e-6), 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(group_velocity_ratio(1e3), 0.5);
    // Shallow water: C_g = C = sqrt(g h).
    // to second order C_g / sqrt(g h) = 1 − (kh)²/2.
    const double h = 0.05, omega = 2.0 * std::numbers::pi / 20.0;
    const auto w = linear_wave(omega, h);
    const double kh = w.k * h;
    EXPECT_NEAR(w.group_velocity / std::sqrt(kGravity * h), 1.0 - 0.5 * kh * kh, 0.5 * std::pow(kh, 4));
}

TEST(Shoaling, DeepUnitMinimumAndGreensLaw) {
    const double T = 10.0, omega = 2.0 * std::numbers::pi / T, L0 = deep_wavelength(T);
    EXPECT_NEAR(shoaling_coefficient(omega, 5.0 * L0), 1.0, 1e-12);
    // The classic minimum K_s = 0.9130 near d/L0 = 0.15 (SPM Table C-1).
    double lowest = 2.0, at = 0.0;
    for (int n = 0; n <= 2000; ++n) {
        const double r = 0.05 + 0.45 * n / 2000.0;
        const double ks = shoaling_coefficient(omega, r * L0);
        if (ks < lowest) lowest = ks, at = r;
    }
    EXPECT_NEAR(lowest, 0.9130, 5e-4);
    EXPECT_NEAR(at, 0.15, 0.02);
    // Shallow water: K_s = sqrt(C_g∞ / sqrt(g h)) (Green's law, H ∝ h^{-1/4}).
    const double h = 1e-4 * L0;
    EXPECT_NEAR(shoaling_coefficient(omega, h) / std::sqrt(0.5 * kGravity / omega / std::sqrt(kGravity * h)), 1.0, 1e-3);
    // Gonzato eq. 3 written as printed: (A/A∞)² = 1 / (tanh Kh (1 + 2Kh / sinh 2Kh)).
    for (double r : {0.02, 0.1, 0.3}) {
        const auto w = linear_wave(omega, r * L0);
        const double kh = w.k * w.depth;
        EXPECT_NEAR(w.shoaling * w.shoaling, 1.0 / (std::tanh(kh) * (1.0 + 2 * kh / std::sinh(2 * kh))), 1e-12);
    }
}

TEST(Refraction, CoefficientFromRaySpacing) {
    EXPECT_DOUBLE_EQ(refraction_coefficient(1.0, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(refraction_coefficient(1.0, 4.0), 0.5);  // diverging rays: smaller waves
    EXPECT_DOUBLE_EQ(refraction_coefficient(4.0, 1.0), 2.0);
}

TEST(Breaking, DepthLimitedAndIribarren) {
    EXPECT_TRUE(is_depth_limited_breaking(0.78, 1.0));
    EXPECT_FALSE(is_depth_limited_breaking(0.77, 1.0));
    EXPECT_TRUE(is_depth_limited_breaking(0.1, 0.0));
    EXPECT_NEAR(iribarren_number(0.1, 1.0, 100.0), 1.0, 1e-15);
    EXPECT_EQ(classify_breaker(0.3), BreakerType::spilling);
    EXPECT_EQ(classify_breaker(0.5), BreakerType::plunging);
    EXPECT_EQ(classify_breaker(3.29), BreakerType::plunging);
    EXPECT_EQ(classify_breaker(3.3), BreakerType::collapsing);
    EXPECT_EQ(classify_breaker(7.0), BreakerType::surging);
    // The names a run's report counts Jeschke's breaking rays by (breaker_types).
    EXPECT_STREQ(to_string(BreakerType::spilling), "spilling");
    EXPECT_STREQ(to_string(BreakerType::plunging), "plunging");
    EXPECT_STREQ(to_string(BreakerType::collapsing), "collapsing");
    EXPECT_STREQ(to_string(BreakerType::surging), "surging");
}

TEST(Breaking, ShoalingProfileOnAPlaneSlope) {
    const double T = 8.0, H0 = 1.0, slope = 0.02, dx = 0.5;
    std::vector<double> depth;
    for (double h = 10.0; h > -1.0; h -= slope * dx) depth.push_back(h);
    const auto p = shoal_profile(2 * std::numbers::pi / T, H0, depth, dx);
    ASSERT_GE(p.break_index, 1);
    const auto b = static_cast<std::size_t>(p.break_index);
    EXPECT_GE(p.height[b], 0.78 * depth[b]);
    EXPECT_LT(p.height[b - 1], 0.78 * depth[b - 1]);  // first breaking sample
    EXPECT_NEAR(p.break_height, H0 * shoaling_coefficient(2 * std::numbers::pi / T, depth[b]), 1e-12);
    // ξ0 = 0.02 / sqrt(1/99.9) ≈ 0.2: a gentle beach gives spilling breakers.
    EXPECT_NEAR(p.iribarren, slope / std::sqrt(H0 / deep_wavelength(T)), 1e-9);
    EXPECT_EQ(p.type, BreakerType::spilling);
    EXPECT_EQ(p.height.back(), 0.0);  // dry
}

// --- Fresnel -------------------------------------------------------------------

double eq44(double theta_i, double n) {  // Tessendorf eq. 44 / Ts'o §4.2.2 as printed
    const double theta_t = std::asin(std::sin(theta_i) / n);
    const double sm = std::sin(theta_t - theta_i), sp = std::sin(theta_t + theta_i);
    const double tm = std::tan(theta_t - theta_i), tp = std::tan(theta_t + theta_i);
    return 0.5 * (sm * sm / (sp * sp) + tm * tm / (tp * tp));
}

TEST(Fresnel, NormalIncidenceGrazingAndEq44) {
    const double n = kWaterRefractiveIndex;
    EXPECT_NEAR(fresnel_reflectivity(1.0), std::pow((n - 1) / (n + 1), 2), 1e-15);
    EXPECT_NEAR(fresnel_reflectivity(1.0), 0.02, 1e-3);
    EXPECT_DOUBLE_EQ(fresnel_reflectivity(0.0), 1.0);
    for (double deg = 1.0; deg < 90.0; deg += 0.5) {
        const double t = deg * std::numbers::pi / 180.0;
        EXPECT_NEAR(fresnel_reflectivity(std::cos(t)), eq44(t, n), 1e-12) << deg;
        EXPECT_NEAR(fresnel_reflectivity(std::cos(t)) + fresnel_transmissivity(std::cos(t)), 1.0, 1e-15);
    }
    // Brewster's angle: the p-polarised part vanishes, R = rs²/2.
    const double brewster = std::atan(n);
    const double ci = std::cos(brewster), ct = std::cos(std::numbers::pi / 2 - brewster);
    const double rs = (ci - n * ct) / (ci + n * ct);
    EXPECT_NEAR(fresnel_reflectivity(ci), 0.5 * rs * rs, 1e-14);
}

TEST(Fresnel, TotalInternalReflectionFromBelow) {
    const double n = kWaterRefractiveIndex;
    const double critical = std::asin(1.0 / n);  // 48.75° (Tessendorf's "Brewster" misnomer)
    EXPECT_NEAR(critical * 180.0 / std::numbers::pi, 48.75, 0.01);
    EXPECT_DOUBLE_EQ(fresnel_reflectivity(std::cos(critical + 1e-6), n, 1.0), 1.0);
    EXPECT_LT(fresnel_reflectivity(std::cos(critical - 1e-3), n, 1.0), 1.0);
    EXPECT_NEAR(fresnel_reflectivity(1.0, n, 1.0), fresnel_reflectivity(1.0, 1.0, n), 1e-15);
}

TEST(Fresnel, TsoApproximation) {
    EXPECT_DOUBLE_EQ(fresnel_reflectivity_tso(0.0), 0.02);
    EXPECT_DOUBLE_EQ(fresnel_reflectivity_tso(std::numbers::pi / 4), 0.02);  // continuous at the join
    EXPECT_NEAR(fresnel_reflectivity_tso(std::numbers::pi / 2), 1.0, 1e-14);
    // The approximation is poor near grazing: its largest error against the exact curve
    // is 0.266 at 79.5° (measured here; the paper shows the curves in its figure 11).
    double worst = 0.0, at = 0.0;
    for (int k = 0; k <= 9000; ++k) {
        const double t = k * (std::numbers::pi / 2) / 9000.0;
        const double e = std::abs(fresnel_reflectivity_tso(t) - fresnel_reflectivity(std::cos(t)));
        if (e > worst) worst = e, at = t * 180.0 / std::numbers::pi;
    }
    EXPECT_NEAR(worst, 0.266, 0.002);
    EXPECT_NEAR(at, 79.5, 0.2);
    // Below 45° the flat 0.02 stays within 0.007 of the exact curve (0.0267 at 44°).
    for (double deg = 0.0; deg < 45.0; deg += 1.0)
        EXPECT_NEAR(fresnel_reflectivity_tso(deg * std::numbers::pi / 180), fresnel_reflectivity(std::cos(deg * std::numbers::pi / 180)), 7e-3);
}

TEST(Fresnel, DirectionsObeySnellAndMirror) {
    const double n = kWaterRefractiveIndex;
    for (double deg = 0.0; deg < 89.0; deg += 7.0) {
        const double t = deg * std::numbers::pi / 180.0;
        const Vec3 down{std::sin(t), 0.0, -std::cos(t)};  // from the air onto z-up water
        for (const Vec3& normal : {Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {  // either orientation
            const Refraction r = refract(down, normal, 1.0, n);
            ASSERT_FALSE(r.total_internal_reflection);
            const Vec3& d = r.direction;
            EXPECT_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-14);
            EXPECT_LT(d[2], 0.0);                                  // continues into the water
            EXPECT_NEAR(n * d[0], std::sin(t), 1e-14);             // n_i sin θi = n_t sin θt
            const Vec3 m = reflect(down, normal);
            EXPECT_NEAR(m[0], down[0], 1e-15);
            EXPECT_NEAR(m[2], -down[2], 1e-15);
        }
        // From below: beyond the critical angle the ray cannot leave the water.
        const Vec3 up{std::sin(t), 0.0, std::cos(t)};
        const Refraction out = refract(up, {0, 0, 1}, n, 1.0);
        EXPECT_EQ(out.total_internal_reflection, n * std::sin(t) > 1.0) << deg;
    }
}

}  // namespace
