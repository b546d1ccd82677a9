// Height field and Beta2-spline surface: deposits against the traced rays, exact loops,
// crest sharpening by tension, topology counts.
#include "libwave/beta_spline.h"
#include "libwave/errors.h"
#include "libwave/surface.h"
#include "surface/triangle_locator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>
#include <cstring>
#include <numbers>

namespace {

using namespace wave;

TEST(BetaSpline, BasisSumsToOneAndIsTheBSplineAtZeroTension) {
    for (double b2 : {0.0, 1.0, 10.0, 100.0})
        for (double u = 0.0; u <= 1.0; u += 0.125) {
            double w[4];
            beta_spline_basis(u, 1.0, b2, w);
            EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0, 1e-15);
            if (b2 == 0.0) {
                EXPECT_NEAR(w[0], std::pow(1 - u, 3) / 6, 1e-15);
                EXPECT_NEAR(w[3], u * u * u / 6, 1e-15);
            }
        }
    double w[4];
    beta_spline_basis(0.0, 1.0, 1e6, w);  // infinite tension: the control polygon
    EXPECT_NEAR(w[1], 1.0, 1e-5);
}

TEST(LoopPeriod, LeastCommonMultiple) {
    const double tso[] = {6.0, 1.0};
    EXPECT_DOUBLE_EQ(loop_period(tso), 6.0);
    const double thirds[] = {1.5, 2.5};
    EXPECT_NEAR(loop_period(thirds), 7.5, 1e-12);
    const double irrational[] = {1.0, std::numbers::sqrt2};
    EXPECT_EQ(loop_period(irrational), 0.0);
}

struct BeachScene {
    Seafloor beach = make_planar_beach({.size_x = 60, .size_y = 100, .spacing = 1.0, .shore_distance = 30.0});
    DepthContours iso;
    std::vector<WaveTrain> trains{{.period = 6.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0}};
    RaySet rays;
    BeachScene() {
        IsobathOptions io;
        io.spacing = 0.25;
        iso = extract_isobaths(beach, io);
        TraceOptions to;
        to.ray_spacing = 0.5;
        rays = trace_rays(beach, iso, trains, to);
    }
};

TEST(HeightField, DepositsMatchTheRaysAtNormalIncidence) {
    const BeachScene s;
    for (Footprint footprint : {Footprint::bresenham, Footprint::smooth}) {
        HeightFieldOptions o;
        o.nx = 31;
        o.ny = 51;  // 2 m cells, 4 orthogonals per cell
        o.footprint = footprint;
        const HeightFieldPlan plan = plan_height_field(s.beach, s.rays, s.trains, o);
        EXPECT_DOUBLE_EQ(plan.loop_period, 6.0);
        // Every ray is identical at normal incidence: a node's term is the ray's wave there.
        const std::size_t r0 = 0;
        for (std::size_t j = 2; j < plan.ny; j += 5) {
            const std::size_t v = j * plan.nx + 15;
            const double y = plan.y0 + static_cast<double>(j) * plan.dy;
            if (depth_at(s.beach.grid, 30.0, y) <= 0.0) {
                EXPECT_EQ(plan.term_offsets[v + 1], plan.term_offsets[v]) << "land node has no wave";
                continue;
            }
            ASSERT_EQ(plan.term_offsets[v + 1] - plan.term_offsets[v], 1u) << j;
            std::size_t p = s.rays.offsets[r0];
            while (p + 1 < s.rays.offsets[r0 + 1] && s.rays.y[p + 1] <= y) ++p;  // the leg holding y
            const double phase = s.rays.phase[p] + s.rays.k[p] * (y - s.rays.y[p]);
            const std::size_t k = plan.term_offsets[v];
            EXPECT_NEAR(plan.term_amplitude[k], s.rays.amplitude[p], 1e-12);
            EXPECT_NEAR(std::remainder(plan.term_phase[k] - phase, 2 * std::numbers::pi), 0.0, 1e-9);
        }
    }
}

