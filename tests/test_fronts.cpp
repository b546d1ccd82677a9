// Gonzato's adaptive fronts in gradient mode: convergence to Snell's law and to
// A∞ K_s K_r on a planar beach as the step shrinks; the bay and island scenes.
#include "libwave/errors.h"
#include "libwave/isobath.h"
#include "libwave/trace.h"
#include "planar_beach_wave.h"
#include "trace/common.h"  // white-box: the tracers' dispersion table

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <vector>

namespace {

using namespace wave;

struct Errors {
    double snell = 0.0, amplitude = 0.0;
};

// Largest relative errors, over alive points of rays that entered across the deep
// edge, of the Snell invariant sin θ / C and of the amplitude A∞ K_s √(cos θ0 / cos θ).
Errors planar_beach_errors(double step, double isobath_spacing = 0.0) {
    const Seafloor beach = make_planar_beach();  // sea to −y, 8 m at y = 0
    const double c30 = std::sqrt(3.0) / 2.0;
    const WaveTrain t{.period = 8.0, .amplitude = 0.4, .direction_x = 0.5, .direction_y = c30};
    FrontOptions o;
    o.ray_spacing = 2.0;
    o.step = step;
    o.split_distance = 1e9;  // no insertion: straight contours keep the tubes regular
    DepthContours isobaths;
    if (isobath_spacing > 0.0) {
        o.refraction = FrontRefraction::isobath;
        isobaths = extract_isobaths(beach, IsobathOptions{.levels = {}, .spacing = isobath_spacing});
    }
    const FrontSet f = trace_fronts(beach, t, o, &isobaths);
    const double invariant0 = 0.5 / linear_wave(f.omega, 8.0).celerity;
    Errors e;
    for (std::size_t i = 0; i < f.x.size(); ++i) {
        if (f.flag[i] != RayFlag::alive || f.depth[i] < 0.5 || f.x[i] < 60.0 || f.x[i] > 190.0) continue;
        // Gradient mode refracts continuously: compare with C at the point. Isobath
        // mode keeps a band's direction between isobaths: compare with C of the band,
        // the isobath crossed last — the next level at or below the point (shoreward).
        double h = f.depth[i];
        if (isobath_spacing > 0.0) {
            const double level = std::ceil(h / isobath_spacing - 1e-9) * isobath_spacing;
            if (std::abs(level - h) < 1e-6) continue;  // on an isobath: either band
            h = std::min(level, 8.0);
        }
        const LinearWave w = linear_wave(f.omega, h);
        e.snell = std::max(e.snell, std::abs(f.dir_x[i] / w.celerity / invariant0 - 1.0));
        const double expected = 0.4 * linear_wave(f.omega, f.depth[i]).shoaling * std::sqrt(c30 / f.dir_y[i]);
        if (expected < 0.5 * kBreakerIndex * f.depth[i])
            e.amplitude = std::max(e.amplitude, std::abs(f.amplitude[i] / expected - 1.0));
    }
    return e;
}

TEST(Fronts, GradientModeConvergesToSnellAndShoalingOnAPlanarBeach) {
    const Errors coarse = planar_beach_errors(0.8), mid = planar_beach_errors(0.4), fine = planar_beach_errors(0.2);
    // First order in the step: halving it halves the error (measured 2.7e-3, 1.3e-3, 6.7e-4).
    EXPECT_NEAR(mid.snell / coarse.snell, 0.5, 0.05);
    EXPECT_NEAR(fine.snell / mid.snell, 0.5, 0.05);
    EXPECT_LT(fine.snell, 1e-3);
    EXPECT_NEAR(fine.amplitude / mid.amplitude, 0.5, 0.05);
    EXPECT_LT(fine.amplitude, 5e-3);
}

TEST(Fronts, IsobathModeIsExactSnellPerBandWhateverTheStep) {
    // Exact crossings (Ts'o–Barsky): in every band the direction satisfies Snell's law
    // with the band's celerity (to the dispersion table's 1e-9), for any step length.
    for (const double step : {0.8, 0.4}) {
        const Errors e = planar_beach_errors(step, 0.25);
        EXPECT_LT(e.snell, 1e-8) << step;  // the dispersion table interpolates to ~1e-9
        // Amplitude from the spacing of rays refracted band by band: within 2 %.
        EXPECT_LT(e.amplitude, 2e-2) << step;
    }
}

TEST(Fronts, RaysEnteringAcrossTheShallowSideStartOnTheRefractedWave) {
    // The shipped breaking beach's geometry: an oblique swell enters across the deep
    // edge y = 0 and across the west side x = 0, which runs up the beach to the shore.
    // Beyond that side the seafloor is the side's own, continued west (the far field's
    // apron too): the corner's plane wave refracted by Snell. Rays entering there used to
    // start with the deep edge's direction and the plane wave's phase at the local k: up
    // to 54 rad (8 wavelengths) wrong at the shore, 0.25 off in sin θ.
    const Seafloor beach = make_planar_beach();
    const double c30 = std::sqrt(3.0) / 2.0;
    const WaveTrain t{.period = 8.0, .amplitude = 0.4, .direction_x = 0.5, .direction_y = c30};
    FrontOptions o;
    o.ray_spacing = 2.0;
    o.step = 0.2;
    o.split_distance = 3.0;  // new rays between the west side's, as in the example
    const FrontSet f = trace_fronts(beach, t, o);
    const test::BeachWave exact(beach, f.omega, 0.5);
    std::size_t west = 0;
    double worst_phase = 0.0, worst_snell = 0.0, worst_amplitude = 0.0;
    for (std::size_t i = 0; i < f.x.size(); ++i) {
        if (f.flag[i] != RayFlag::alive || f.depth[i] < 0.5 || f.x[i] > 60.0) continue;
        ++west;
        worst_phase = std::max(worst_phase, std::abs(f.phase[i] - exact.phase(f.x[i], f.y[i])));
        const LinearWave w = linear_wave(f.omega, f.depth[i]);
        worst_snell = std::max(worst_snell, std::abs(f.dir_x[i] * w.k / exact.kx - 1.0));
        const double expected = 0.4 * w.shoaling * std::sqrt(c30 / f.dir_y[i]);
        if (expected < 0.5 * kBreakerIndex * f.depth[i])
            worst_amplitude = std::max(worst_amplitude, std::abs(f.amplitude[i] / expected - 1.0));
    }
    EXPECT_GT(west, 5000u);
    // Measured: 0.035 rad; sin θ / C to 4.9e-3 (one 0.2 m step after the shallowest
    // entry, 0.5 m deep, where gradient mode's first-order error in the step is largest:
    // 1.5e-3 at 0.9 m); the amplitude to 2.7e-3.
    EXPECT_LT(worst_phase, 0.1);
    EXPECT_LT(worst_snell, 1e-2);
    EXPECT_LT(worst_amplitude, 1e-2);
    // The west side runs into the surf zone: rays entering beyond the apron's break
    // point (y = 133.9 m) entered broken, at the phase their wave had there; the others
    // did not. Measured: 7 rays, 0.002–0.009 rad from the exact phase (the walk's
    // half-metre midpoints, the break between two of them found by bisection).
    const double y_b = exact.break_y(0.4);
    std::size_t broken = 0;
    for (std::size_t i = 0; i < f.front_offsets[1]; ++i) {
        const double before = f.entry_break_phase[f.ray[i]];
        if (f.x[i] != 0.0 || f.y[i] < y_b - 0.5) {
            EXPECT_TRUE(std::isnan(before)) << f.x[i] << ", " << f.y[i];
            continue;
        }
        if (f.y[i] < y_b + 0.5) continue;  // within the walk's step of the break
        ASSERT_FALSE(std::isnan(before)) << f.y[i];
        ++broken;
        EXPECT_NEAR(before, exact.phase_back_to(y_b, f.y[i]), 0.05) << f.y[i];
        EXPECT_LT(before, f.phase[i]);
    }
    EXPECT_GT(broken, 5u);
    // Inserted rays start unbroken as far as the tracer knows.
    for (std::size_t id = f.initial_rays; id < f.entry_break_phase.size(); ++id) EXPECT_TRUE(std::isnan(f.entry_break_phase[id]));
}

// Along the planar beach's straight shore the exact wave's phase is k_x x + ∫ k_y dy to
// the shore, a line in x: the integral from the corner to the shore (depth 8 − y/20), in
// s = √h, where k_y s is smooth up to the shore: dy = −40 s ds.
double phase_to_shore(const test::BeachWave& exact, double omega) {
    double to_shore = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double s = std::sqrt(8.0) * (i + 0.5) / n, k = linear_wave(omega, s * s).k;
        to_shore += std::sqrt(k * k - exact.kx * exact.kx) * 40.0 * s * std::sqrt(8.0) / n;
    }
    return to_shore;
}

