// The refraction–diffraction field against analytic solutions: a plane wave on a flat
// bottom, a planar beach (shoaling and refraction, and the rays' phase), diffraction
// behind a semi-infinite breakwater (Sommerfeld's half-plane, Penney & Price 1952).
#include "grid_seafloor.h"
#include "libwave/errors.h"
#include "libwave/field.h"
#include "libwave/physics.h"
#include "libwave/surface.h"
#include "libwave/trace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <functional>
#include <numbers>
#include <vector>

namespace {

using namespace wave;
using cd = std::complex<double>;

using test::grid_seafloor;

// The wrapped difference of two phases, in (−π, π].
double phase_gap(double a, double b) { return std::remainder(a - b, 2.0 * std::numbers::pi); }

TEST(WaveField, FlatBottomCarriesAPlaneWaveUnchanged) {
    // 10 m of water, T = 4 s (L = 23.5 m), travelling at 30° to x over 10+ wavelengths.
    const Seafloor flat = grid_seafloor(400.0, 400.0, 5.0, [](double, double) { return 10.0; });
    const WaveTrain train{.period = 4.0, .amplitude = 0.2, .direction_x = std::cos(std::numbers::pi / 6), .direction_y = std::sin(std::numbers::pi / 6)};
    const WaveField f = solve_wave_field(flat, train);
    const LinearWave w = linear_wave(2.0 * std::numbers::pi / train.period, 10.0);
    const double expected = train.amplitude * w.shoaling;
    const double x0 = 100.0, y0 = 120.0;
    const FieldSample s0 = sample_wave_field(f, x0, y0);
    ASSERT_TRUE(s0.wet);
    double worst_phase = 0.0, worst_amp = 0.0;
    for (double d = 0.0; d <= 10.0 * w.wavelength; d += 0.37 * w.wavelength) {
        const double x = x0 + d * train.direction_x, y = y0 + d * train.direction_y;
        const FieldSample s = sample_wave_field(f, x, y);
        ASSERT_TRUE(s.wet) << d;
        worst_amp = std::max(worst_amp, std::abs(std::abs(s.eta) / expected - 1.0));
        worst_phase = std::max(worst_phase, std::abs(phase_gap(std::arg(s.eta) - std::arg(s0.eta), w.k * d)));
        EXPECT_NEAR(s.dir_x, train.direction_x, 1e-3);
        EXPECT_NEAR(s.dir_y, train.direction_y, 1e-3);
    }
    EXPECT_LT(worst_amp, 0.005);                     // amplitude within 0.5 %
    EXPECT_LT(worst_phase / (2.0 * std::numbers::pi), 0.01);      // phase within 1 % of a wavelength over 10
}

TEST(WaveField, APointOnTheGridsEdgeByARoundingErrorIsOnIt) {
    // The swell's grid is rotated to cover the domain, whose corners it just touches; a
    // corner computed another way can land 1e-16 m outside it. Such a point samples the
    // wave of the edge (one random seafloor's corner took none and stood still while the
    // water round it moved 1 m); a point a hundredth of a cell outside stays dry.
    const Seafloor flat = grid_seafloor(400.0, 400.0, 5.0, [](double, double) { return 10.0; });
    const WaveTrain train{.period = 4.0, .amplitude = 0.2, .direction_x = std::cos(std::numbers::pi / 6), .direction_y = std::sin(std::numbers::pi / 6)};
    const WaveField f = solve_wave_field(flat, train);
    const FieldSample corner = sample_wave_field(f, f.x0, f.y0);
    ASSERT_TRUE(corner.wet);
    for (const double out : {1e-12, 1e-10 * f.dx}) {  // back along the swell: s < 0 by out / dx
        const FieldSample s = sample_wave_field(f, f.x0 - out * f.ux, f.y0 - out * f.uy);
        ASSERT_TRUE(s.wet) << out;
        EXPECT_NEAR(std::abs(s.eta - corner.eta), 0.0, 1e-9) << out;
    }
    EXPECT_FALSE(sample_wave_field(f, f.x0 - 0.01 * f.dx * f.ux, f.y0 - 0.01 * f.dx * f.uy).wet);
}

TEST(WaveField, PlanarBeachShoalsAndRefractsLikeSnellAndTheRays) {
    // Straight parallel contours (depth falls towards +y), 15 m (nearly deep for T = 4 s)
    // to 1 m at a 1:20 slope, the swell at 30° to the shore normal.
    const double slope = 0.05, h0 = 15.0;
    const auto depth = [&](double, double y) { return h0 - slope * y; };
    const Seafloor beach = grid_seafloor(700.0, 290.0, 5.0, depth);
    const double theta0 = std::numbers::pi / 6;
    const WaveTrain train{.period = 4.0, .amplitude = 0.1, .direction_x = std::sin(theta0), .direction_y = std::cos(theta0)};
    FieldOptions o;
    o.min_resolved_depth = 1.0;
    o.nodes_per_wavelength = 16.0;
    const WaveField f = solve_wave_field(beach, train, o);
    const double omega = 2.0 * std::numbers::pi / train.period;
    const LinearWave deep = linear_wave(omega, 1e6);
    // Snell from deep water: sin θ / C = sin θ∞ / C∞; the wave entered at 15 m along θ∞.
    const double ky = deep.k * std::sin(theta0);
    const double x = 350.0;
    double worst_amp = 0.0, worst_phase = 0.0, phase_field0 = 0.0, phase_ray = 0.0;
    double y_prev = 0.0;
    bool first = true;
    for (double y = 30.0; y <= 250.0; y += 5.0) {  // 13.5 m to 2.5 m
        const LinearWave w = linear_wave(omega, depth(x, y));
        const double sin_t = ky / w.k, cos_t = std::sqrt(1.0 - sin_t * sin_t);
        const double expected = train.amplitude * w.shoaling * std::sqrt(std::cos(theta0) / cos_t);
        const FieldSample s = sample_wave_field(f, x, y);
        ASSERT_TRUE(s.wet);
        worst_amp = std::max(worst_amp, std::abs(std::abs(s.eta) / expected - 1.0));
        // The ray phase: ∫ k cos θ dy along y at fixed x (k_x = k sin θ is constant).
        if (first) {
            phase_field0 = std::arg(s.eta);
            first = false;
        } else {
            const LinearWave wm = linear_wave(omega, depth(x, 0.5 * (y + y_prev)));
            const double sm = ky / wm.k;
            phase_ray += wm.k * std::sqrt(1.0 - sm * sm) * (y - y_prev);
            worst_phase = std::max(worst_phase, std::abs(phase_gap(std::arg(s.eta) - phase_field0, phase_ray)));
        }
        y_prev = y;
        EXPECT_NEAR(std::atan2(s.dir_x, s.dir_y), std::asin(sin_t), 0.02) << "direction at y = " << y;
    }
    EXPECT_LT(worst_amp, 0.01) << "amplitude against A∞ K_s K_r";
    EXPECT_LT(worst_phase / (2.0 * std::numbers::pi), 0.05) << "phase against the ray's ∫ k·ds (over ~25 wavelengths)";
}

// Sommerfeld's solution for a rigid half-plane (the screen along θ = 0, tip at the
// origin) lit by exp(−i k r cos(θ − θ0)), e^{−iωt} convention:
// φ = Σ± F(−√(2kr) cos((θ ∓ θ0)/2)) exp(−i k r cos(θ ∓ θ0)),
// F(a) = e^{−iπ/4}/√π ∫_a^∞ e^{iμ²} dμ.
cd fresnel_f(double a) {
    // ∫_a^∞ e^{iμ²} dμ = (√π/2) e^{iπ/4} − ∫_0^a e^{iμ²} dμ (Simpson, 2000 steps per unit).
    const int n = 2 * std::max(1, static_cast<int>(std::ceil(std::abs(a) * 1000.0)));
    const double h = a / n;
    cd sum = 1.0 + std::exp(cd(0.0, a * a));
    for (int i = 1; i < n; ++i) {
        const double m = i * h;
        sum += (i % 2 ? 4.0 : 2.0) * std::exp(cd(0.0, m * m));
    }
    const cd from0 = sum * h / 3.0;
    const cd tail = std::sqrt(std::numbers::pi) / 2.0 * std::exp(cd(0.0, std::numbers::pi / 4)) - from0;
    return std::exp(cd(0.0, -std::numbers::pi / 4)) / std::sqrt(std::numbers::pi) * tail;
}

cd sommerfeld(double k, double r, double theta, double theta0) {
    const double s = std::sqrt(2.0 * k * r);
    return fresnel_f(-s * std::cos(0.5 * (theta - theta0))) * std::exp(cd(0.0, -k * r * std::cos(theta - theta0))) +
           fresnel_f(-s * std::cos(0.5 * (theta + theta0))) * std::exp(cd(0.0, -k * r * std::cos(theta + theta0)));
}

TEST(WaveField, DiffractionBehindASemiInfiniteBreakwater) {
    // 5 m of water, T = 3 s (L = 12.2 m), waves along +x; a breakwater 2 m thick along
    // x = 100 m from y = 0 to its tip at y = 200 m.
    const double h = 5.0, tip_x = 101.0, tip_y = 200.0;
    const Seafloor basin = grid_seafloor(400.0, 400.0, 1.0, [&](double x, double y) {
        return x >= 100.0 && x <= 102.0 && y <= tip_y ? -1.0 : h;
    });
    const WaveTrain train{.period = 3.0, .amplitude = 0.1, .direction_x = 1.0, .direction_y = 0.0};
    FieldOptions o;
    o.nodes_per_wavelength = 16.0;
    const WaveField f = solve_wave_field(basin, train, o);
    const LinearWave w = linear_wave(2.0 * std::numbers::pi / train.period, h);
    const double a_inc = train.amplitude * w.shoaling;
    // Sanity of the reference solution: lit far from the boundary ≈ 1, deep shadow ≈ 0.
    // Map: screen along y < tip (x = tip_x) → standard frame x' = tip_y − y, y' = x − tip_x;
    // the incident wave travels +x = +y', i.e. θ0 = −π/2.
    const auto exact = [&](double x, double y) {
        const double xp = tip_y - y, yp = x - tip_x;
        double theta = std::atan2(yp, xp);
        if (theta < 0.0) theta += 2.0 * std::numbers::pi;
        return std::abs(sommerfeld(w.k, std::hypot(xp, yp), theta, 1.5 * std::numbers::pi));
    };
    ASSERT_NEAR(exact(tip_x + 60.0, tip_y + 120.0), 1.0, 0.1);
    ASSERT_LT(exact(tip_x + 60.0, tip_y - 120.0), 0.1);
    // Transect 10 wavelengths behind, from deep in the shadow to the lit zone.
    const double x = tip_x + 10.0 * w.wavelength;
    double worst = 0.0, worst_y = 0.0;
    std::size_t shadow = 0, lit = 0;
    for (double y = tip_y - 50.0; y <= tip_y + 50.0; y += 2.5) {
        const FieldSample s = sample_wave_field(f, x, y);
        ASSERT_TRUE(s.wet);
        const double model = std::abs(s.eta) / a_inc, ref = exact(x, y);
        if (std::abs(model - ref) > worst) worst = std::abs(model - ref), worst_y = y;
        shadow += y < tip_y;
        lit += y > tip_y;
    }
    EXPECT_GT(shadow, 10u);
    EXPECT_GT(lit, 10u);
    EXPECT_LT(worst, 0.05) << "H/H0 against Sommerfeld's half-plane, worst at y = " << worst_y;
}

TEST(WaveField, RefusesBadOptionsAndBoundsItsGrid) {
    const Seafloor flat = grid_seafloor(100.0, 100.0, 5.0, [](double, double) { return 10.0; });
    const WaveTrain train{.period = 4.0, .amplitude = 0.2, .direction_x = 1.0, .direction_y = 0.0};
    FieldOptions o;
    o.nodes_per_wavelength = 1.0;
    EXPECT_THROW(solve_wave_field(flat, train, o), InputError);
    o = {};
    o.max_nodes = 100;
    EXPECT_THROW(solve_wave_field(flat, train, o), LimitError);
    const Seafloor land = grid_seafloor(100.0, 100.0, 5.0, [](double, double) { return -1.0; });
    EXPECT_THROW(solve_wave_field(land, train), InputError);
}

TEST(WaveField, BreakingLimitsTheHeightToGammaH) {
    // A 1:30 beach to the shore: the height never exceeds γh, and the surf zone is flagged.
    const Seafloor beach = grid_seafloor(200.0, 300.0, 2.0, [](double, double y) { return 9.0 - y / 30.0; });
    const WaveTrain train{.period = 6.0, .amplitude = 0.5, .direction_x = 0.0, .direction_y = 1.0};
    const WaveField f = solve_wave_field(beach, train);
    EXPECT_GT(f.broken_nodes, 0u);
    for (double y = 0.0; y < 270.0; y += 3.0) {
        const FieldSample s = sample_wave_field(f, 100.0, y);
        const double h = 9.0 - y / 30.0;
        EXPECT_LE(2.0 * std::abs(s.eta), 0.78 * h * 1.02 + 1e-9) << y;
    }
}

TEST(WaveField, AgroundRaysKeepNoAmplitude) {
    // Rays that reach the shore of a 1:30 beach stand on h = 0 give or take rounding
    // (about half of them a hair on the wet side): none takes the field's amplitude.
    const Seafloor beach = grid_seafloor(200.0, 300.0, 2.0, [](double x, double y) { return 9.0 - y / 30.0 + 0.3 * std::sin(x / 7.0); });
    const WaveTrain train{.period = 6.0, .amplitude = 0.5, .direction_x = 0.3, .direction_y = 1.0};
    FrontSet fronts = trace_fronts(beach, train);
    const WaveField f = solve_wave_field(beach, train);
    std::size_t aground = 0, wet_side = 0;
    for (std::size_t i = 0; i < fronts.x.size(); ++i)
        if (fronts.flag[i] == RayFlag::aground) {
            ++aground;
            wet_side += fronts.depth[i] > 0.0;
        }
    ASSERT_GT(wet_side, 0u) << "no aground point on the wet side of h = 0: the case tests nothing";
    EXPECT_GT(take_field_amplitudes(f, fronts), fronts.x.size() / 2);
    for (std::size_t i = 0; i < fronts.x.size(); ++i)
        if (fronts.flag[i] == RayFlag::aground) {
            EXPECT_EQ(fronts.amplitude[i], 0.0) << i << " depth " << fronts.depth[i];
        }
    EXPECT_GT(aground, 0u);
}

// Strips resampled on a water mesh over 10 m of water, carrying a plane wave along +x
// (T = 4 s, L = 23.5 m) — except where a second layer of rays took over (x > 100 m,
// y > 100 m: the same wave half a period behind, as where rays that wrapped round an
// island lie over rays that did not) and along the downwave side (x > 180 m: no ray
// reached it).
struct TornStrips {
    Seafloor flat = grid_seafloor(200.0, 200.0, 5.0, [](double, double) { return 10.0; });
    WaveTrain train{.period = 4.0, .amplitude = 0.2, .direction_x = 1.0, .direction_y = 0.0};
    LinearWave wave = linear_wave(2.0 * std::numbers::pi / 4.0, 10.0);
    RayStrips strips;
    TornStrips() {
        const WaterMesh m = mesh_water(flat, [&](double, double) { return wave.wavelength / 12.0; });
        strips.x = m.x, strips.y = m.y, strips.triangles = m.triangles, strips.omega = wave.omega;
        const std::size_t n = m.x.size();
        for (auto* f : {&strips.phase, &strips.k, &strips.amplitude, &strips.depth, &strips.slope, &strips.rise, &strips.dir_y})
            f->assign(n, 0.0);
        strips.dir_x.assign(n, 1.0);
        strips.ray.assign(n, 0), strips.step.assign(n, 0), strips.caustic.assign(n, 0), strips.flag.assign(n, RayFlag::alive);
        for (std::size_t v = 0; v < n; ++v) {
            strips.depth[v] = 10.0;
            if (m.x[v] > 180.0) continue;  // a gap
            strips.k[v] = wave.k;
            strips.amplitude[v] = train.amplitude * wave.shoaling;  // as the field's
            strips.phase[v] = wave.k * m.x[v] + (second_layer(v) ? std::numbers::pi : 0.0);
        }
    }
    bool second_layer(std::size_t v) const { return strips.x[v] > 100.0 && strips.y[v] > 100.0; }
    // From a point to the second layer's edges (x = 100 m above y = 100 m, y = 100 m right of x = 100 m).
    static double distance_to_tear(double x, double y) {
        if (x > 100.0 && y > 100.0) return std::min(x - 100.0, y - 100.0);
        return std::hypot(std::max(100.0 - x, 0.0), std::max(100.0 - y, 0.0));
    }
    // The largest phase step along an edge beyond what the wave itself makes (rad).
    double worst_step(const RayStrips& s) const {
        double worst = 0.0;
        for (std::size_t t = 0; t < s.triangles.size(); t += 3)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t a = s.triangles[t + c], b = s.triangles[t + (c + 1) % 3];
                const double along = s.k[a] * (s.x[b] - s.x[a]);  // the wave's own step along x
                worst = std::max(worst, std::abs(phase_gap(s.phase[b] - s.phase[a], along)));
            }
        return worst;
    }
};

