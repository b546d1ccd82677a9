// Ts'o–Barsky tracing: Snell's law at every exact crossing, amplitude against
// A∞ K_s K_r on a planar beach, total reflection, vertex and along-contour rays.
#include "libwave/errors.h"
#include "libwave/scene.h"
#include "libwave/trace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

using namespace wave;
constexpr double kDeg = std::numbers::pi / 180.0;

TEST(Trace, PlanarBeachSnellAtEveryCrossingAndAmplitude) {
    // The shipped example: a planar beach (straight contours along x, sea to −y) and a
    // T = 8 s, A∞ = 0.4 m swell at 30° to the shore normal, rays 2 m apart.
    const Scene scene = read_scene(std::string(LIBWAVE_EXAMPLES_DIR) + "/planar-beach.json");
    const Seafloor beach = load_seafloor(scene.seafloor);
    const DepthContours iso = extract_isobaths(beach, scene.isobaths);
    ASSERT_EQ(scene.waves.size(), 1u);
    const WaveTrain& train = scene.waves[0];
    ASSERT_EQ(train.period, 8.0);
    ASSERT_EQ(train.amplitude, 0.4);
    ASSERT_NEAR(std::atan2(train.direction_x, train.direction_y), 30 * kDeg, 1e-12);
    const RaySet rays = trace_rays(beach, iso, std::span(&train, 1), scene.trace);
    ASSERT_GT(rays.ray_count(), 50u);
    // Every ray, including those entering across the shallow west side (x = 0): those
    // start on the wave the corner's plane wave refracts into over the apron, so the
    // Snell invariant and K_r are the train's, counted from the up-wave corner (8 m deep).
    const double omega = 2 * std::numbers::pi / 8.0, cos0 = std::cos(30 * kDeg);
    const double invariant = std::sin(30 * kDeg) / linear_wave(omega, 8.0).celerity;
    const auto deep = [&](std::size_t q) { return rays.y[rays.offsets[q]] == 0.0; };  // entered across y = 0
    std::size_t checked = 0, aground = 0, west = 0;
    double worst_west = 0.0;
    for (std::size_t r = 0; r < rays.ray_count(); ++r) {
        const std::size_t s = rays.offsets[r];
        EXPECT_EQ(rays.event[s], RayEvent::start);
        west += rays.x[s] == 0.0;
        EXPECT_NEAR(rays.dir_x[s] / rays.celerity[s], invariant, 1e-13 * invariant) << r;
        for (std::size_t i = s + 1; i < rays.offsets[r + 1]; ++i) {
            if (rays.event[i] != RayEvent::refracted) continue;
            // The contour normal is ±y, so sin θ = dir_x; Snell: sin θ / C is invariant.
            EXPECT_NEAR(rays.dir_x[i] / rays.celerity[i], invariant, 1e-13 * invariant);
            ++checked;
            // Straight parallel contours: K_r = sqrt(cos θ0 / cos θ) exactly between rays
            // that entered across the deep edge y = 0 (translates of one another). Rays
            // entering across the west side 4 m apart start in different places within a
            // band, whose direction is the band's, not the entry depth's: their spacing, so
            // K_r, is off by a share of a band (measured up to 4.6 % at 1.5 m depth, where
            // one band turns the ray most; 1.1 % at 6.5 m).
            if (!(rays.flags[i] & kAmplitudeCapped)) {
                const double kr = std::sqrt(cos0 / rays.dir_y[i]);
                if (r > 0 && deep(r - 1) && deep(r) && r + 1 < rays.ray_count() && deep(r + 1)) {
                    EXPECT_NEAR(rays.refraction[i], kr, 1e-9);
                    EXPECT_NEAR(rays.amplitude[i], 0.4 * shoaling_coefficient(omega, rays.depth[i]) * kr, 1e-9);
                } else {
                    worst_west = std::max(worst_west, std::abs(rays.refraction[i] / kr - 1.0));
                }
            }
            EXPECT_LE(2 * rays.amplitude[i], kBreakerIndex * rays.depth[i] + 1e-12);
        }
        const RayEvent end = rays.event[rays.offsets[r + 1] - 1];
        EXPECT_TRUE(end == RayEvent::aground || end == RayEvent::left_domain);
        aground += end == RayEvent::aground;
    }
    EXPECT_GT(west, 20u);
    EXPECT_LT(worst_west, 0.05);
    EXPECT_GT(checked, 1000u);
    EXPECT_GT(aground, rays.ray_count() / 2);
    // The phase grows by k Δs along every leg.
    for (std::size_t i = 1; i < rays.offsets[1]; ++i)
        EXPECT_NEAR(rays.phase[i] - rays.phase[i - 1], rays.k[i - 1] * (rays.arc_length[i] - rays.arc_length[i - 1]), 1e-9);
}