TEST(HeightField, LoopsExactlyAndIsDeterministic) {
    const BeachScene s;
    std::vector<WaveTrain> two = s.trains;
    two.push_back({.period = 1.0, .amplitude = 0.05, .direction_x = -0.5, .direction_y = 0.7});
    TraceOptions to;
    to.ray_spacing = 0.5;
    const RaySet rays = trace_rays(s.beach, s.iso, two, to);
    HeightFieldOptions o;
    o.nx = o.ny = 20;
    o.samples_per_span = 4;
    const HeightFieldPlan plan = plan_height_field(s.beach, rays, two, o);
    EXPECT_DOUBLE_EQ(plan.loop_period, 6.0);  // LCM of 6 s and 1 s, as in Ts'o's animation
    std::vector<float> h(plan.control_count()), a(3 * plan.vertex_count()), b(a.size()), c(a.size());
    evaluate_height_field(plan, 0.0, h, a);
    evaluate_height_field(plan, plan.loop_period, h, b);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);  // frame 0 == frame T
    evaluate_height_field(plan, 1.25, h, b);
    evaluate_height_field(plan, 1.25, h, c);
    EXPECT_EQ(std::memcmp(b.data(), c.data(), b.size() * sizeof(float)), 0);
    EXPECT_NE(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);  // it moves
    // Incommensurate periods need a repeat time; with one, they loop after it exactly.
    two[1].period = std::numbers::sqrt2;
    EXPECT_THROW(plan_height_field(s.beach, rays, two, o), InputError);
    o.repeat_time = 12.0;
    const HeightFieldPlan q = plan_height_field(s.beach, rays, two, o);
    evaluate_height_field(q, 0.5, h, a);
    evaluate_height_field(q, 12.5, h, b);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
}

TEST(HeightField, SurfaceSpansTheGridAndTensionSharpensCrests) {
    const BeachScene s;
    HeightFieldOptions o;
    o.nx = 31;
    o.ny = 51;
    o.tension_per_metre = 0.0;
    const HeightFieldPlan flat = plan_height_field(s.beach, s.rays, s.trains, o);
    o.tension_per_metre = 100.0;
    o.max_tension = 50.0;
    const HeightFieldPlan tense = plan_height_field(s.beach, s.rays, s.trains, o);
    EXPECT_EQ(flat.vertex_count(), (8u * 30 + 1) * (8u * 50 + 1));
    EXPECT_EQ(flat.triangle_count(), 2u * 240 * 400);
    std::vector<float> h(flat.control_count()), p0(3 * flat.vertex_count()), p1(p0.size());
    evaluate_height_field(flat, 0.7, h, p0);
    evaluate_height_field(tense, 0.7, h, p1);
    // Corners pass through the border control vertices (phantom vertices).
    EXPECT_NEAR(p0[0], flat.x0, 1e-5);
    EXPECT_NEAR(p0[1], flat.y0, 1e-5);
    EXPECT_NEAR(p0[2], h[0], 1e-6);
    const std::size_t last = flat.vertex_count() - 1;
    EXPECT_NEAR(p0[3 * last], 60.0, 1e-4);
    EXPECT_NEAR(p0[3 * last + 1], 100.0, 1e-4);
    // Tension pulls crests up towards their control vertices; troughs (β2 = 0) equal.
    float crest0 = -1e9f, crest1 = -1e9f, trough0 = 1e9f, trough1 = 1e9f;
    for (std::size_t v = 0; v < flat.vertex_count(); ++v) {
        crest0 = std::max(crest0, p0[3 * v + 2]);
        crest1 = std::max(crest1, p1[3 * v + 2]);
        trough0 = std::min(trough0, p0[3 * v + 2]);
        trough1 = std::min(trough1, p1[3 * v + 2]);
    }
    float control_max = -1e9f;
    for (float z : h) control_max = std::max(control_max, z);
    EXPECT_GT(crest1, crest0 + 0.01f);
    EXPECT_LE(crest1, control_max + 1e-6f);
    EXPECT_NEAR(trough1, trough0, 0.02);
}

TEST(HeightField, BadOptionsAndLimits) {
    const BeachScene s;
    HeightFieldOptions o;
    o.nx = 1;
    EXPECT_THROW(plan_height_field(s.beach, s.rays, s.trains, o), InputError);
    o = {};
    o.samples_per_span = 0;
    EXPECT_THROW(plan_height_field(s.beach, s.rays, s.trains, o), InputError);
    o = {};
    o.max_vertices = 1000;
    EXPECT_THROW(plan_height_field(s.beach, s.rays, s.trains, o), LimitError);
}