TEST(Fronts, RaysReachThePlanarBeachsShoreOnTheExactPhase) {
    // The step that reaches the shoreline used to add ½ k₀ Δs (the trapezoid rule with k
    // taken as 0 there, where it diverges as h^−½) instead of 2 k₀ Δs: the breaking
    // beach's rays landed up to 0.7 rad short, each by where its last wet vertex fell,
    // and Jeschke's lips, whose lives end at that phase, stepped from ray to ray.
    const FrontSet f = test::breaking_beach_fronts();
    const test::BeachWave exact(make_planar_beach(), f.omega, 0.34 / std::hypot(0.34, 0.94));
    const double to_shore = phase_to_shore(exact, f.omega);
    std::set<std::uint32_t> landed;
    std::size_t count = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < f.x.size(); ++i) {
        if (f.flag[i] != RayFlag::aground || !landed.insert(f.ray[i]).second) continue;  // each ray's landfall
        if (f.x[i] < 40.0 || f.x[i] > 160.0) continue;  // the rays of the deep edge
        ++count;
        worst = std::max(worst, std::abs(f.phase[i] - (exact.kx * f.x[i] + to_shore)));
    }
    EXPECT_GT(count, 20u);
    // Measured: 2.5e-4 rad (0.69 before).
    EXPECT_LT(worst, 0.01) << count << " rays";
}