// A flat shallow floor (h = 1 m) with hand-made contours, as in Ts'o's contour input.
Seafloor flat_shallow() {
    Seafloor s;
    s.grid.nx = s.grid.ny = 2;
    s.grid.dx = s.grid.dy = 100.0;
    s.grid.z = {-1.0, -1.0, -1.0, -1.0};
    return s;
}

DepthContours one_line(std::vector<double> xy, double depth) {
    DepthContours c;
    c.xy = std::move(xy);
    c.offsets = {0, c.xy.size() / 2};
    c.depth = {depth};
    c.closed = {0};
    return c;
}

TEST(Trace, TotalReflectionWhenSinRExceedsOne) {
    const Seafloor floor = flat_shallow();
    const DepthContours deep_edge = one_line({0, 50, 100, 50}, 20.0);  // shallow -> deep
    TraceOptions opt;
    opt.ray_spacing = 10.0;
    for (double angle : {60.0, 5.0}) {
        const WaveTrain t{.period = 8.0, .amplitude = 0.1, .direction_x = std::sin(angle * kDeg), .direction_y = std::cos(angle * kDeg)};
        const RaySet rays = trace_rays(floor, deep_edge, std::span(&t, 1), opt);
        std::size_t reflected = 0, refracted = 0;
        for (std::size_t i = 0; i < rays.point_count(); ++i) {
            if (rays.event[i] == RayEvent::reflected) {
                ++reflected;
                EXPECT_NEAR(rays.dir_x[i], std::sin(angle * kDeg), 1e-15);  // mirrored across y = 50
                EXPECT_NEAR(rays.dir_y[i], -std::cos(angle * kDeg), 1e-15);
                EXPECT_DOUBLE_EQ(rays.depth[i], 1.0);  // stays in the shallow band
            }
            refracted += rays.event[i] == RayEvent::refracted;
        }
        // C(20 m) / C(1 m) ≈ 3.6 at T = 8 s: 60° reflects, 5° refracts.
        const bool steep = angle == 60.0;
        EXPECT_EQ(reflected > 0, steep);
        EXPECT_EQ(refracted > 0, !steep);
    }
}

TEST(Trace, RayThroughAContourVertexCrossesOnce) {
    const Seafloor floor = flat_shallow();
    // Rays heading +y start at x = 0.5, 1.5, … 99.5: one passes the vertex (50.5, 50).
    const DepthContours vee = one_line({0, 40, 50.5, 50, 100, 40}, 0.5);
    const WaveTrain t{.period = 4.0, .amplitude = 0.05, .direction_x = 0.0, .direction_y = 1.0};
    const RaySet rays = trace_rays(floor, vee, std::span(&t, 1), TraceOptions{});
    bool found = false;
    for (std::size_t r = 0; r < rays.ray_count(); ++r) {
        if (rays.x[rays.offsets[r]] != 50.5) continue;
        found = true;
        ASSERT_EQ(rays.offsets[r + 1] - rays.offsets[r], 3u);  // start, one crossing, exit
        const std::size_t c = rays.offsets[r] + 1;
        EXPECT_EQ(rays.event[c], RayEvent::refracted);
        EXPECT_DOUBLE_EQ(rays.x[c], 50.5);
        EXPECT_DOUBLE_EQ(rays.y[c], 50.0);
    }
    EXPECT_TRUE(found);
}

