// Tessendorf's FFT ocean and Gerstner waves (motion), fold foam (shade): against
// analytic integrals, the statistics of eq. 25, Gerstner's eqs. 9–10, the folding of
// the choppy map (figures 16 and 20), exact loops (eq. 18), and the dispersion
// relation recovered from the animation by a space-time Fourier transform (§3.6).
#include "libwave/errors.h"
#include "libwave/motion.h"
#include "libwave/physics.h"
#include "libwave/shade.h"

#include <fftw3.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

namespace {

using namespace wave;

TEST(OceanSpectrum, PiersonMoskowitzVarianceIsAnalytic) {
    // ∫ α g² ω⁻⁵ e^{−β (g/Uω)⁴} dω = α U⁴ / (4 β g²), whatever the spreading.
    for (double U : {5.0, 12.0, 31.0}) {
        for (double p : {2.0, 6.0}) {
            OceanSpectrum s{.model = OceanSpectrumModel::pierson_moskowitz, .wind_speed = U, .directional_exponent = p};
            const double exact = 8.1e-3 * std::pow(U, 4) / (4.0 * 0.74 * kGravity * kGravity);
            EXPECT_NEAR(ocean_spectrum_variance(s) / exact, 1.0, 1e-6) << "U " << U << " p " << p;
            s.against_wind = 0.0;  // a one-sided sea keeps the spectrum's energy
            EXPECT_NEAR(ocean_spectrum_variance(s) / exact, 1.0, 1e-6);
        }
        // H_s = 0.21 U²/g, the textbook value.
        const double hs = 4.0 * std::sqrt(ocean_spectrum_variance({.model = OceanSpectrumModel::pierson_moskowitz, .wind_speed = U}));
        EXPECT_NEAR(hs / (U * U / kGravity), 0.209, 0.001);
    }
}

TEST(OceanSpectrum, PhillipsVarianceIsAnalytic) {
    // eq. 23 with p = 2, no cutoff: A ∫ e^{−1/(kL)²} k⁻³ dk ∫ cos²θ dθ = A π L² / 2.
    const OceanSpectrum s{.model = OceanSpectrumModel::phillips, .wind_speed = 31.0};
    const double L = 31.0 * 31.0 / kGravity;
    EXPECT_NEAR(ocean_spectrum_variance(s) / (s.phillips_constant * std::numbers::pi * L * L / 2.0), 1.0, 1e-6);
    // The default A matches Pierson–Moskowitz's tail: F k (per unit k, all directions)
    // = α / (2 k³) far above the peak.
    const double k = 50.0 / L;
    double omni = 0.0;
    for (int i = 0; i < 3600; ++i) {
        const double th = 2.0 * std::numbers::pi * (i + 0.5) / 3600.0;
        omni += ocean_spectrum_density(s, k * std::cos(th), k * std::sin(th)) * k * 2.0 * std::numbers::pi / 3600.0;
    }
    EXPECT_NEAR(omni / (8.1e-3 / (2.0 * k * k * k)), std::exp(-1.0 / 2500.0), 1e-6);
}

TEST(OceanSpectrum, JonswapAndTma) {
    // γ = 1 is Pierson–Moskowitz's shape (with JONSWAP's α and ω_p): the variance is
    // α g² / (5 ω_p⁴) exactly.
    const OceanSpectrum s{.model = OceanSpectrumModel::jonswap, .wind_speed = 15.0, .fetch = 50e3, .peak_enhancement = 1.0};
    const auto p = jonswap_parameters(15.0, 50e3, 1.0);
    EXPECT_NEAR(ocean_spectrum_variance(s) / (p.alpha * kGravity * kGravity / (5.0 * std::pow(p.peak_omega, 4))), 1.0, 1e-6);
    // Peak enhancement raises the energy; TMA in shallow water lowers it, and in deep
    // water TMA is JONSWAP.
    OceanSpectrum j = s;
    j.peak_enhancement = 3.3;
    const double vj = ocean_spectrum_variance(j);
    EXPECT_GT(vj, ocean_spectrum_variance(s) * 1.3);
    OceanSpectrum t = j;
    t.model = OceanSpectrumModel::tma;
    t.depth = 1000.0;
    EXPECT_NEAR(ocean_spectrum_variance(t) / vj, 1.0, 1e-6);
    t.depth = 3.0;
    EXPECT_LT(ocean_spectrum_variance(t), 0.5 * vj);
    // Kitaigorodskii's φ: ½ω_h² below 1, continuous at 1 and 2, 1 in deep water.
    const double w = 1.0;
    EXPECT_NEAR(kitaigorodskii_depth_factor(w, 0.5 * kGravity), 0.25, 1e-12);
    for (double wh : {1.0, 2.0}) {
        const double h = wh * wh * kGravity;  // ω_h = ω sqrt(h/g) with ω = 1
        EXPECT_NEAR(kitaigorodskii_depth_factor(w, h * (1 - 1e-9)), kitaigorodskii_depth_factor(w, h * (1 + 1e-9)), 1e-8);
    }
    EXPECT_EQ(kitaigorodskii_depth_factor(w, 100.0), 1.0);
    EXPECT_EQ(kitaigorodskii_depth_factor(w, 0.0), 0.0);
}

TEST(OceanDispersion, ForwardRelationAndQuantisation) {
    // dispersion_omega inverts solve_dispersion (eqs. 14–16).
    for (double h : {0.5, 5.0, 1e6})
        for (double L : {0.0, 2.7e-3})
            for (double T : {0.2, 2.0, 12.0}) {
                const double omega = 2.0 * std::numbers::pi / T;
                const double k = solve_dispersion(omega, h, {.capillary_length = L}).k;
                EXPECT_NEAR(dispersion_omega(k, h, L) / omega, 1.0, 1e-12);
            }
    EXPECT_NEAR(dispersion_omega(1.0), std::sqrt(kGravity), 1e-15);
    // eq. 18: whole multiples of ω0 = 2π/T, the nearest one (within ω0/2), at least ω0.
    const double w0 = 2.0 * std::numbers::pi / 20.0;
    for (double omega : {0.7, 3.3, 0.2 * w0, 1.49 * w0, 1.51 * w0}) {
        const double q = quantize_frequency(omega, 20.0);
        EXPECT_NEAR(q / w0, std::round(q / w0), 1e-12);
        EXPECT_GE(q, w0);
        if (omega > w0) {
            EXPECT_LE(std::abs(q - omega), 0.5 * w0 + 1e-12);
        }
    }
    EXPECT_EQ(quantize_frequency(1.49 * w0, 20.0), w0);
    EXPECT_EQ(quantize_frequency(1.51 * w0, 20.0), 2.0 * w0);
    EXPECT_EQ(quantize_frequency(0.0, 20.0), 0.0);
    EXPECT_EQ(quantize_frequency(0.7, 0.0), 0.7);
}

OceanOptions small_ocean() {
    OceanOptions o;
    o.resolution = 64;
    o.size = 200.0;
    o.spectrum.wind_speed = 10.0;  // L = 10.2 m: the peak (λ ≈ 78 m) and the tail on the grid
    o.spectrum.small_wave_cutoff = 1.0;
    return o;
}

double sample_variance(std::span<const float> h) {
    double m = 0.0, s = 0.0;
    for (float v : h) m += v;
    m /= static_cast<double>(h.size());
    for (float v : h) s += (v - m) * (v - m);
    return s / static_cast<double>(h.size());
}

TEST(OceanFft, SampleVarianceMatchesTheSpectrum) {
    // Parseval: the sample variance is Σ |h̃(k,t)|² over the lattice; for each pair
    // (k, −k) that is 2 |a e^{−iωt} + conj(b) e^{iωt}|², an exponential variable of mean
    // 2 (P(k) + P(−k)), P = F Δk²/2. Its mean is plan.expected_variance and its
    // standard deviation sqrt(Σ 4 μ²), computed here from the same lattice.
    OceanOptions o = small_ocean();
    const OceanPlan p0 = plan_ocean(o);
    const double dk = 2.0 * std::numbers::pi / o.size;
    double mean = 0.0, var = 0.0;
    const long N = 64;
    for (long m = -N / 2 + 1; m < N / 2; ++m)
        for (long n = -N / 2 + 1; n < N / 2; ++n) {
            if (n < 0 || (n == 0 && m <= 0)) continue;  // one of each pair
            const double mu = (ocean_spectrum_density(o.spectrum, double(n) * dk, double(m) * dk) +
                               ocean_spectrum_density(o.spectrum, -double(n) * dk, -double(m) * dk)) * dk * dk / 2.0;
            mean += 2.0 * mu;
            var += 4.0 * mu * mu;
        }
    EXPECT_NEAR(p0.expected_variance / mean, 1.0, 1e-9);
    // The lattice resolves the spectrum: within 3 % of the continuous integral (eq. 24's
    // cutoff included; what is lost is below the patch's fundamental and beyond Nyquist).
    EXPECT_NEAR(mean / ocean_spectrum_variance(o.spectrum), 1.0, 0.03);
    // Average over 16 seeds and 2 times: within 4 standard deviations of the mean.
    const int seeds = 16;
    double sum = 0.0;
    OceanWorkspace ws(o.resolution);
    for (int s = 0; s < seeds; ++s) {
        o.seed = 1000 + static_cast<std::uint64_t>(s);
        const OceanPlan p = plan_ocean(o);
        sum += sample_variance(evaluate_ocean(p, 0.0, ws).height.values());
        sum += sample_variance(evaluate_ocean(p, 7.3, ws).height.values());
    }
    const double avg = sum / (2 * seeds);
    // Two times of one seed are not independent: count seeds only in the error.
    EXPECT_NEAR(avg, mean, 4.0 * std::sqrt(var / seeds)) << "mean " << mean << " sd " << std::sqrt(var);
}

TEST(OceanFft, SingleModeIsGerstner) {
    // One wave component: the FFT's height and x − λD with λ = 1 are Gerstner's eqs. 9–10
    // (Tessendorf §3.7 says the two are alike; with the sign used here they are equal).
    OceanOptions o = small_ocean();
    o.choppiness = 1.0;
    OceanPlan p = plan_ocean(o);
    std::fill(p.h0.begin(), p.h0.end(), std::complex<float>{});
    std::fill(p.h0_minus.begin(), p.h0_minus.end(), std::complex<float>{});
    const std::size_t i = 3, j = 2, e = j * p.half() + i;  // k = 2π/200 (3, 2)
    const double A = 1.5;
    p.h0[e] = {static_cast<float>(A / 2), 0.0f};  // h = 2 Re(h̃ e^{ik·x}) = A cos(k·x − ωt)
    const GerstnerWave g{.kx = p.kx[i], .ky = p.ky[j], .amplitude = A, .omega = p.omega[e]};
    OceanWorkspace ws(p.n);
    const double t = 4.2;
    const OceanFields f = evaluate_ocean(p, t, ws);
    const std::size_t side = p.n + 1, count = side * side;
    std::vector<float> pos(3 * count), nrm(3 * count), jm(count);
    ocean_patch_frame(p, f, pos, nrm, jm);
    std::vector<double> x(count), y(count);
    std::vector<float> gp(3 * count);
    for (std::size_t v = 0; v < count; ++v) {
        x[v] = p.spacing() * static_cast<double>(v % side);
        y[v] = p.spacing() * static_cast<double>(v / side);
        gp[3 * v] = static_cast<float>(x[v]);
        gp[3 * v + 1] = static_cast<float>(y[v]);
    }
    add_gerstner_waves(std::span<const GerstnerWave>(&g, 1), x, y, {}, t, gp);
    double worst = 0.0;
    for (std::size_t q = 0; q < 3 * count; ++q) worst = std::max(worst, std::abs(double(pos[q]) - gp[q]));
    EXPECT_LT(worst, 1e-4);  // float FFT of a 1.5 m wave on a 200 m patch
    // Its Jacobian is 1 − kA cos θ along k̂ (folding at the crest when kA > 1).
    const double k = std::hypot(g.kx, g.ky);
    for (std::size_t v = 0; v < count; v += 97) {
        const double theta = g.kx * x[v] + g.ky * y[v] - g.omega * t;
        EXPECT_NEAR(jm[v], std::min(1.0, 1.0 - k * A * std::cos(theta)), 1e-5);
    }
    EXPECT_NEAR(gerstner_steepness(std::span<const GerstnerWave>(&g, 1)), k * A, 1e-12);
}

TEST(OceanFft, FoldsExactlyWhereTheJacobianIsNegative) {
    // A 1D random sea (only the k_y = 0 row of a real spectrum) with strong chop: the
    // horizontal map x → x − λDx(x) runs backwards (the surface folds, figures 16 and
    // 20) exactly where J₋ = J < 0.
    OceanOptions o = small_ocean();
    o.resolution = 1024;
    o.size = 400.0;
    o.spectrum.small_wave_cutoff = 0.5;
    OceanPlan p = plan_ocean(o);
    for (std::size_t j = 1; j < p.n; ++j)
        for (std::size_t i = 0; i < p.half(); ++i) p.h0[j * p.half() + i] = p.h0_minus[j * p.half() + i] = {};
    OceanWorkspace ws(p.n);
    const OceanFields f = evaluate_ocean(p, 3.0, ws);
    // λ such that the steepest point folds to J = −0.5 (the fields do not depend on λ).
    float steepest = 0.0f;
    for (std::size_t i = 0; i < p.n; ++i) steepest = std::max(steepest, f.disp_xx[i]);
    p.choppiness = 1.5 / steepest;
    std::size_t folded = 0, checked = 0, disagree = 0;
    for (std::size_t i = 0; i + 1 < p.n; ++i) {
        const double X0 = p.spacing() * double(i) - p.choppiness * f.disp_x[i];
        const double X1 = p.spacing() * double(i + 1) - p.choppiness * f.disp_x[i + 1];
        const double jm = 0.5 * (ocean_jacobian(f.disp_xx[i], f.disp_yy[i], f.disp_xy[i], p.choppiness).j +
                                 ocean_jacobian(f.disp_xx[i + 1], f.disp_yy[i + 1], f.disp_xy[i + 1], p.choppiness).j);
        if (std::abs(jm) < 0.05) continue;  // at a fold's edge the midpoint rule cannot decide
        ++checked;
        folded += X1 < X0;
        disagree += (X1 < X0) != (jm < 0.0);
        const auto J = ocean_jacobian(f.disp_xx[i], f.disp_yy[i], f.disp_xy[i], p.choppiness);
        EXPECT_NEAR(J.j, J.j_minus * J.j_plus, 1e-9);
        // Nothing varies along y: the eigenvalues are 1 − λ ∂Dx/∂x and 1. ∂Dy/∂y is 0 but
        // for the float rounding of the transform it shares with ∂Dx/∂x (evaluate_ocean's
        // pairs): within 1e-6 of the steepest ∂Dx/∂x.
        EXPECT_LE(std::abs(f.disp_yy[i]), 1e-6 * steepest);
        EXPECT_NEAR(J.j_minus + J.j_plus, 2.0 - p.choppiness * f.disp_xx[i], 1e-6);
        EXPECT_LE(J.j_minus, 1.0 + 1e-6 * p.choppiness * steepest);
    }
    EXPECT_GT(folded, 20u) << "the test needs folds";
    EXPECT_LT(folded, checked / 2);
    EXPECT_EQ(disagree, 0u);
}

TEST(OceanFft, EigenvectorPointsAcrossTheFold) {
    // eqs. 33–34: ê₋ is the unit eigenvector of J₋; for a wave along k̂ it is ±k̂.
    const double c = std::cos(0.6), s = std::sin(0.6), a = 0.8;  // ∂D = a k̂ k̂ᵀ
    const auto J = ocean_jacobian(a * c * c, a * s * s, a * c * s, 2.0);
    EXPECT_NEAR(J.j_minus, 1.0 - 2.0 * a, 1e-12);
    EXPECT_NEAR(J.j_plus, 1.0, 1e-12);
    EXPECT_NEAR(std::abs(J.e_minus[0] * c + J.e_minus[1] * s), 1.0, 1e-12);
}

TEST(OceanFft, LoopsBitIdentically) {
    OceanOptions o = small_ocean();
    o.repeat_time = 20.0;
    const OceanPlan p = plan_ocean(o);
    OceanWorkspace ws(p.n);
    const double fps = 24.0;
    const std::vector<float> first = evaluate_ocean(p, 0.0 / fps, ws).height.values();
    const std::vector<float> last = evaluate_ocean(p, 480.0 / fps, ws).height.values();  // frame T·fps
    ASSERT_EQ(first.size(), last.size());
    EXPECT_EQ(std::memcmp(first.data(), last.data(), first.size() * sizeof(float)), 0);
    const std::vector<float> mid = evaluate_ocean(p, 10.0, ws).height.values();
    EXPECT_NE(std::memcmp(first.data(), mid.data(), first.size() * sizeof(float)), 0);
    // Every quantised frequency is a multiple of 2π/T.
    for (std::size_t e = 0; e < p.omega.size(); ++e)
        EXPECT_EQ(p.omega[e], p.omega_steps[e] * (2.0 * std::numbers::pi / 20.0));
}

TEST(OceanFft, SameBitsForAnyThreadCount) {
    const OceanOptions o = small_ocean();
    std::vector<float> one, two;
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        const OceanPlan p = plan_ocean(o);
        OceanWorkspace ws(p.n);
        const OceanFields f = evaluate_ocean(p, 2.5, ws);
        auto& out = threads == 1 ? one : two;
        for (auto field : {f.height, f.disp_x, f.disp_xy, f.slope_y}) {
            const std::vector<float> v = field.values();
            out.insert(out.end(), v.begin(), v.end());
        }
    }
    EXPECT_EQ(one, two);
}