TEST(Fronts, NoRayWalksAlongTheShoreWithItsPhaseFrozen) {
    // An aground ray follows the shoreline, adding no phase, while it marks the front's
    // end beside a wet neighbour. One at an end of the front beside an aground ray used
    // to walk on: a ray entering 0.22 m deep on the beach's west side followed the shore
    // for 161 m, its phase 6 rad behind the wave's. Every aground point, the whole shore
    // included, now carries the exact wave's phase to within the few steps an end ray
    // walks beside a wet neighbour.
    const FrontSet f = test::breaking_beach_fronts();
    const test::BeachWave exact(make_planar_beach(), f.omega, 0.34 / std::hypot(0.34, 0.94));
    const double to_shore = phase_to_shore(exact, f.omega);
    double worst = 0.0;
    std::size_t aground = 0;
    for (std::size_t i = 0; i < f.x.size(); ++i) {
        if (f.flag[i] != RayFlag::aground) continue;
        ++aground;
        worst = std::max(worst, std::abs(f.phase[i] - (exact.kx * f.x[i] + to_shore)));
    }
    EXPECT_GT(aground, 200u);
    // Measured: 0.28 rad, at a ray inserted on the shore by the west side (its phase the
    // mean of its neighbours'); the 161 m walk was 5.3 rad off before.
    EXPECT_LT(worst, 0.35) << aground << " aground points";
}

TEST(Fronts, IsobathModeNeedsIsobaths) {
    FrontOptions o;
    o.refraction = FrontRefraction::isobath;
    EXPECT_THROW(trace_fronts(make_planar_beach(), WaveTrain{}, o), InputError);
}

TEST(Fronts, DispersionTableMatchesTheSolver) {
    // Linear interpolation of k√h, C/√h and K_s h^{1/4} in s = √h: 1e-9-level over the range,
    // exact below the first node, above the range, and for capillary waves.
    const double omega = 2.0 * std::numbers::pi / 5.0;
    const detail::WaveTable table(omega, 12.0, DispersionOptions{});
    double worst = 0.0;
    for (double h = 1e-7; h < 20.0; h *= 1.013) {
        const LinearWave w = linear_wave(omega, h);
        const detail::WaveTable::Entry e = table.at(h);
        worst = std::max({worst, std::abs(e.k / w.k - 1.0), std::abs(e.celerity / w.celerity - 1.0),
                          std::abs(e.shoaling / w.shoaling - 1.0)});
        ASSERT_EQ(table.celerity(h), e.celerity) << h;  // the tracers' lookup of C alone
    }
    EXPECT_LT(worst, 1e-8);
    // At the nodes (one Newton step from the extrapolated root) the table is the solver's to 1e-13.
    const double ds = std::sqrt(12.0) / 4095.0;
    double at_nodes = 0.0;
    for (int i = 2; i < 4095; i += 7) {
        const double h = (i * ds) * (i * ds);
        const LinearWave w = linear_wave(omega, h);
        const detail::WaveTable::Entry e = table.at(h);
        at_nodes = std::max({at_nodes, std::abs(e.k / w.k - 1.0), std::abs(e.shoaling / w.shoaling - 1.0)});
    }
    EXPECT_LT(at_nodes, 1e-13);
    EXPECT_EQ(table.at(0.0).k, 0.0);
    EXPECT_EQ(table.at(-1.0).celerity, 0.0);
    const detail::WaveTable capillary(omega, 12.0, DispersionOptions{.capillary_length = 2.7e-3});
    EXPECT_EQ(capillary.at(3.3).k, linear_wave(omega, 3.3, DispersionOptions{.capillary_length = 2.7e-3}).k);
}