TEST(HeightField, SmoothFootprintCoversTheGapsBetweenRays) {
    const BeachScene s;
    TraceOptions to;
    to.ray_spacing = 6.0;  // 3 cells apart: Bresenham leaves columns empty
    const RaySet sparse = trace_rays(s.beach, s.iso, s.trains, to);
    HeightFieldOptions o;
    o.nx = 31;
    o.ny = 51;
    o.footprint = Footprint::bresenham;
    const HeightFieldPlan thin = plan_height_field(s.beach, sparse, s.trains, o);
    o.footprint = Footprint::smooth;
    o.footprint_radius = 2.0;
    const HeightFieldPlan wide = plan_height_field(s.beach, sparse, s.trains, o);
    EXPECT_GT(wide.term_amplitude.size(), thin.term_amplitude.size() + 200);
}

}  // namespace

// The locator keeps the mesh's large triangles (a far skirt's) in a grid of their own:
// against a brute-force search over every triangle, on a graded mesh of 1 m cells inside
// a ring of 200 m triangles, with a large low-numbered triangle lying over some small ones
// (where triangles overlap the lowest index wins) and points on shared edges (the same
// tie rule), each point's triangle and weights must be the brute force's.
TEST(TriangleLocator, LargeTrianglesApartGiveTheBruteForceAnswer) {
    std::vector<double> x, y;
    std::vector<std::uint32_t> tri;
    const auto vertex = [&](double px, double py) {
        x.push_back(px), y.push_back(py);
        return static_cast<std::uint32_t>(x.size() - 1);
    };
    // A large triangle first (index 0), over part of the fine grid.
    tri.insert(tri.end(), {vertex(-5, -5), vertex(12, -5), vertex(-5, 12)});
    constexpr int n = 40;  // 40 × 40 cells of 1 m
    const std::uint32_t g0 = static_cast<std::uint32_t>(x.size());
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) vertex(i, j);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = g0 + static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1, c = a + n + 1, d = c + 1;
            tri.insert(tri.end(), {a, b, d, a, d, c});
        }
    // A ring of large triangles around the grid, to 400 m.
    const std::uint32_t o0 = vertex(-400, -400), o1 = vertex(440, -400), o2 = vertex(440, 440), o3 = vertex(-400, 440);
    const std::uint32_t i0 = g0, i1 = g0 + n, i2 = g0 + n * (n + 1) + n, i3 = g0 + n * (n + 1);
    tri.insert(tri.end(), {o0, o1, i1, o0, i1, i0, o1, o2, i2, o1, i2, i1, o2, o3, i3, o2, i3, i2, o3, o0, i0, o3, i0, i3});
    const wave::detail::TriangleLocator locator(x, y, tri);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> far(-420.0, 460.0), near(-6.0, 46.0);
    std::uniform_int_distribution<int> whole(0, n);
    int found = 0;
    for (int k = 0; k < 20000; ++k) {
        double px, py;
        if (k % 4 == 0) px = far(rng), py = far(rng);
        else if (k % 4 == 1) px = whole(rng), py = near(rng);  // on a grid line
        else px = near(rng), py = near(rng);
        wave::detail::TriangleLocator::Hit want{}, got{};
        bool hit = false;
        for (std::size_t t = 0; t < tri.size() / 3 && !hit; ++t) {
            const std::uint32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
            const double ux = x[b] - x[a], uy = y[b] - y[a], wx = x[c] - x[a], wy = y[c] - y[a], d = ux * wy - uy * wx;
            const double qx = px - x[a], qy = py - y[a];
            const double wb = (qx * wy - qy * wx) / d, wc = (ux * qy - uy * qx) / d, wa = 1.0 - wb - wc;
            if (wa >= -1e-9 && wb >= -1e-9 && wc >= -1e-9) want = {a, b, c, wa, wb, wc}, hit = true;
        }
        ASSERT_EQ(locator.locate(px, py, got), hit) << px << ", " << py;
        if (!hit) continue;
        ++found;
        ASSERT_EQ(got.a, want.a) << px << ", " << py;
        ASSERT_EQ(got.b, want.b);
        ASSERT_EQ(got.c, want.c);
        ASSERT_EQ(got.wa, want.wa);
        ASSERT_EQ(got.wb, want.wb);
    }
    EXPECT_GT(found, 15000);
}