// The fields come in pairs, two real fields from one complex transform (the spectrum
// A + iB over the whole lattice): each equals its own real transform from the half
// lattice (FFTW's complex-to-real, as eqs. 19, 20 and 29 write the spectra) to float
// rounding, within 1e-6 of its largest value — for every field, so every pair's factors
// and its mirror's signs are right.
TEST(OceanFft, EachPairedFieldIsItsOwnRealTransform) {
    OceanOptions o = small_ocean();
    o.choppiness = 1.3;
    const OceanPlan p = plan_ocean(o);  // no repeat time: h̃ from ω itself
    const double t = 4.75;
    OceanWorkspace ws(p.n);
    const OceanFields f = evaluate_ocean(p, t, ws);
    const std::size_t n = p.n, half = p.half();
    fftwf_complex* in = fftwf_alloc_complex(n * half);
    std::vector<float> out(n * n);
    fftwf_plan plan = fftwf_plan_dft_c2r_2d(int(n), int(n), in, out.data(), FFTW_ESTIMATE);
    using C = std::complex<float>;
    const C i1(0.0f, 1.0f);
    // Each field's spectrum as factor(k) · h̃ (eqs. 19, 20, 29 and the derivatives of 29).
    const std::vector<std::pair<OceanField, std::function<C(float, float, float)>>> fields{
        {f.height, [](float, float, float) { return C(1.0f); }},
        {f.slope_x, [&](float kx, float, float) { return i1 * kx; }},
        {f.slope_y, [&](float, float ky, float) { return i1 * ky; }},
        {f.disp_x, [&](float kx, float, float ik) { return -i1 * kx * ik; }},
        {f.disp_y, [&](float, float ky, float ik) { return -i1 * ky * ik; }},
        {f.disp_xx, [](float kx, float, float ik) { return C(kx * kx * ik); }},
        {f.disp_yy, [](float, float ky, float ik) { return C(ky * ky * ik); }},
        {f.disp_xy, [](float kx, float ky, float ik) { return C(kx * ky * ik); }},
    };
    for (std::size_t q = 0; q < fields.size(); ++q) {
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t i = 0; i < half; ++i) {
                const std::size_t e = j * half + i;
                const C ef(std::polar(1.0, -p.omega[e] * t));
                const C h = p.h0[e] * ef + p.h0_minus[e] * std::conj(ef);
                const C v = fields[q].second(p.kx[i], p.ky[j], p.inv_k[e]) * h;
                in[e][0] = v.real();
                in[e][1] = v.imag();
            }
        fftwf_execute(plan);
        float largest = 0.0f, worst = 0.0f;
        for (std::size_t c = 0; c < n * n; ++c) {
            largest = std::max(largest, std::abs(out[c]));
            worst = std::max(worst, std::abs(out[c] - fields[q].first[c]));
        }
        EXPECT_GT(largest, 0.0f) << "field " << q;
        EXPECT_LE(worst, 1e-6f * largest) << "field " << q << ": largest " << largest;
    }
    fftwf_destroy_plan(plan);
    fftwf_free(in);
}

