// Isobaths: slicing against analytic contours, Beta-spline smoothing, and exact
// ray–contour crossings at vertices, tangencies and collinear overlaps.
#include "libwave/errors.h"
#include "libwave/isobath.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace wave;

TEST(Isobath, PlanarBeachGivesStraightContoursAtTheirDepth) {
    const Seafloor beach = make_planar_beach();  // shoreline y = 160, slope 0.05, sea to −y
    IsobathOptions o;
    o.levels = {1.0, 2.5, 4.0};
    const DepthContours c = extract_isobaths(beach, o);
    ASSERT_EQ(c.size(), 4u);  // three levels + the shoreline
    for (std::size_t p = 0; p < c.size(); ++p) {
        EXPECT_FALSE(c.closed[p]);
        const double y_expected = 160.0 - c.depth[p] / 0.05;
        for (std::size_t k = c.offsets[p]; k < c.offsets[p + 1]; ++k)
            EXPECT_NEAR(c.xy[2 * k + 1], y_expected, 1e-9) << "depth " << c.depth[p];
        // The contour spans the whole domain in x.
        double lo = 1e9, hi = -1e9;
        for (std::size_t k = c.offsets[p]; k < c.offsets[p + 1]; ++k) lo = std::min(lo, c.xy[2 * k]), hi = std::max(hi, c.xy[2 * k]);
        EXPECT_NEAR(lo, 0.0, 1e-9);
        EXPECT_NEAR(hi, 200.0, 1e-9);
    }
    EXPECT_EQ(c.depth.front(), 0.0);  // sorted: shoreline first
}

TEST(Isobath, ConicalIslandGivesClosedCircles) {
    const Seafloor island = make_conical_island({.spacing = 0.1});  // 75 k nodes: quick under ASan
    IsobathOptions o;
    o.levels = {0.1};
    o.include_shoreline = true;
    const DepthContours c = extract_isobaths(island, o);
    ASSERT_EQ(c.size(), 2u);
    for (std::size_t p = 0; p < c.size(); ++p) {
        EXPECT_TRUE(c.closed[p]);
        // Elevation −0.32 + 0.625 (3.6 − r)/2.5 = −h  ->  r = 3.6 − 2.5 (0.32 − h)/0.625.
        const double r = 3.6 - 2.5 * (0.32 - c.depth[p]) / 0.625;
        for (std::size_t k = c.offsets[p]; k < c.offsets[p + 1]; ++k)
            EXPECT_NEAR(std::hypot(c.xy[2 * k] - 12.5, c.xy[2 * k + 1] - 15.0), r, 5e-3);  // chordal error of the grid
    }
}

TEST(Isobath, MeshSeafloorsAreSlicedDirectly) {
    Seafloor s = make_planar_beach({.size_x = 20, .size_y = 20, .spacing = 10});
    s.mesh.xyz = {0, 0, -2, 20, 0, -2, 20, 20, 1, 0, 20, 1};  // a plane rising along y
    s.mesh.triangles = {0, 1, 2, 0, 2, 3};
    IsobathOptions o;
    o.levels = {0.5};
    const DepthContours c = extract_isobaths(s, o);
    ASSERT_EQ(c.size(), 2u);
    for (std::size_t k = c.offsets[1]; k < c.offsets[2]; ++k) EXPECT_NEAR(c.xy[2 * k + 1], 20.0 * 1.5 / 3.0, 1e-9);
}

TEST(Isobath, BadLevelsNameTheRange) {
    const Seafloor bay = make_gonzato_bay();
    IsobathOptions o;
    o.levels = {12.0};
    try {
        extract_isobaths(bay, o);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("12"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("-2 .. 5"), std::string::npos) << e.what();
    }
    EXPECT_THROW(extract_isobaths(bay, IsobathOptions{.levels = {}, .spacing = 0.0}), InputError);  // neither levels nor spacing
    // The default options are a scene's: every 0.25 m, and the shoreline.
    const DepthContours d = extract_isobaths(bay);
    ASSERT_GT(d.size(), 0u);
    for (std::size_t i = 0; i < d.size(); ++i)
        EXPECT_NEAR(std::remainder(d.depth[i], 0.25), 0.0, 1e-12) << d.depth[i];
    o.levels = {NAN};
    EXPECT_THROW(extract_isobaths(bay, o), InputError);
    o.levels.clear();
    o.spacing = 1.0;
    EXPECT_EQ(extract_isobaths(bay, o).size(), 5u);  // 1, 2, 3, 4 m and the shoreline
}

TEST(Isobath, BetaSplineSmoothing) {
    DepthContours c;
    c.xy = {0, 0, 1, 1, 2, 0, 3, 1, 4, 0};
    c.offsets = {0, 5};
    c.depth = {2.0};
    c.closed = {0};
    for (double b2 : {0.0, 5.0, 50.0}) {
        const DepthContours s = smooth_isobaths(c, 8, 1.0, b2);
        ASSERT_EQ(s.size(), 1u);
        EXPECT_EQ(s.depth[0], 2.0);
        const std::size_t n = s.offsets[1];
        EXPECT_NEAR(s.xy[0], 0.0, 1e-12);  // open ends are kept
        EXPECT_NEAR(s.xy[2 * n - 2], 4.0, 1e-12);
        // Smoothing pulls the zig-zag in; higher tension pulls the curve towards the
        // control polygon (Barsky's β2), so the peaks get closer to y = 1.
        double peak = 0;
        for (std::size_t k = 0; k < n; ++k) peak = std::max(peak, s.xy[2 * k + 1]);
        EXPECT_LT(peak, 1.0);
        if (b2 == 0.0) {  // cubic B-spline at a vertex: (0 + 4·1 + 0)/6
            EXPECT_NEAR(peak, 2.0 / 3.0, 1e-9);
        }
        if (b2 == 50.0) {
            EXPECT_GT(peak, 0.9);
        }
    }
    EXPECT_THROW(smooth_isobaths(c, 0), InputError);
    EXPECT_THROW(smooth_isobaths(c, 4, -1.0), InputError);
}