TEST(Fronts, GonzatoBayScene) {
    // The paper's set-up: 100 m bay, one ray per metre, step 0.4 m, split at 1.2 m.
    const Seafloor bay = make_gonzato_bay();
    const WaveTrain t{.period = 5.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0};
    const FrontSet f = trace_fronts(bay, t);
    EXPECT_EQ(f.initial_rays, 100u);
    // The paper reports 209 new rays and 39 097 facets for its bay; ours differs in
    // shape (the figure's bathymetry is not given), so only the order of magnitude.
    EXPECT_GT(f.inserted_rays, 50u);
    EXPECT_LT(f.inserted_rays, 400u);
    EXPECT_GT(f.rays_aground, 50u);
    for (std::size_t i = 0; i < f.x.size(); ++i) {
        ASSERT_TRUE(std::isfinite(f.x[i]) && std::isfinite(f.y[i]) && std::isfinite(f.amplitude[i]));
        EXPECT_LE(2.0 * f.amplitude[i], kBreakerIndex * std::max(f.depth[i], 0.0) + 1e-12);
    }
    // Every front is ordered and every point's flag is one that stays in the list.
    for (std::size_t i = 0; i < f.flag.size(); ++i) EXPECT_NE(f.flag[i], RayFlag::dead);
}

TEST(Fronts, IslandOrbitsAreCutAndTracingEnds) {
    const Seafloor island = make_gonzato_island();
    const WaveTrain t{.period = 5.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0};
    const FrontSet f = trace_fronts(island, t);
    EXPECT_GT(f.rays_aground, 0u);
    EXPECT_GT(f.rays_trapped, 0u);  // rays refracted into orbit round the shelf
    EXPECT_GT(f.front_count(), 100u);
}

TEST(Fronts, CausticsBehindTheBerkhoffShoalAreKeptFlaggedAndCapped) {
    // The elliptic shoal focuses rays behind it (Berkhoff's lens): rays cross, the
    // points are flagged, and the amplitude stays under the breaking limit there.
    const Seafloor shoal = make_named_seafloor("berkhoff-shoal");
    FrontOptions o;
    o.ray_spacing = 0.1;
    o.step = 0.05;
    o.split_distance = 0.2;
    const FrontSet f = trace_fronts(shoal, WaveTrain{.period = 1.0, .amplitude = 0.0232, .direction_x = 0.0, .direction_y = 1.0}, o);
    EXPECT_GT(f.caustic_points, 0u);
    std::size_t flagged = 0;
    for (std::size_t i = 0; i < f.x.size(); ++i) {
        flagged += f.caustic[i];
        ASSERT_TRUE(std::isfinite(f.amplitude[i]));
        EXPECT_LE(2.0 * f.amplitude[i], kBreakerIndex * std::max(f.depth[i], 0.0) + 1e-12);
    }
    EXPECT_EQ(flagged, f.caustic_points);
    // Straight parallel contours focus nothing.
    const FrontSet beach = trace_fronts(make_planar_beach(), WaveTrain{.period = 8.0, .amplitude = 0.4}, FrontOptions{.ray_spacing = 2.0, .step = 0.8});
    EXPECT_EQ(beach.caustic_points, 0u);
}

TEST(Fronts, BadOptions) {
    const Seafloor bay = make_gonzato_bay();
    const WaveTrain t{};
    FrontOptions o;
    o.step = 0.0;
    EXPECT_THROW(trace_fronts(bay, t, o), InputError);
    o = {};
    o.max_steps = 10;
    EXPECT_THROW(trace_fronts(bay, t, o), LimitError);
    o = {};
    o.max_rays = 120;
    EXPECT_THROW(trace_fronts(bay, t, o), LimitError);
    EXPECT_THROW(trace_fronts(bay, WaveTrain{.period = -1.0}, FrontOptions{}), InputError);
}

}  // namespace