// The wisdom libwave ships (bench/fftw_wisdom.cpp) holds a plan for every resolution
// the scene accepts, and a workspace planned after FFTW forgot it (a host may call
// fftwf_forget_wisdom) computes the same bits: the plan comes from the wisdom alone.
TEST(OceanFft, ShippedWisdomPlansEveryResolution) {
    const char* const wisdom =
#include "motion/ocean_fft_wisdom.inc"
        ;
    ASSERT_NE(fftwf_import_wisdom_from_string(wisdom), 0);
    for (int n = 16; n <= 4096; n *= 2) {
        fftwf_complex* data = fftwf_alloc_complex(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
        fftwf_plan plan = fftwf_plan_dft_2d(n, n, data, data, FFTW_BACKWARD, FFTW_MEASURE | FFTW_WISDOM_ONLY);
        EXPECT_NE(plan, nullptr) << n << "²";
        if (plan) fftwf_destroy_plan(plan);
        fftwf_free(data);
    }
    const OceanPlan p = plan_ocean(small_ocean());
    std::vector<float> kept;
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) fftwf_forget_wisdom();
        OceanWorkspace ws(p.n);
        const OceanFields f = evaluate_ocean(p, 3.25, ws);
        if (pass == 0) kept = f.disp_xy.values();
        else EXPECT_EQ(kept, f.disp_xy.values());
    }
}

