// Gonzato's profile (eq. 7): Gerstner in deep water, the trough where eq. 5 puts it,
// the disc limit, continuity round the orbit, negative slopes, and plunging lips on
// the bay's ray strips.
#include "libwave/errors.h"
#include "libwave/motion.h"
#include "libwave/shade.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <string>
#include <numbers>

namespace {

using namespace wave;
constexpr double pi = std::numbers::pi;

TEST(GonzatoProfile, DeepWaterIsGerstnersTrochoid) {
    // h = 400 m: S_x = S_z = 1 to 1e-15, no tilt, stretch and displacement e^{−160}.
    const double R = 0.5, k = 0.1;
    const ProfileShape s = gonzato_shape(R, k, 400.0, 0.05, GonzatoProfileOptions{});
    for (double phi = -3.0; phi <= 3.0; phi += 0.25) {
        const ProfileOffset d = gonzato_offset(s, phi);
        // Eq. 1 with Kx0 − ωt = φ − π: x − x0 = R sin φ, z = −R cos φ.
        EXPECT_NEAR(d.forward, R * std::sin(phi), 1e-12) << phi;
        EXPECT_NEAR(d.up, -R * std::cos(phi), 1e-12) << phi;
    }
}

TEST(GonzatoProfile, TroughPhaseIsTheLowestPointOfTheTiltedEllipse) {
    GonzatoProfileOptions o;
    o.stretch_max = 0.0;  // the ellipse alone
    o.displacement_depth_factor = 50.0;
    const ProfileShape s = gonzato_shape(0.3, 0.5, 2.0, 0.2, o);
    ASSERT_GT(s.tilt_sin, 0.0);
    EXPECT_NEAR(s.tilt_sin, std::sin(std::atan(0.2)) * std::exp(-0.2), 1e-15);
    EXPECT_NEAR(s.tilt_cos * s.tilt_cos + s.tilt_sin * s.tilt_sin, 1.0, 1e-15);  // τ' = √(1 − τ²), the misprint fixed
    const double z_min = gonzato_offset(s, s.trough_phase).up;
    for (double phi = -pi; phi < pi; phi += 0.01) EXPECT_GE(gonzato_offset(s, phi).up, z_min - 1e-12) << phi;
    EXPECT_LT(s.trough_phase, 0.0);  // the tilted major axis lifts the front: the trough moves back
}

TEST(GonzatoProfile, MajorAxisLimitedToTheDisc) {
    // h = 0.5 m: S_x ≈ 18.7, so R S_x would leave the disc of radius 1/k.
    const double R = 0.19, k = 1.2;
    GonzatoProfileOptions o;
    const ProfileShape limited = gonzato_shape(R, k, 0.5, 0.05, o);
    EXPECT_DOUBLE_EQ(limited.major, 1.0 / k);
    o.limit_to_disc = false;
    const ProfileShape free = gonzato_shape(R, k, 0.5, 0.05, o);
    EXPECT_NEAR(free.major, R / (1.0 - std::exp(-0.055)), 1e-12);
    EXPECT_NEAR(free.minor, free.major * (1.0 - std::exp(-0.045)), 1e-12);
}

TEST(GonzatoProfile, TheAxisConstantsNeverRaiseTheWave) {
    // K_x = 1e-3 /m (in the schema's range) against the default K_z: S_z = S_x (1 − e^{−K_z h})
    // was 59 at 10 m, and a 0.3 m swell rose ±5.55 m (to the disc 1/k). S_z ≤ 1: the
    // vertical semi-axis is at most R, and the crest within the profile's 2R of height.
    const double R = 0.3, k = 2.0 * pi / 39.0;
    for (const double kx : {1e-3, 1e-6, 0.11}) {
        for (const double h : {0.5, 2.0, 10.0, 100.0}) {
            GonzatoProfileOptions o;
            o.kx = kx;
            const ProfileShape s = gonzato_shape(R, k, h, 0.05, o);
            EXPECT_LE(s.minor, R) << kx << " " << h;
            double z_min = 1e9, z_max = -1e9;
            for (double phi = -pi; phi < pi; phi += 0.01) {
                z_min = std::min(z_min, gonzato_offset(s, phi).up);
                z_max = std::max(z_max, gonzato_offset(s, phi).up);
            }
            EXPECT_LT(z_max - z_min, 4.0 * R) << kx << " " << h;
        }
    }
    // The defaults flatten the orbit towards the shore as before (K_z < K_x).
    const ProfileShape s = gonzato_shape(R, k, 2.0, 0.05, GonzatoProfileOptions{});
    EXPECT_NEAR(s.minor, R * (1.0 - std::exp(-0.18)) / (1.0 - std::exp(-0.22)), 1e-12);
}

TEST(GonzatoProfile, ContinuousRoundTheOrbitAndPeriodic) {
    const ProfileShape s = gonzato_shape(0.4, 0.6, 1.2, 0.08, GonzatoProfileOptions{});
    ASSERT_GT(s.displacement, 0.0);
    ASSERT_GT(s.stretch, 0.0);
    // Piecewise-linear Orientation/Displacement and the parabolic stretch meet at
    // Φ_min ± π, −π/3, 7π/8: no jump larger than the sampling step allows.
    double max_jump = 0.0;
    ProfileOffset prev = gonzato_offset(s, s.trough_phase - pi);
    for (int i = 1; i <= 20000; ++i) {
        const ProfileOffset d = gonzato_offset(s, s.trough_phase - pi + 2.0 * pi * i / 20000.0);
        max_jump = std::max(max_jump, std::hypot(d.forward - prev.forward, d.up - prev.up));
        prev = d;
    }
    EXPECT_LT(max_jump, 2e-3);
    const ProfileOffset a = gonzato_offset(s, 0.7), b = gonzato_offset(s, 0.7 + 6.0 * pi);
    EXPECT_NEAR(a.forward, b.forward, 1e-12);
    EXPECT_NEAR(a.up, b.up, 1e-12);
}

TEST(GonzatoProfile, NegativeSlopeIsClampedAndDryPointsStayPut) {
    const ProfileShape down = gonzato_shape(0.3, 0.5, 2.0, -0.3, GonzatoProfileOptions{});
    EXPECT_EQ(down.tilt_sin, 0.0);  // §2.4: no backward tilt
    EXPECT_EQ(down.bottom_angle, 0.0);
    const ProfileShape dry = gonzato_shape(0.3, 0.5, 0.0, 0.1, GonzatoProfileOptions{});
    const ProfileOffset d = gonzato_offset(dry, 1.0);
    EXPECT_EQ(d.forward, 0.0);
    EXPECT_EQ(d.up, 0.0);
}

TEST(GonzatoProfile, CrestPlungesForwardNearTheShore) {
    // Eq. 7 as drawn (min_packing 0), near breaking (h = 1 m, H = 0.7 m): the crest is
    // pushed ahead of its own base, so the section x(φ) is not monotone — an overhang.
    GonzatoProfileOptions eq7;
    eq7.min_packing = 0.0;
    const ProfileShape s = gonzato_shape(0.35, 0.42, 1.0, 0.1, eq7);
    bool overhang = false;
    const double k = 0.42;
    double previous_x = -1e9;
    for (int i = 0; i <= 4000; ++i) {
        const double x0 = -pi / k + 2.0 * pi / k * i / 4000.0;
        const double x = x0 + gonzato_offset(s, k * x0 + s.trough_phase).forward;
        if (x < previous_x) overhang = true;
        previous_x = x;
    }
    EXPECT_TRUE(overhang);
    // Offshore (h = 15 m) the same wave has no overhang.
    const ProfileShape deep = gonzato_shape(0.35, 0.17, 15.0, 0.1, eq7);
    previous_x = -1e9;
    for (int i = 0; i <= 4000; ++i) {
        const double x0 = -pi / 0.17 + 2.0 * pi / 0.17 * i / 4000.0;
        const double x = x0 + gonzato_offset(deep, 0.17 * x0 + deep.trough_phase).forward;
        EXPECT_GT(x, previous_x) << i;
        previous_x = x;
    }
}

// A point's speed over its phase speed: k |dO/dφ| (it runs through the phase at ω, the
// crest at ω/k), by chords over 40 000 steps of one period.
double fastest_over_phase_speed(const ProfileShape& s, double k) {
    double fastest = 0.0;
    const int steps = 40000;
    const double step = 2.0 * pi / steps;
    ProfileOffset prev = gonzato_offset(s, s.trough_phase - pi);
    for (int i = 1; i <= steps; ++i) {
        const ProfileOffset d = gonzato_offset(s, s.trough_phase - pi + step * i - (i == steps ? 1e-9 : 0.0));
        fastest = std::max(fastest, k * std::hypot(d.forward - prev.forward, d.up - prev.up) / step);
        prev = d;
    }
    return fastest;
}

// The test swell (T = 5 s) at each of `depths`, at four amplitudes and three bottom
// slopes, with its wavenumber there: visit(h, R, rise, k).
template <class Visit>
void for_each_shoaling_swell(std::initializer_list<double> depths, Visit&& visit) {
    const double omega = 2.0 * pi / 5.0;
    for (double h : depths)
        for (double R : {0.05, 0.1, 0.2, 0.3})
            for (double rise : {0.0, 0.05, 0.33}) {
                double k = omega / std::sqrt(9.81 * h);
                for (int i = 0; i < 60; ++i) k = omega * omega / (9.81 * std::tanh(k * h));
                visit(h, R, rise, k);
            }
}

TEST(GonzatoProfile, NoPointOutrunsOneAndAHalfTimesThePhaseSpeed) {
    // Swell of T = 5 s from 2 m of water to the swash, on slopes up to 1:3: in the
    // shallowest water the displacement's rise over the rear face threw crest points
    // forward at up to ~3 × the phase speed.
    GonzatoProfileOptions bounded, unbounded;
    bounded.min_packing = unbounded.min_packing = 0.0;  // the speed bound alone (eq. 7's sections)
    unbounded.max_speed_ratio = 0.0;
    double worst_unbounded = 0.0;
    int scaled = 0, kept = 0;
    for_each_shoaling_swell({0.03, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0}, [&](double h, double R, double rise, double k) {
        const ProfileShape b = gonzato_shape(R, k, h, rise, bounded), u = gonzato_shape(R, k, h, rise, unbounded);
        const double fast_b = fastest_over_phase_speed(b, k), fast_u = fastest_over_phase_speed(u, k);
        worst_unbounded = std::max(worst_unbounded, fast_u);
        EXPECT_LE(fast_b, 1.5 * 1.001) << "h " << h << " R " << R << " rise " << rise;
        if (fast_u <= 1.5) {  // slow enough already: eq. 7 as it is
            EXPECT_EQ(b.displacement, u.displacement);
            EXPECT_EQ(b.stretch, u.stretch);
            ++kept;
        } else {  // scaled by the largest share within the bound: it reaches it
            EXPECT_GT(fast_b, 1.5 * 0.999) << "h " << h << " R " << R << " rise " << rise;
            EXPECT_NEAR(b.stretch / u.stretch, b.displacement / u.displacement, 1e-12);
            ++scaled;
        }
    });
    EXPECT_GT(worst_unbounded, 2.5);
    EXPECT_GT(scaled, 10);
    EXPECT_GT(kept, 40);
}

// The section per unit of rest length over 40 000 steps of one period: the smallest
// |d(x, z)/dx₀| (x = x₀ + forward, z = up; x₀ = φ/k), and the most negative dx/dx₀.
struct Packing {
    double least = 1e9, least_dx = 1e9;
};
Packing section_packing(const ProfileShape& s, double k) {
    Packing p;
    const int steps = 40000;
    const double step = 2.0 * pi / steps;
    ProfileOffset prev = gonzato_offset(s, s.trough_phase - pi);
    for (int i = 1; i <= steps; ++i) {
        const ProfileOffset d = gonzato_offset(s, s.trough_phase - pi + step * i - (i == steps ? 1e-9 : 0.0));
        const double dx = 1.0 + k * (d.forward - prev.forward) / step, dz = k * (d.up - prev.up) / step;
        p.least = std::min(p.least, std::hypot(dx, dz));
        p.least_dx = std::min(p.least_dx, dx);
        prev = d;
    }
    return p;
}

TEST(GonzatoProfile, MinPackingKeepsEveryRestSpacingAndEveryHeight) {
    // The same swell, depths and slopes as the speed bound's test. Eq. 7 packs the mesh's
    // rest spacing along the ray down to a few percent near breaking and folds; with the
    // default min_packing (0.6) no spacing is packed below 0.6, nothing folds, and only
    // the offset along the ray is scaled (by the share the plan reports): every height
    // and the speed bound stay.
    GonzatoProfileOptions bounded, eq7;
    eq7.min_packing = 0.0;
    ASSERT_EQ(bounded.min_packing, 0.6);
    double tightest_eq7 = 1e9;
    int scaled = 0, kept = 0;
    for_each_shoaling_swell({0.03, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 6.0}, [&](double h, double R, double rise, double k) {
        const ProfileShape b = gonzato_shape(R, k, h, rise, bounded), e = gonzato_shape(R, k, h, rise, eq7);
        const Packing pb = section_packing(b, k), pe = section_packing(e, k);
        tightest_eq7 = std::min(tightest_eq7, pe.least);
        const std::string where = "h " + std::to_string(h) + " R " + std::to_string(R) + " rise " + std::to_string(rise);
        EXPECT_GE(pb.least, 0.6 * 0.999) << where;
        EXPECT_GT(pb.least_dx, 0.0) << where;  // no fold
        EXPECT_LE(fastest_over_phase_speed(b, k), 1.5 * 1.001) << where;
        ASSERT_GE(b.forward_scale, 0.0);
        ASSERT_LE(b.forward_scale, 1.0);
        for (double phi = -pi; phi < pi; phi += 0.1) {
            const ProfileOffset ob = gonzato_offset(b, phi), oe = gonzato_offset(e, phi);
            EXPECT_EQ(ob.up, oe.up) << where;
            EXPECT_NEAR(ob.forward, b.forward_scale * oe.forward, 1e-12) << where;
        }
        if (pe.least >= 0.6) {  // eq. 7 packs no tighter: left as it is
            EXPECT_EQ(b.forward_scale, 1.0) << where;
            ++kept;
        } else {  // scaled by the largest share within the bound: it reaches it
            EXPECT_LT(pb.least, 0.6 * 1.02) << where;
            ++scaled;
        }
    });
    EXPECT_LT(tightest_eq7, 0.1);  // the witness: eq. 7 alone packs tighter than a tenth
    EXPECT_GT(scaled, 20);
    EXPECT_GT(kept, 10);
    GonzatoProfileOptions bad;
    bad.min_packing = 1.0;
    EXPECT_THROW(plan_gonzato_motion(RayStrips{}, bad), InputError);
    bad.min_packing = -0.1;
    EXPECT_THROW(plan_gonzato_motion(RayStrips{}, bad), InputError);
}

TEST(GonzatoMotion, BayStripsHaveDownwardFacingLipsAtSomeFrame) {
    // Eq. 7's lips (min_packing 0) on the bay's traced strips.
    const FrontSet f = trace_fronts(make_gonzato_bay(), WaveTrain{.period = 5.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0});
    const RayStrips strips = build_ray_strips(f);
    GonzatoProfileOptions eq7;
    eq7.min_packing = 0.0;
    const GonzatoMotionPlan plan = plan_gonzato_motion(strips, eq7);
    std::vector<float> p(3 * plan.vertex_count()), n(p.size());
    std::size_t downward = 0, downward_offshore = 0;
    for (int frame = 0; frame < 10; ++frame) {
        evaluate_gonzato_motion(plan, 0.5 * frame, p);
        for (float v : p) ASSERT_TRUE(std::isfinite(v));
        for (std::size_t t = 0; t < strips.triangle_count(); ++t) {
            const std::uint32_t a = strips.triangles[3 * t], b = strips.triangles[3 * t + 1], c = strips.triangles[3 * t + 2];
            const double ux = p[3 * b] - p[3 * a], uy = p[3 * b + 1] - p[3 * a + 1];
            const double vx = p[3 * c] - p[3 * a], vy = p[3 * c + 1] - p[3 * a + 1];
            if (ux * vy - uy * vx < 0.0) {  // the triangle's normal points down: under a lip
                ++downward;
                if (strips.depth[a] > 4.0) ++downward_offshore;
            }
        }
    }
    EXPECT_GT(downward, 100u);
    EXPECT_EQ(downward_offshore, 0u);  // far from breaking: no overhang
    EXPECT_THROW(evaluate_gonzato_motion(plan, 0.0, std::span<float>(p.data(), 3)), InputError);
}

TEST(GonzatoMotion, ThreadCountDoesNotChangeTheFrame) {
    // Every vertex is evaluated alone: the parallel loop gives the serial bytes.
    const RayStrips strips = build_ray_strips(trace_fronts(make_gonzato_bay(), WaveTrain{.period = 5.0, .amplitude = 0.3}));
    const GonzatoMotionPlan plan = plan_gonzato_motion(strips);
    std::vector<float> p(3 * plan.vertex_count());
    evaluate_gonzato_motion(plan, 1.3, p);
    for (std::size_t v = 0; v < plan.vertex_count(); v += 101) {
        const ProfileOffset d = gonzato_offset(plan.shape[v], plan.phase[v] - plan.omega * 1.3);
        EXPECT_EQ(p[3 * v], static_cast<float>(plan.x[v] + d.forward * plan.dir_x[v]));
        EXPECT_EQ(p[3 * v + 2], static_cast<float>(d.up));
    }
}

}  // namespace
