// Mesh inspection (libwave/inspect.h) on meshes whose answers are known by construction.
#include "libwave/errors.h"
#include "libwave/inspect.h"
#include "libwave/surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using namespace wave;

// A flat n × n grid of unit cells (z = 0), counter-clockwise from above.
struct Grid {
    std::size_t n;
    std::vector<float> positions;
    std::vector<std::uint32_t> triangles;
    explicit Grid(std::size_t n_) : n(n_), triangles(grid_triangles(n_, n_)) {
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t i = 0; i < n; ++i) positions.insert(positions.end(), {float(i), float(j), 0.0f});
    }
};

MorphAnimationView view_of(const std::vector<float>& positions, const std::vector<std::uint32_t>& triangles,
                           std::size_t vertices, std::size_t frames, const std::vector<float>& foam = {}) {
    MorphAnimationView v;
    v.positions = positions;
    v.triangles = triangles;
    v.vertex_count = vertices;
    v.frame_count = frames;
    v.loop_frames = frames;
    v.foam = foam;
    v.fps = 24.0;
    return v;
}

TEST(Inspect, AFlatGridIsCleanWithOneLoopOnTheBorder) {
    const Grid g(5);
    const MeshInspection m = inspect_animation(view_of(g.positions, g.triangles, 25, 1));
    EXPECT_EQ(m.triangle_count, 32u);
    EXPECT_EQ(m.unreferenced_vertices, 0u);
    EXPECT_EQ(m.non_manifold_edges, 0u);
    EXPECT_EQ(m.boundary_edges, 16u);
    ASSERT_EQ(m.loops.size(), 1u);
    EXPECT_EQ(m.loops[0].edges, 16u);
    EXPECT_DOUBLE_EQ(m.loops[0].length, 16.0);
    EXPECT_EQ(m.loops[0].on_border, 16u);
    EXPECT_DOUBLE_EQ(m.loops[0].farthest_inside, 0.0);
    const FrameInspection& f = m.frames[0];
    EXPECT_EQ(f.facing_down, 0u);
    EXPECT_EQ(f.folds, 0u);
    EXPECT_EQ(f.slivers, 0u);
    EXPECT_NEAR(f.smallest_angle_deg, 45.0, 1e-9);     // right isosceles halves of squares
    EXPECT_NEAR(f.longest_edge, std::sqrt(2.0), 1e-6);  // the diagonals
    EXPECT_DOUBLE_EQ(f.median_edge, 1.0);
    EXPECT_EQ(f.long_edges, 0u);
    EXPECT_EQ(f.max_speed, 0.0);  // one frame of a whole loop: compared with itself
}

TEST(Inspect, ATriangleTurnedOverIsAFoldWithoutFoamAndALipOnABreakingCrest) {
    Grid g(5);
    // Pull the inner vertex (2, 2) back to (0.5, 0.5), past its neighbours: triangles
    // around it turn over, each of them holding it.
    const std::size_t v = 2 * 5 + 2;
    g.positions[3 * v] = 0.5f;
    g.positions[3 * v + 1] = 0.5f;
    const MeshInspection folds = inspect_animation(view_of(g.positions, g.triangles, 25, 1));
    EXPECT_EQ(folds.frames[0].facing_down, folds.frames[0].folds);
    EXPECT_GE(folds.frames[0].folds, 2u);
    EXPECT_EQ(folds.frames[0].lips, 0u);
    std::vector<float> foam(25, 0.0f);
    foam[v] = 0.8f;  // the crest that overturns is breaking
    const MeshInspection lips = inspect_animation(view_of(g.positions, g.triangles, 25, 1, foam));
    EXPECT_EQ(lips.frames[0].lips, folds.frames[0].folds);
    EXPECT_EQ(lips.frames[0].folds, 0u);
    InspectOptions strict;
    strict.lip_foam = 0.9;  // below the threshold: still folds
    EXPECT_EQ(inspect_animation(view_of(g.positions, g.triangles, 25, 1, foam), strict).frames[0].folds,
              folds.frames[0].folds);
}