// The patch in blocks of rows (as the ocean's frames are made, each block's Fresnel
// weights beside it) is the whole frame's patch to the bit, the repeated last row
// included; rows beyond the lattice and spans of the wrong size are refused. The
// normals and J₋ are computed in float: against the double Jacobian (ocean_jacobian),
// J₋ within 1e-5 and each normal a unit vector within 1e-6.
TEST(OceanFft, PatchRowsAreTheFrameBitForBit) {
    OceanOptions o = small_ocean();
    o.choppiness = 1.3;
    const OceanPlan p = plan_ocean(o);
    OceanWorkspace ws(p.n);
    const OceanFields f = evaluate_ocean(p, 2.0, ws);
    const std::size_t side = p.n + 1, count = side * side;
    std::vector<float> pos(3 * count), nrm(3 * count), jm(count), pos2(3 * count), nrm2(3 * count), jm2(count);
    ocean_patch_frame(p, f, pos, nrm, jm);
    for (std::size_t first = 0; first < side; first += 7) {
        const std::size_t rows = std::min<std::size_t>(7, side - first), v = first * side, size = rows * side;
        ocean_patch_rows(p, f, first, rows, std::span<float>(pos2).subspan(3 * v, 3 * size),
                         std::span<float>(nrm2).subspan(3 * v, 3 * size), std::span<float>(jm2).subspan(v, size));
    }
    EXPECT_EQ(std::memcmp(pos.data(), pos2.data(), pos.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(nrm.data(), nrm2.data(), nrm.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(jm.data(), jm2.data(), jm.size() * sizeof(float)), 0);
    double worst_j = 0.0, worst_unit = 0.0;
    for (std::size_t row = 0; row < side; ++row)
        for (std::size_t col = 0; col < side; ++col) {
            const std::size_t v = row * side + col, i = (row % p.n) * p.n + col % p.n;
            const auto J = ocean_jacobian(f.disp_xx[i], f.disp_yy[i], f.disp_xy[i], p.choppiness);
            worst_j = std::max(worst_j, std::abs(jm[v] - J.j_minus));
            worst_unit = std::max(worst_unit, std::abs(std::hypot(nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2]) - 1.0));
        }
    EXPECT_LT(worst_j, 1e-5);
    EXPECT_LT(worst_unit, 1e-6);
    std::vector<float> one(3 * side), j_one(side);
    EXPECT_THROW(ocean_patch_rows(p, f, side, 1, one, one, j_one), InputError);       // beyond the last row
    EXPECT_THROW(ocean_patch_rows(p, f, 0, 2, one, one, j_one), InputError);          // spans for one row
    EXPECT_NO_THROW(ocean_patch_rows(p, f, side - 1, 1, one, std::span<float>(nrm2).first(3 * side), {}));
    // Fields not laid out as evaluate_ocean lays them (its pairs interleaved) are
    // refused, not read out of step: contiguous copies, or the pairs' partners swapped.
    const std::vector<float> height = f.height.values(), dxx = f.disp_xx.values();
    OceanFields contiguous = f;
    contiguous.height = {height.data(), 1, height.size()};
    std::vector<float> whole_p(3 * side * side), whole_n(3 * side * side), whole_j(side * side), lattice_j(p.n * p.n);
    EXPECT_THROW(ocean_patch_frame(p, contiguous, whole_p, whole_n, whole_j), InputError);
    EXPECT_THROW(ocean_jacobian_field(p, contiguous, lattice_j), InputError);
    OceanFields swapped = f;
    std::swap(swapped.disp_xx, swapped.disp_yy);
    EXPECT_THROW(ocean_patch_rows(p, swapped, 0, 1, one, std::span<float>(nrm2).first(3 * side), {}), InputError);
    EXPECT_THROW(ocean_jacobian_field(p, swapped, lattice_j), InputError);
    OceanFields only_jacobian;  // what evaluate_ocean_jacobian makes: its two pairs, enough for J₋
    only_jacobian.n = f.n;
    only_jacobian.disp_xx = f.disp_xx, only_jacobian.disp_yy = f.disp_yy, only_jacobian.disp_xy = f.disp_xy;
    only_jacobian.height = f.height;
    EXPECT_NO_THROW(ocean_jacobian_field(p, only_jacobian, lattice_j));
    EXPECT_THROW(ocean_patch_frame(p, only_jacobian, whole_p, whole_n, whole_j), InputError);
    contiguous = f;
    contiguous.disp_xx = {dxx.data(), 1, dxx.size()};
    EXPECT_THROW(ocean_jacobian_field(p, contiguous, lattice_j), InputError);
}

TEST(OceanFft, SlopesAndNormalsAreExact) {
    // eq. 20's spectral slope against a central difference of the height on a smooth
    // sea (the cutoff keeps waves > 8 cells long), and the patch normal against the
    // cross product of the displaced surface's finite-difference tangents.
    OceanOptions o = small_ocean();
    o.spectrum.small_wave_cutoff = 8.0;
    o.choppiness = 0.8;
    const OceanPlan p = plan_ocean(o);
    OceanWorkspace ws(p.n);
    const OceanFields f = evaluate_ocean(p, 1.0, ws);
    const std::size_t n = p.n, side = n + 1;
    std::vector<float> pos(3 * side * side), nrm(3 * side * side);
    ocean_patch_frame(p, f, pos, nrm, {});
    double slope_err = 0.0, slope_max = 0.0, angle = 0.0;
    for (std::size_t j = 1; j + 1 < n; ++j)
        for (std::size_t i = 1; i + 1 < n; ++i) {
            const double fd = (f.height[j * n + i + 1] - f.height[j * n + i - 1]) / (2.0 * p.spacing());
            slope_err = std::max(slope_err, std::abs(fd - f.slope_x[j * n + i]));
            slope_max = std::max(slope_max, std::abs(double(f.slope_x[j * n + i])));
            const auto P = [&](std::size_t jj, std::size_t ii, int c) { return double(pos[3 * (jj * side + ii) + c]); };
            double tx[3], ty[3];
            for (int c = 0; c < 3; ++c) {
                tx[c] = P(j, i + 1, c) - P(j, i - 1, c);
                ty[c] = P(j + 1, i, c) - P(j - 1, i, c);
            }
            const double cx = tx[1] * ty[2] - tx[2] * ty[1], cy = tx[2] * ty[0] - tx[0] * ty[2], cz = tx[0] * ty[1] - tx[1] * ty[0];
            const double len = std::sqrt(cx * cx + cy * cy + cz * cz);
            const float* nv = &nrm[3 * (j * side + i)];
            angle = std::max(angle, std::acos(std::min(1.0, (cx * nv[0] + cy * nv[1] + cz * nv[2]) / len)));
        }
    EXPECT_LT(slope_err, 0.05 * slope_max);  // central differences: O((k dx)²) with k dx <= 0.35
    EXPECT_LT(angle, 2.0 * std::numbers::pi / 180.0);
}

TEST(OceanFft, DispersionRecoveredFromTheAnimation) {
    // Tessendorf §3.6: transform the animated heights in space and time; each
    // wavevector's energy lies at ω² = g k tanh(k h) (here finite depth h = 2 m, no
    // quantisation), within one frequency bin.
    OceanOptions o;
    o.resolution = 16;
    o.size = 40.0;
    o.spectrum.wind_speed = 6.0;
    o.spectrum.depth = 2.0;
    const OceanPlan p = plan_ocean(o);
    OceanWorkspace ws(p.n);
    const std::size_t n = p.n, frames = 256;
    const double dt = 0.1;
    std::vector<std::vector<float>> h(frames);
    for (std::size_t f = 0; f < frames; ++f) {
        h[f] = evaluate_ocean(p, static_cast<double>(f) * dt, ws).height.values();
    }
    const double dk = 2.0 * std::numbers::pi / o.size, dw = 2.0 * std::numbers::pi / (frames * dt);
    int checked = 0;
    for (long m = -3; m <= 3; ++m)
        for (long q = 1; q <= 5; ++q) {
            // spatial DFT at k = (q, m) Δk, per frame
            std::vector<std::complex<double>> c(frames);
            for (std::size_t f = 0; f < frames; ++f)
                for (std::size_t j = 0; j < n; ++j)
                    for (std::size_t i = 0; i < n; ++i)
                        c[f] += double(h[f][j * n + i]) *
                                std::polar(1.0, -2.0 * std::numbers::pi * (double(q) * double(i) + double(m) * double(j)) / double(n));
            // temporal DFT: the peak over ω
            double best = 0.0, best_w = 0.0;
            for (long b = -long(frames) / 2; b < long(frames) / 2; ++b) {
                std::complex<double> s;
                for (std::size_t f = 0; f < frames; ++f) s += c[f] * std::polar(1.0, 2.0 * std::numbers::pi * double(b) * double(f) / double(frames));
                if (std::abs(s) > best) best = std::abs(s), best_w = std::abs(double(b) * dw);
            }
            const double k = dk * std::hypot(double(q), double(m));
            EXPECT_NEAR(best_w, std::sqrt(kGravity * k * std::tanh(2.0 * k)), dw) << "k " << k;
            ++checked;
        }
    EXPECT_EQ(checked, 35);
}

TEST(OceanFft, SamplingInterpolatesTheLatticeAndTiles) {
    const OceanPlan p = plan_ocean(small_ocean());
    OceanWorkspace ws(p.n);
    const OceanFields f = evaluate_ocean(p, 0.5, ws);
    const std::vector<double> x{0.0, 3 * p.spacing(), 3 * p.spacing() + p.size, -p.size + 5 * p.spacing()};
    const std::vector<double> y{0.0, 7 * p.spacing(), 7 * p.spacing() - 2 * p.size, 0.0};
    std::vector<float> pos(12, 0.0f);
    add_ocean_samples(p, f, x, y, {}, pos);
    EXPECT_FLOAT_EQ(pos[2], f.height[0]);
    EXPECT_NEAR(pos[5], f.height[7 * p.n + 3], 1e-6);
    EXPECT_NEAR(pos[8], pos[5], 1e-6);  // one patch further: the same water
    EXPECT_NEAR(pos[11], f.height[5], 1e-6);
    EXPECT_NEAR(pos[3], -p.choppiness * f.disp_x[7 * p.n + 3], 1e-6);
    // The depth factor: 1 in deep water, ≈ 0 near the shore, monotonic.
    EXPECT_EQ(wind_sea_depth_factor(1.0, std::numeric_limits<double>::infinity()), 1.0);
    EXPECT_LT(wind_sea_depth_factor(1.0, 0.05), 0.06);
    EXPECT_LT(wind_sea_depth_factor(1.0, 1.0), wind_sea_depth_factor(1.0, 3.0));
}

TEST(OceanFft, BadOptionsNameTheField) {
    const auto message = [](OceanOptions o) {
        try {
            validate_ocean_options(o, "scene.json: /ocean");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    OceanOptions o;
    o.resolution = 100;
    EXPECT_NE(message(o).find("/ocean/resolution: expected a power of two"), std::string::npos) << message(o);
    o = {};
    o.spectrum.wind_speed = 0.0;
    EXPECT_NE(message(o).find("/ocean/wind_speed: expected a wind speed > 0"), std::string::npos);
    o = {};
    o.spectrum.small_wave_cutoff = 1000.0;
    EXPECT_NE(message(o).find("/ocean/small_wave_cutoff: the cutoff 1000 m is not smaller than the patch"), std::string::npos) << message(o);
    o = {};
    o.spectrum.model = OceanSpectrumModel::tma;
    EXPECT_NE(message(o).find("/ocean/depth: the TMA spectrum needs a finite water depth"), std::string::npos);
    o = {};
    o.repeat_time = -1.0;
    EXPECT_NE(message(o).find("/ocean/repeat_time"), std::string::npos);
    EXPECT_EQ(message(OceanOptions{}), "");
    OceanWorkspace ws(32);
    EXPECT_THROW(evaluate_ocean(plan_ocean(small_ocean()), 0.0, ws), InputError);  // 64² plan, 32² workspace
}

TEST(FoldFoam, CoverageFadeAndLattice) {
    FoldFoamOptions o;
    EXPECT_EQ(fold_coverage(0.5, o), 0.0);
    EXPECT_EQ(fold_coverage(0.4, o), 0.0);
    EXPECT_NEAR(fold_coverage(0.25, o), 0.5, 1e-12);
    EXPECT_EQ(fold_coverage(0.1, o), 1.0);
    o.threshold = 0.0;  // Tessendorf's strict criterion: foam only where the map folds
    EXPECT_EQ(fold_coverage(0.0, o), 0.0);
    EXPECT_NEAR(fold_coverage(-0.15, o), 0.5, 1e-12);
    o = {};
    EXPECT_EQ(fold_fade(0.0, o), 1.0);
    EXPECT_EQ(fold_fade(o.window, o), 0.0);
    EXPECT_NEAR(fold_fade(o.window - 1e-9, o), 0.0, 1e-8);  // no pop when a time leaves the window
    for (double a = 0.0; a < o.window; a += 0.1) EXPECT_GT(fold_fade(a, o), fold_fade(a + 0.1, o));
    // With a loop of 10 s and a 0.3 s step, the step becomes 10/33 s and the lattice
    // indices at t and t + T differ by exactly 33.
    double step = 0.0;
    o.lattice_step = 0.3;
    const auto a = fold_lattice(1.0, o, 10.0, step);
    EXPECT_NEAR(step, 10.0 / 33.0, 1e-15);
    const auto b = fold_lattice(11.0, o, 10.0, step);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(b[i] - a[i], 33);
    for (long long j : a) {
        EXPECT_LE(double(j) * step, 1.0 + 1e-12);
        EXPECT_GT(double(j) * step, 1.0 - o.window);
    }
    // Foam combines with what is already there by max, and fades.
    std::vector<float> foam{0.3f, 0.0f}, jm{-1.0f, -1.0f};
    accumulate_fold_foam(jm, 1.0, o, foam);
    EXPECT_NEAR(foam[1], fold_fade(1.0, o), 1e-6);
    EXPECT_EQ(foam[0], std::max(0.3f, foam[1]));
    EXPECT_THROW(validate_fold_foam({.softness = 0.0}), InputError);
    // The sparse sample of a lattice time accumulates exactly what the dense J₋ does.
    std::vector<float> j_field{0.9f, 0.2f, 0.39f, -0.4f, 0.41f, 0.1f};
    const FoldSample sample = fold_sample(j_field, o);
    EXPECT_EQ(sample.vertex, (std::vector<std::uint32_t>{1, 2, 3, 5}));
    std::vector<float> dense(6, 0.05f), sparse(6, 0.05f);
    accumulate_fold_foam(j_field, 0.7, o, dense);
    accumulate_fold_foam(sample, 0.7, o, sparse);
    EXPECT_EQ(dense, sparse);
}

// A window of samples at once, over several blocks of vertices (16 384 a block): the
// same bits as one sample after another, in any order; a sample out of the window
// adds nothing; vertices that do not ascend, repeat or lie beyond the foam are refused.
TEST(FoldFoam, AWindowOfSamplesAtOnceIsOneAfterAnother) {
    const FoldFoamOptions o;
    const std::size_t n = 50000;
    std::vector<FoldSample> samples;
    std::uint32_t state = 7;
    for (int s = 0; s < 6; ++s) {
        std::vector<float> j(n);
        for (auto& v : j) v = static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) / 16777216.0f * 1.6f - 0.6f;
        samples.push_back(fold_sample(j, o));
    }
    const double ages[] = {0.1, 0.6, 1.4, 2.2, 3.9, 5.0};  // the last beyond the 4.5 s window
    std::vector<float> one_by_one(n, 0.02f), at_once(n, 0.02f), reversed(n, 0.02f);
    std::vector<AgedFoldSample> window, backwards;
    for (std::size_t s = 0; s < samples.size(); ++s) {
        accumulate_fold_foam(samples[s], ages[s], o, one_by_one);
        window.push_back({&samples[s], ages[s]});
        backwards.insert(backwards.begin(), {&samples[s], ages[s]});
    }
    accumulate_fold_foam(window, o, at_once);
    accumulate_fold_foam(backwards, o, reversed);
    EXPECT_EQ(std::memcmp(one_by_one.data(), at_once.data(), n * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(one_by_one.data(), reversed.data(), n * sizeof(float)), 0);
    EXPECT_GT(*std::max_element(at_once.begin(), at_once.end()), 0.5f);
    std::vector<float> untouched(n, 0.02f);
    accumulate_fold_foam(samples[5], ages[5], o, untouched);
    EXPECT_EQ(untouched, std::vector<float>(n, 0.02f));
    FoldSample bad = samples[0];
    std::swap(bad.vertex[10], bad.vertex[11]);  // out of order inside a block
    EXPECT_THROW(accumulate_fold_foam(bad, 0.5, o, at_once), InputError);
    bad = samples[0];
    bad.vertex[20] = bad.vertex[19];  // repeated
    EXPECT_THROW(accumulate_fold_foam(bad, 0.5, o, at_once), InputError);
    bad = samples[0];
    std::swap(bad.vertex.front(), bad.vertex.back());  // across blocks
    EXPECT_THROW(accumulate_fold_foam(bad, 0.5, o, at_once), InputError);
    bad = samples[0];
    bad.vertex.back() = static_cast<std::uint32_t>(n);  // beyond the foam
    EXPECT_THROW(accumulate_fold_foam(bad, 5.0, o, at_once), InputError);  // out of the window: still checked
    bad.j_minus.pop_back();
    EXPECT_THROW(accumulate_fold_foam(bad, 0.5, o, at_once), InputError);
}

}  // namespace

// ---------------------------------------------------------------------------------
// Scenes: the open-ocean patch and wind waves superposed on the traced swell
// ---------------------------------------------------------------------------------
#include "libwave/scene.h"

namespace {

const char* kSmallOcean = R"({"surface": {"kind": "ocean"},
  "ocean": {"resolution": 32, "size": 100, "wind_speed": 15, "repeat_time": 2, "choppiness": 4, "small_wave_cutoff": 0.2},
  "animation": {"fps": 8}})";

TEST(OceanScene, AnyFrameAloneEqualsTheSameFrameOfARun) {
    // The fold foam's fade looks back on a time lattice that the run caches; a frame
    // computed alone must get the same bits (no history).
    const Scene scene = parse_scene(kSmallOcean, "small.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const SceneAnimation all = animate_scene(scene, plan);
    ASSERT_EQ(all.frame_count, 16u);
    ASSERT_EQ(plan.model_vertices, 33u * 33u);  // the patch, then the skirt that carries it to the horizon
    ASSERT_EQ(all.vertex_count, plan.rest_x.size());
    ASSERT_GT(all.vertex_count, 33u * 33u);
    const std::size_t n = all.vertex_count;
    float foam_max = 0.0f;
    for (float f : all.foam) foam_max = std::max(foam_max, f);
    EXPECT_GT(foam_max, 0.2f) << "the test needs folds";
    for (std::size_t k : {0u, 7u, 15u}) {
        const SceneAnimation one = animate_scene(scene, plan, 2e9, {k, k + 1});
        EXPECT_EQ(std::memcmp(one.foam.data(), &all.foam[k * n], n * sizeof(float)), 0) << "frame " << k;
        EXPECT_EQ(std::memcmp(one.positions.data(), &all.positions[3 * k * n], 3 * n * sizeof(float)), 0);
    }
    // The patch tiles: the last column repeats the first one patch further.
    const std::size_t side = 33;
    for (std::size_t row = 0; row < side; ++row) {
        const float* a = &all.positions[3 * (row * side)];
        const float* b = &all.positions[3 * (row * side + side - 1)];
        EXPECT_NEAR(b[0] - a[0], 100.0f, 1e-4f);
        EXPECT_EQ(b[1], a[1]);
        EXPECT_EQ(b[2], a[2]);
    }
}

TEST(FoldFoam, WhitecapCoverageFollowsCallaghan) {
    // Callaghan, Deane & Stokes (2008): W = 3.18e-3 (U − 3.70)³ % to 9.25 m/s,
    // 4.82e-4 (U + 1.98)³ % from 11.25 m/s, blended between.
    EXPECT_EQ(whitecap_coverage(3.0), 0.0);
    EXPECT_NEAR(whitecap_coverage(8.0), 3.18e-3 * std::pow(4.3, 3.0) / 100.0, 1e-12);
    EXPECT_NEAR(whitecap_coverage(23.0), 4.82e-4 * std::pow(24.98, 3.0) / 100.0, 1e-12);  // 7.5 %
    EXPECT_NEAR(whitecap_coverage(31.0), 0.1729, 1e-4);
    for (double u = 9.0; u < 11.5; u += 0.01)  // continuous and growing across the overlap
        EXPECT_LT(whitecap_coverage(u), whitecap_coverage(u + 0.01) + 1e-12) << u;
    EXPECT_NEAR(whitecap_coverage(9.25), 3.18e-3 * std::pow(5.55, 3.0) / 100.0, 1e-12);
    EXPECT_NEAR(whitecap_coverage(11.25), 4.82e-4 * std::pow(13.23, 3.0) / 100.0, 1e-12);
    EXPECT_EQ(whitecap_coverage(200.0), 1.0);
}

TEST(FoldFoam, ThresholdForACoverageIsAnalyticOnUniformJ) {
    // J₋ uniform on [−1, 1] at one time (no history): foam >= 0.1 where
    // (T − J)/softness >= 0.1, i.e. J <= T − 0.1·softness, a share (T − 0.1 s + 1)/2.
    FoldFoamOptions o;
    const std::size_t n = 200'001;
    std::vector<std::vector<float>> past(1, std::vector<float>(n));
    for (std::size_t v = 0; v < n; ++v) past[0][v] = static_cast<float>(-1.0 + 2.0 * static_cast<double>(v) / (n - 1));
    for (double share : {0.01, 0.17, 0.5, 0.9}) {
        const double t = fold_threshold_for_coverage(past, 0.25, o, share);
        EXPECT_NEAR(t, 2.0 * share - 1.0 + 0.1 * o.softness, 1e-4) << share;
    }
    // Older samples add foam (faded): a lower threshold reaches the same share.
    past.insert(past.begin(), past[0]);
    std::reverse(past[0].begin(), past[0].end());  // another sea 0.25 s ago
    EXPECT_LT(fold_threshold_for_coverage(past, 0.25, o, 0.17), 2.0 * 0.17 - 1.0 + 0.1 * o.softness);
    EXPECT_EQ(fold_threshold_for_coverage(past, 0.25, o, 0.0), -2.0);
    // Random seas at three past times: the threshold is the smallest that reaches the
    // share, to 1e-6 (the foam of every point recomputed here from the public pieces).
    std::mt19937 rng(7);
    std::normal_distribution<float> sea(0.3f, 0.5f);
    std::vector<std::vector<float>> three(3, std::vector<float>(50'000));
    for (auto& times : three)
        for (float& j : times) j = sea(rng);
    const auto share_at = [&](double threshold) {
        FoldFoamOptions at = o;
        at.threshold = threshold;
        std::size_t count = 0;
        for (std::size_t v = 0; v < three[0].size(); ++v) {
            double foam = 0.0;
            for (std::size_t i = 0; i < 3; ++i) foam = std::max(foam, fold_coverage(three[i][v], at) * fold_fade((2.0 - double(i)) * 0.25, at));
            count += foam >= 0.1;
        }
        return static_cast<double>(count) / static_cast<double>(three[0].size());
    };
    for (double share : {0.03, 0.3}) {
        const double t = fold_threshold_for_coverage(three, 0.25, o, share);
        EXPECT_GE(share_at(t), share) << share;
        EXPECT_LT(share_at(t - 1e-6), share) << share;
    }
    EXPECT_THROW(fold_threshold_for_coverage(past, 0.25, o, 1.5), InputError);
    EXPECT_THROW(fold_threshold_for_coverage({}, 0.25, o, 0.1), InputError);
}

TEST(OceanScene, FoldFoamCoversTheWindsWhitecapShare) {
    // A 20 m/s sea: the threshold is calibrated on frame 0's history so that foam >= 0.1
    // covers whitecap_coverage(20) = 4.4 % of the sea; every frame of the loop stays near it.
    const Scene scene = parse_scene(R"({"surface": {"kind": "ocean"}, "animation": {"fps": 4},
      "ocean": {"resolution": 128, "size": 400, "wind_speed": 20, "repeat_time": 8, "choppiness": 1.5, "small_wave_cutoff": 0.5}})",
                                    "gale.json", ".");
    const ScenePlan plan = plan_scene(scene);
    EXPECT_NEAR(plan.whitecap_coverage, whitecap_coverage(20.0), 1e-15);
    EXPECT_LT(plan.fold_foam.threshold, 1.0);
    const SceneAnimation a = animate_scene(scene, plan);
    const std::size_t patch = plan.model_vertices;  // the skirt beyond fades the foam with the waves
    ASSERT_EQ(patch, 129u * 129u);
    for (std::size_t f = 0; f < a.frame_count; ++f) {
        std::size_t covered = 0;
        for (std::size_t v = 0; v < patch; ++v) covered += a.foam[f * a.vertex_count + v] >= 0.1f ? 1 : 0;
        EXPECT_NEAR(static_cast<double>(covered) / static_cast<double>(patch), plan.whitecap_coverage, 0.02)
            << "frame " << f;
    }
    // A threshold the scene gives is kept; a coverage it gives is met instead of the wind's.
    const ScenePlan fixed = plan_scene(parse_scene(R"({"surface": {"kind": "ocean"}, "shade": {"fold_threshold": 0.4},
      "ocean": {"resolution": 64, "size": 400, "wind_speed": 20}})", "fixed.json", "."));
    EXPECT_EQ(fixed.fold_foam.threshold, 0.4);
    EXPECT_EQ(fixed.whitecap_coverage, 0.0);
    const ScenePlan chosen = plan_scene(parse_scene(R"({"surface": {"kind": "ocean"}, "shade": {"whitecap_coverage": 0.3},
      "ocean": {"resolution": 64, "size": 400, "wind_speed": 20}})", "chosen.json", "."));
    EXPECT_EQ(chosen.whitecap_coverage, 0.3);
    EXPECT_GT(chosen.fold_foam.threshold, plan.fold_foam.threshold);
    EXPECT_THROW(parse_scene(R"({"surface": {"kind": "ocean"}, "shade": {"whitecap_coverage": 0.3, "fold_threshold": 0.4}})",
                             "both.json", "."),
                 InputError);
}

TEST(OceanScene, WindWavesCalmDownOverTheShelf) {
    // The bay with its swell, with and without FFT wind waves: the difference is the
    // wind sea, scaled by sqrt(φ(ω_p sqrt(h/g))) — small near the shore, full offshore.
    const std::string base = R"({"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
      "fronts": {"step": 0.8, "split_distance": 2.4}, "outputs": {"attributes": "none"})";
    const Scene calm = parse_scene(base + "}", "calm.json", ".");
    const Scene windy = parse_scene(base + R"(, "ocean": {"resolution": 64, "size": 64, "wind_speed": 6,
      "spectrum": "pierson-moskowitz", "small_wave_cutoff": 0.05, "repeat_time": 5}})", "windy.json", ".");
    const ScenePlan pc = plan_scene(calm), pw = plan_scene(windy);
    EXPECT_EQ(pw.loop_period, 5.0);
    const SceneAnimation ac = animate_scene(calm, pc, 2e9, {0, 12}), aw = animate_scene(windy, pw, 2e9, {0, 12});
    // The same water mesh; the skirts differ (the windy one holds the wind sea's band).
    ASSERT_EQ(pc.model_vertices, pw.model_vertices);
    ASSERT_GT(aw.vertex_count, ac.vertex_count);
    double shallow = 0.0, deep = 0.0, scale_shallow = 0.0, scale_deep = 0.0;
    double ns = 0, nd = 0;
    for (std::size_t f = 0; f < 12; ++f)
        for (std::size_t v = 0; v < pc.model_vertices; ++v) {
            const double dz = aw.positions[3 * (f * aw.vertex_count + v) + 2] - ac.positions[3 * (f * ac.vertex_count + v) + 2];
            const double h = pw.rest_depth[v];
            if (h < 0.3) shallow += dz * dz, scale_shallow += pw.wind_sea_scale[v] * pw.wind_sea_scale[v], ++ns;
            if (h > 2.0) deep += dz * dz, scale_deep += pw.wind_sea_scale[v] * pw.wind_sea_scale[v], ++nd;
        }
    ASSERT_GT(ns, 100.0);
    ASSERT_GT(nd, 100.0);
    const double rms_ratio = std::sqrt(shallow / ns) / std::sqrt(deep / nd);
    EXPECT_LT(rms_ratio, 0.5);
    // …in proportion to the depth factor's RMS (the field's own RMS varies by ±30 % between regions).
    EXPECT_NEAR(rms_ratio / std::sqrt((scale_shallow / ns) / (scale_deep / nd)), 1.0, 0.3);
    // A repeat time that is no multiple of the swell's 5 s cannot loop.
    const Scene bad = parse_scene(base + R"(, "ocean": {"repeat_time": 12}})", "bad.json", ".");
    try {
        plan_scene(bad);
        ADD_FAILURE() << "expected an error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/ocean/repeat_time 12 s is not a whole multiple of the swell's loop (5 s)"),
                  std::string::npos) << e.what();
    }
}

TEST(OceanScene, GerstnerOnThePatch) {
    // Gerstner waves on a calm patch: the surface is eqs. 12–13; Σ kA >= 1 is warned about.
    const Scene s = parse_scene(R"({"surface": {"kind": "ocean"}, "ocean": {"resolution": 16, "size": 40, "wind_speed": 0.5,
      "repeat_time": 4}, "gerstner": [{"wavelength": 10, "amplitude": 1.7, "direction": [1, 0]}], "animation": {"fps": 4}})",
                                "g.json", ".");
    const ScenePlan p = plan_scene(s);
    ASSERT_EQ(p.gerstner.size(), 1u);
    EXPECT_NEAR(p.gerstner[0].omega, quantize_frequency(std::sqrt(kGravity * 2 * std::numbers::pi / 10), 4.0), 1e-12);
    ASSERT_EQ(p.warnings.size(), 2u);  // V²/g = 2.5 cm under two 2.5 m cells, and kA = 1.07
    EXPECT_NE(p.warnings[1].find("Σ k A = 1.068"), std::string::npos) << p.warnings[1];
}

}  // namespace