TEST(FillStripGaps, BridgesATearBetweenLayersOfRaysAndTheGapsBeyondThem) {
    TornStrips c;
    const WaveField f = solve_wave_field(c.flat, c.train);
    RayStrips s = c.strips;
    const double before = c.worst_step(s);
    EXPECT_GT(before, 3.0);  // the tear: half a wave between neighbours
    const std::size_t filled = fill_strip_gaps(f, c.flat, s);
    EXPECT_GT(filled, 0u);
    // Every edge steps by at most 0.35 rad more than the wave (a ninth of the tear; 0.31
    // measured, where the tear turns a corner), the gap's edges included: the offset
    // changes over the band, a wavelength each side.
    EXPECT_LT(c.worst_step(s), 0.35);
    std::size_t kept = 0, bridged = 0;
    for (std::size_t v = 0; v < s.x.size(); ++v) {
        EXPECT_GT(s.k[v], 0.0) << "still water left at " << s.x[v] << ", " << s.y[v];
        EXPECT_NEAR(s.k[v], c.wave.k, 1e-9);
        EXPECT_NEAR(s.dir_x[v], 1.0, 1e-3);
        EXPECT_NEAR(s.amplitude[v], c.train.amplitude * c.wave.shoaling, 0.03 * c.train.amplitude);
        // Off the band (a wavelength from the tear, and an edge for the tear's own ends)
        // and off the gap, the rays' own wave.
        const double from_tear = c.distance_to_tear(s.x[v], s.y[v]);
        if (from_tear > 1.2 * c.wave.wavelength && s.x[v] <= 180.0) {
            EXPECT_EQ(s.phase[v], c.strips.phase[v]) << s.x[v] << ", " << s.y[v];
            ++kept;
        } else if (from_tear < 0.25 * c.wave.wavelength && s.phase[v] != c.strips.phase[v]) {
            ++bridged;
        }
    }
    EXPECT_GT(kept, s.x.size() / 2);
    EXPECT_GT(bridged, 10u);
}

TEST(FillStripGaps, LeavesUnbrokenStripsAndDryPointsAlone) {
    TornStrips c;
    for (std::size_t v = 0; v < c.strips.x.size(); ++v)
        if (c.second_layer(v)) c.strips.phase[v] -= std::numbers::pi;  // one layer, no tear
    for (std::size_t v = 0; v < c.strips.x.size(); ++v)
        if (c.strips.x[v] > 180.0) c.strips.depth[v] = 0.0;  // the gap is land now
    const WaveField f = solve_wave_field(c.flat, c.train);
    RayStrips s = c.strips;
    EXPECT_EQ(fill_strip_gaps(f, c.flat, s), 0u);
    EXPECT_EQ(s.phase, c.strips.phase);
    EXPECT_EQ(s.k, c.strips.k);
}

}  // namespace