TEST(Inspect, AHoleIsASecondLoopInsideTheBorder) {
    Grid g(5);
    // Remove both triangles of cell (2, 2): a unit square hole 2 m from every side.
    const std::size_t cell = 2 * 4 + 2;
    g.triangles.erase(g.triangles.begin() + static_cast<std::ptrdiff_t>(6 * cell),
                      g.triangles.begin() + static_cast<std::ptrdiff_t>(6 * cell + 6));
    const MeshInspection m = inspect_animation(view_of(g.positions, g.triangles, 25, 1));
    ASSERT_EQ(m.loops.size(), 2u);
    EXPECT_DOUBLE_EQ(m.loops[0].length, 16.0);
    EXPECT_EQ(m.loops[1].edges, 4u);
    EXPECT_EQ(m.loops[1].on_border, 0u);
    EXPECT_DOUBLE_EQ(m.loops[1].farthest_inside, 2.0);
    EXPECT_EQ(m.open_boundary_chains, 0u);
}

TEST(Inspect, TheShoreIsNoBreakingCrestAndItsDriftIsMeasured) {
    Grid g(5);
    const std::size_t cell = 2 * 4 + 2;  // the hole of the test above: its corners 12, 13, 17, 18 are the shore
    g.triangles.erase(g.triangles.begin() + static_cast<std::ptrdiff_t>(6 * cell),
                      g.triangles.begin() + static_cast<std::ptrdiff_t>(6 * cell + 6));
    std::vector<float> two = g.positions;
    two.insert(two.end(), g.positions.begin(), g.positions.end());
    two[75 + 3 * 12 + 1] = 0.5f;  // frame 1: shore vertex 12 (2, 2) pulled down to (2, 0.5)
    const std::vector<float> foam(50, 1.0f);  // foamy everywhere, as a breaking crest would be
    const MeshInspection m = inspect_animation(view_of(two, g.triangles, 25, 2, foam));
    EXPECT_EQ(m.shore_vertices, 4u);
    EXPECT_DOUBLE_EQ(m.shore_drift, 1.5);
    EXPECT_EQ(m.frames[0].facing_down, 0u);
    // Every triangle turned over has vertex 12, on the shore: folds, not lips.
    EXPECT_GT(m.frames[1].facing_down, 0u);
    EXPECT_EQ(m.frames[1].folds, m.frames[1].facing_down);
    EXPECT_EQ(m.frames[1].lips, 0u);
    // Away from the shore: vertex 6 (1, 1) pulled down to (1, −0.5) turns the
    // triangles below it over, and on a breaking crest they are lips.
    two = g.positions;
    two.insert(two.end(), g.positions.begin(), g.positions.end());
    two[75 + 3 * 6 + 1] = -0.5f;
    const MeshInspection off = inspect_animation(view_of(two, g.triangles, 25, 2, foam));
    EXPECT_GT(off.frames[1].facing_down, 0u);
    EXPECT_EQ(off.frames[1].lips, off.frames[1].facing_down);
    EXPECT_EQ(off.frames[1].folds, 0u);
    EXPECT_DOUBLE_EQ(off.shore_drift, 0.0);
}