TEST(Trace, RayAlongAContourEnds) {
    const Seafloor floor = flat_shallow();
    const DepthContours wall = one_line({30.5, 20, 30.5, 80}, 2.0);
    const WaveTrain t{.period = 4.0, .amplitude = 0.05, .direction_x = 0.0, .direction_y = 1.0};
    const RaySet rays = trace_rays(floor, wall, std::span(&t, 1), TraceOptions{});
    for (std::size_t r = 0; r < rays.ray_count(); ++r) {
        if (rays.x[rays.offsets[r]] != 30.5) continue;
        // Grazing a deeper contour: sin i = 1 > C_i / C_r, reflected without turning.
        EXPECT_EQ(rays.event[rays.offsets[r] + 1], RayEvent::reflected);
        EXPECT_DOUBLE_EQ(rays.dir_y[rays.offsets[r] + 1], 1.0);
        EXPECT_EQ(rays.event[rays.offsets[r + 1] - 1], RayEvent::left_domain);
        return;
    }
    FAIL() << "no ray started at x = 30.5";
}

TEST(Trace, CausticsAreCappedNotInfinite) {
    // Berkhoff's shoal focuses rays behind it into a caustic.
    const Seafloor shoal = make_berkhoff_shoal({.spacing = 0.1});
    IsobathOptions io;
    io.spacing = 0.02;
    const DepthContours iso = extract_isobaths(shoal, io);
    const WaveTrain t{.period = 1.0, .amplitude = 0.0232, .direction_x = 1.0, .direction_y = 0.0};
    TraceOptions opt;
    opt.ray_spacing = 0.1;
    const RaySet rays = trace_rays(shoal, iso, std::span(&t, 1), opt);
    std::size_t capped = 0;
    double largest_kr = 0;
    for (std::size_t i = 0; i < rays.point_count(); ++i) {
        EXPECT_TRUE(std::isfinite(rays.amplitude[i]));
        EXPECT_LE(2 * rays.amplitude[i], kBreakerIndex * rays.depth[i] + 1e-12);
        capped += (rays.flags[i] & kAmplitudeCapped) != 0;
        largest_kr = std::max(largest_kr, rays.refraction[i]);
    }
    EXPECT_GT(largest_kr, 2.0);  // focusing happened
    EXPECT_GT(capped, 0u);
}

TEST(Trace, BadTrainsAndLimits) {
    const Seafloor floor = flat_shallow();
    const DepthContours iso = one_line({0, 50, 100, 50}, 0.5);
    const auto fails = [&](WaveTrain t, TraceOptions o, const char* part) {
        try {
            trace_rays(floor, iso, std::span(&t, 1), o);
            ADD_FAILURE() << "no error for " << part;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    fails({.period = 0.0}, {}, "period must be > 0 s, got 0");
    fails({.amplitude = -1.0}, {}, "amplitude");
    fails({.direction_x = 0.0, .direction_y = 0.0}, {}, "non-zero vector");
    fails({}, {.ray_spacing = -1.0}, "ray_spacing");
    fails({}, {.ray_spacing = 0.001, .max_rays = 1000}, "max_rays");
    EXPECT_THROW(trace_rays(floor, iso, std::span<const WaveTrain>(), {}), InputError);
}

TEST(Trace, CsvHasTheDocumentedColumns) {
    const Seafloor floor = flat_shallow();
    const WaveTrain t{.period = 4.0, .amplitude = 0.05};
    TraceOptions o;
    o.ray_spacing = 25.0;
    const RaySet rays = trace_rays(floor, one_line({0, 50, 100, 50}, 0.5), std::span(&t, 1), o);
    const std::string csv = rays_to_csv(rays);
    EXPECT_EQ(csv.substr(0, csv.find('\n')), "ray,step,x,y,dir_x,dir_y,depth,k,omega,celerity,group_velocity,amplitude,flag");
    EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), rays.point_count() + 1);
    EXPECT_NE(csv.find(",refracted\n"), std::string::npos);
}

}  // namespace