DepthContours square_and_line() {
    DepthContours c;
    // Contour 0: closed square (0,0)–(2,2) at depth 3; contour 1: open line x = 5 at depth 1.
    c.xy = {0, 0, 2, 0, 2, 2, 0, 2, 5, -10, 5, 10};
    c.offsets = {0, 4, 6};
    c.depth = {3.0, 1.0};
    c.closed = {1, 0};
    return c;
}

TEST(Crossing, NearestCrossingAhead) {
    const IsobathIndex index(square_and_line());
    EXPECT_EQ(index.segment_count(), 5u);
    const auto hit = index.first_crossing({.x = -1, .y = 1, .dx = 1, .dy = 0});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->contour, 0u);
    EXPECT_DOUBLE_EQ(hit->x, 0.0);
    EXPECT_DOUBLE_EQ(hit->distance, 1.0);
    EXPECT_DOUBLE_EQ(hit->depth, 3.0);
    EXPECT_FALSE(hit->at_vertex);
    EXPECT_DOUBLE_EQ(std::abs(hit->tangent_y), 1.0);
    // From inside the square, skipping it, the next crossing is the line x = 5.
    const auto next = index.first_crossing({.x = 1, .y = 1, .dx = 1, .dy = 0, .skip_contour = 0});
    ASSERT_TRUE(next);
    EXPECT_EQ(next->contour, 1u);
    EXPECT_DOUBLE_EQ(next->distance, 4.0);
    // Backwards and beyond max_distance: nothing.
    EXPECT_FALSE(index.first_crossing({.x = 6, .y = 1, .dx = 1, .dy = 0}));
    EXPECT_FALSE(index.first_crossing({.x = -1, .y = 1, .dx = 1, .dy = 0, .max_distance = 0.5}));
    EXPECT_TRUE(index.first_crossing({.x = -1, .y = 1, .dx = 1, .dy = 0, .max_distance = 1.0}));
}

TEST(Crossing, ThroughAVertexAndAlongASegmentAreExact) {
    const IsobathIndex index(square_and_line());
    // Diagonal ray through the corner (0, 0): both corner segments meet there.
    const auto corner = index.first_crossing({.x = -1, .y = -1, .dx = 1, .dy = 1});
    ASSERT_TRUE(corner);
    EXPECT_TRUE(corner->at_vertex);
    EXPECT_DOUBLE_EQ(corner->x, 0.0);
    EXPECT_DOUBLE_EQ(corner->y, 0.0);
    EXPECT_NEAR(corner->distance, std::sqrt(2.0), 1e-15);
    // Along the bottom edge y = 0: collinear overlap; the crossing is where it begins.
    const auto along = index.first_crossing({.x = -3, .y = 0, .dx = 1, .dy = 0});
    ASSERT_TRUE(along);
    EXPECT_TRUE(along->collinear);
    EXPECT_DOUBLE_EQ(along->x, 0.0);
    EXPECT_DOUBLE_EQ(along->distance, 3.0);
    // A ray grazing the corner (2, 2) from outside touches it and nothing else nearer.
    const auto graze = index.first_crossing({.x = 0, .y = 4, .dx = 1, .dy = -1});
    ASSERT_TRUE(graze);
    EXPECT_TRUE(graze->at_vertex);
    EXPECT_DOUBLE_EQ(graze->x, 2.0);
    EXPECT_DOUBLE_EQ(graze->y, 2.0);
    // A ray that misses by one ulp of 2 misses exactly (no tolerance band).
    const auto miss = index.first_crossing({.x = 0, .y = std::nextafter(4.0, 5.0), .dx = 1, .dy = -1, .skip_contour = 1});
    EXPECT_FALSE(miss);
}

TEST(Crossing, RandomRaysAgreeWithBruteForce) {
    const Seafloor bay = make_gonzato_bay();
    IsobathOptions o;
    o.spacing = 0.5;
    const DepthContours c = extract_isobaths(bay, o);
    const IsobathIndex index(c);
    std::uint64_t state = 12345;
    auto next = [&] { state = state * 6364136223846793005ULL + 1442695040888963407ULL; return double(state >> 11) / double(1ULL << 53); };
    for (int n = 0; n < 200; ++n) {
        const double x = 100 * next(), y = 60 * next(), a = 2 * M_PI * next();
        const auto hit = index.first_crossing({.x = x, .y = y, .dx = std::cos(a), .dy = std::sin(a)});
        // Brute force in doubles: nearest positive ray parameter over all segments.
        double best = INFINITY;
        for (std::size_t p = 0; p < c.size(); ++p)
            for (std::size_t k = c.offsets[p]; k + 1 < c.offsets[p + 1]; ++k) {
                const double ax = c.xy[2 * k], ay = c.xy[2 * k + 1], bx = c.xy[2 * k + 2], by = c.xy[2 * k + 3];
                const double ex = bx - ax, ey = by - ay, den = std::cos(a) * ey - std::sin(a) * ex;
                if (den == 0) continue;
                const double t = ((ax - x) * ey - (ay - y) * ex) / den;
                const double u = ((ax - x) * std::sin(a) - (ay - y) * std::cos(a)) / den;
                if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
            }
        if (std::isinf(best)) {
            EXPECT_FALSE(hit);
        } else {
            ASSERT_TRUE(hit) << n;
            EXPECT_NEAR(hit->distance, best, 1e-9 * (1 + best)) << n;
        }
    }
}

}  // namespace