TEST(Inspect, UnreferencedVerticesNonManifoldEdgesSliversAndLongEdges) {
    Grid g(3);
    // A vertex nothing uses; a needle (0,0)-(0.5,-0.05)-(1,0) below edge (0, 1), angles
    // of 5.7° at both ends, and a triangle (0, 1, 3) over the grid's first: edge (0, 1)
    // then has three triangles.
    g.positions.insert(g.positions.end(), {7.0f, 7.0f, 0.0f, 0.5f, -0.05f, 0.0f});
    g.triangles.insert(g.triangles.end(), {0u, 10u, 1u, 0u, 1u, 3u});
    // The needle hangs 5 cm below the grid: with that much tolerance the grid's lower
    // side is on the border, and the needle is no shore triangle (the next test's are).
    const InspectOptions loose{.border_tolerance = 0.1};
    const MeshInspection m = inspect_animation(view_of(g.positions, g.triangles, 11, 1), loose);
    EXPECT_EQ(m.unreferenced_vertices, 1u);
    EXPECT_EQ(m.non_manifold_edges, 1u);
    EXPECT_EQ(m.frames[0].slivers, 1u);
    EXPECT_EQ(m.frames[0].lip_slivers, 0u);
    EXPECT_NEAR(m.frames[0].smallest_angle_deg, std::atan(0.1) * 180.0 / M_PI, 1e-4);
    EXPECT_NEAR(m.frames[0].smallest_angle_off_lips_deg, std::atan(0.1) * 180.0 / M_PI, 1e-4);
    // The needle's tip foamy: a sliver on a breaking crest. Off the lips the smallest
    // angle is then the grid's (45°) or the third triangle's on edge (0, 1).
    std::vector<float> foam(11, 0.0f);
    foam[10] = 0.5f;
    const MeshInspection on_lip = inspect_animation(view_of(g.positions, g.triangles, 11, 1, foam), loose);
    EXPECT_EQ(on_lip.frames[0].slivers, 1u);
    EXPECT_EQ(on_lip.frames[0].lip_slivers, 1u);
    EXPECT_NEAR(on_lip.frames[0].smallest_angle_deg, std::atan(0.1) * 180.0 / M_PI, 1e-4);
    EXPECT_GT(on_lip.frames[0].smallest_angle_off_lips_deg, 15.0);
    EXPECT_EQ(m.frames[0].facing_down, 0u);  // both run counter-clockwise seen from above
    // A stretched corner: vertex 8 (2, 2) pulled to (9, 9) makes its three edges 10.6 to
    // 11.3 m long where the spacing at their other ends is 1 to 1.4 m.
    Grid s(3);
    s.positions[3 * 8] = 9.0f;
    s.positions[3 * 8 + 1] = 9.0f;
    const MeshInspection l = inspect_animation(view_of(s.positions, s.triangles, 9, 1));
    EXPECT_GT(l.frames[0].worst_edge_ratio, 3.0);
    EXPECT_EQ(l.frames[0].long_edges, 3u);
    EXPECT_NEAR(l.frames[0].longest_edge, std::hypot(8.0, 8.0), 1e-5);  // to (1, 1)
}

TEST(Inspect, VertexSpeedBetweenFramesAndAcrossTheLoop) {
    const Grid g(3);
    std::vector<float> two = g.positions;
    two.insert(two.end(), g.positions.begin(), g.positions.end());
    two[27 + 3 * 4 + 2] = 0.5f;  // frame 1: the middle vertex 0.5 m up
    MorphAnimationView v = view_of(two, g.triangles, 9, 2);
    MeshInspection m = inspect_animation(v);
    EXPECT_DOUBLE_EQ(m.frames[0].max_speed, 12.0);  // 0.5 m in 1/24 s
    EXPECT_EQ(m.frames[0].fastest_vertex, 4u);
    EXPECT_DOUBLE_EQ(m.frames[1].max_speed, 12.0);  // back to frame 0: the loop closes
    v.loop_frames = 10;                             // a slice: nothing after its last frame
    m = inspect_animation(v);
    EXPECT_DOUBLE_EQ(m.frames[1].max_speed, 0.0);
    EXPECT_DOUBLE_EQ(m.worst.max_speed, 12.0);
}

TEST(Inspect, InconsistentSizesAreInputErrors) {
    const Grid g(3);
    EXPECT_THROW(inspect_animation(view_of(g.positions, g.triangles, 9, 2)), InputError);
    std::vector<std::uint32_t> bad = g.triangles;
    bad[4] = 9;
    EXPECT_THROW(inspect_animation(view_of(g.positions, bad, 9, 1)), InputError);
    EXPECT_THROW(inspect_animation(view_of(g.positions, g.triangles, 9, 1, std::vector<float>(3, 0.0f))), InputError);
}

}  // namespace
