// The water mesh (surface.h, mesh_water): a graded constrained Delaunay triangulation
// bounded exactly by the domain rectangle and the shoreline, checked with inspect.
#include "grid_seafloor.h"
#include "libwave/errors.h"
#include "libwave/inspect.h"
#include "libwave/surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace {

using namespace wave;

using test::grid_seafloor;

MeshInspection inspect(const WaterMesh& m, std::vector<float>& positions) {
    positions.clear();
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
        positions.insert(positions.end(), {static_cast<float>(m.x[v]), static_cast<float>(m.y[v]), 0.0f});
    MorphAnimationView view;
    view.positions = positions;
    view.triangles = m.triangles;
    view.vertex_count = m.vertex_count();
    view.frame_count = view.loop_frames = 1;
    return inspect_animation(view);
}

// Every triangle's longest edge against the size at its centroid.
double worst_size_ratio(const WaterMesh& m, const EdgeSize& size) {
    double worst = 0.0;
    for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
        const std::uint32_t a = m.triangles[t], b = m.triangles[t + 1], c = m.triangles[t + 2];
        const double longest = std::max({std::hypot(m.x[a] - m.x[b], m.y[a] - m.y[b]), std::hypot(m.x[b] - m.x[c], m.y[b] - m.y[c]),
                                         std::hypot(m.x[c] - m.x[a], m.y[c] - m.y[a])});
        worst = std::max(worst, longest / size((m.x[a] + m.x[b] + m.x[c]) / 3.0, (m.y[a] + m.y[b] + m.y[c]) / 3.0));
    }
    return worst;
}

TEST(WaterMesh, AFlatBasinIsMeshedToTheSizeWithStraightSides) {
    const Seafloor basin = grid_seafloor(100.0, 60.0, 5.0, [](double, double) { return 5.0; });
    const EdgeSize size = [](double, double) { return 4.0; };
    const WaterMesh m = mesh_water(basin, size);
    std::vector<float> p;
    const MeshInspection in = inspect(m, p);
    EXPECT_EQ(in.unreferenced_vertices, 0u);
    EXPECT_EQ(in.non_manifold_edges, 0u);
    ASSERT_EQ(in.loops.size(), 1u);
    EXPECT_NEAR(in.loops[0].length, 320.0, 1e-9);
    EXPECT_EQ(in.loops[0].on_border, in.loops[0].edges);
    EXPECT_EQ(in.frames[0].facing_down, 0u);
    EXPECT_GE(in.frames[0].smallest_angle_deg, 20.0);  // the refinement's bound (corners are 90°)
    EXPECT_LE(worst_size_ratio(m, size), 1.0);
    // A boundary vertex lies exactly on a side; the others strictly inside.
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const bool side = m.x[v] == 0.0 || m.x[v] == 100.0 || m.y[v] == 0.0 || m.y[v] == 60.0;
        EXPECT_EQ(side, m.boundary[v] != 0) << v;
    }
    // Equilateral triangles of edge 4 m would be 6 000 m² / 6.93 m² = 866; refinement
    // stops between half and all of the bound.
    EXPECT_GT(m.triangles.size() / 3, 400u);
    EXPECT_LT(m.triangles.size() / 3, 4000u);
}

TEST(WaterMesh, APlanarBeachEndsOnTheShorelineAndIsFinerInShallowWater) {
    // h = 10 − x/10: the shore at x = 100, land beyond; the edge size grows with depth.
    const Seafloor beach = grid_seafloor(200.0, 80.0, 2.0, [](double x, double) { return 10.0 - x / 10.0; });
    const EdgeSize size = [](double x, double) { return 0.5 + 0.4 * std::max(10.0 - x / 10.0, 0.0); };
    const WaterMesh m = mesh_water(beach, size);
    std::vector<float> p;
    const MeshInspection in = inspect(m, p);
    ASSERT_EQ(in.loops.size(), 1u);
    EXPECT_EQ(in.frames[0].facing_down, 0u);
    EXPECT_GE(in.frames[0].smallest_angle_deg, 20.0);
    EXPECT_LE(worst_size_ratio(m, size), 1.0);
    std::size_t on_shore = 0;
    double near = 0.0, far = 0.0;
    std::size_t near_n = 0, far_n = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        EXPECT_LE(m.x[v], 100.0 + 1e-9) << "a vertex on land";
        if (m.boundary[v] && m.x[v] > 1e-9 && m.y[v] > 1e-9 && m.y[v] < 80.0 - 1e-9) {
            EXPECT_NEAR(m.x[v], 100.0, 1e-9) << "a boundary vertex off the h = 0 line";
            ++on_shore;
        }
    }
    for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
        const std::uint32_t a = m.triangles[t], b = m.triangles[t + 1];
        const double cx = (m.x[a] + m.x[b] + m.x[m.triangles[t + 2]]) / 3.0, edge = std::hypot(m.x[a] - m.x[b], m.y[a] - m.y[b]);
        if (cx > 90.0) {
            near += edge;
            ++near_n;
        }
        if (cx < 10.0) {
            far += edge;
            ++far_n;
        }
    }
    EXPECT_GT(on_shore, 40u);  // 80 m of shore at ≤ 0.5 m … 0.9 m edges
    EXPECT_LT(near / static_cast<double>(near_n), 0.5 * far / static_cast<double>(far_n));  // graded
}

TEST(WaterMesh, AnIslandIsAHoleBoundedByItsShoreline) {
    // A cone: land within r = 20 m of (100, 100), 4 m deep at r = 40 m and beyond.
    const auto depth = [](double x, double y) { return std::min(std::hypot(x - 100.0, y - 100.0) / 5.0 - 4.0, 4.0); };
    const Seafloor island = grid_seafloor(200.0, 200.0, 2.0, depth);
    const WaterMesh m = mesh_water(island, [](double, double) { return 3.0; });
    std::vector<float> p;
    const MeshInspection in = inspect(m, p);
    ASSERT_EQ(in.loops.size(), 2u);
    EXPECT_EQ(in.loops[0].on_border, in.loops[0].edges);
    EXPECT_EQ(in.loops[1].on_border, 0u);
    EXPECT_NEAR(in.loops[1].length, 2.0 * std::numbers::pi * 20.0, 1.0);
    EXPECT_NEAR(in.loops[1].farthest_inside, 100.0 - 20.0 / std::sqrt(2.0), 0.5);  // the ring's diagonal points
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const double r = std::hypot(m.x[v] - 100.0, m.y[v] - 100.0);
        EXPECT_GE(r, 20.0 - 0.05) << "a vertex on the island";
        if (m.boundary[v] && r < 50.0) {
            EXPECT_NEAR(r, 20.0, 0.05);  // on the sliced h = 0 line
        }
    }
    EXPECT_EQ(in.frames[0].facing_down, 0u);
}

TEST(WaterMesh, APondInlandIsLeftOutUnlessAskedAndAnEnclosedLakeIsKept) {
    // Sea over x < 40 (5 m deep), land beyond it 2 m up, and in the land a pond of radius
    // 10 m round (75, 30), 1 m deep: no water joins it to the domain's border.
    const auto pond = [](double x, double y) { return std::hypot(x - 75.0, y - 30.0) < 10.0 ? 1.0 : -2.0; };
    const Seafloor coast = grid_seafloor(100.0, 60.0, 1.0, [&](double x, double y) { return x < 40.0 ? 5.0 : pond(x, y); });
    const auto in_pond = [](const WaterMesh& m) {
        std::size_t n = 0;
        for (std::size_t v = 0; v < m.vertex_count(); ++v) n += std::hypot(m.x[v] - 75.0, m.y[v] - 30.0) < 9.0 ? 1 : 0;
        return n;
    };
    const auto sea_reaches = [](const WaterMesh& m) { return *std::max_element(m.x.begin(), m.x.end()); };
    const WaterMesh open = mesh_water(coast, [](double, double) { return 3.0; });
    EXPECT_EQ(in_pond(open), 0u) << "the inland pond was meshed";
    EXPECT_LT(sea_reaches(open), 41.0);
    EXPECT_GT(sea_reaches(open), 39.0);
    WaterMeshOptions keep;
    keep.inland_water = true;
    const WaterMesh all = mesh_water(coast, [](double, double) { return 3.0; }, keep);
    EXPECT_GT(in_pond(all), 10u);
    EXPECT_GT(all.vertex_count(), open.vertex_count());
    // A lake with land all round the border: the only water there is, kept.
    const Seafloor lake = grid_seafloor(100.0, 60.0, 1.0, [&](double x, double y) { return pond(x, y); });
    EXPECT_GT(in_pond(mesh_water(lake, [](double, double) { return 3.0; })), 10u);
}

TEST(WaterMesh, SameMeshEveryTimeAndLimitsRefusedBeforeMeshing) {
    const Seafloor beach = grid_seafloor(120.0, 60.0, 2.0, [](double x, double y) { return 6.0 - x / 15.0 + 0.5 * std::sin(y / 7.0); });
    const EdgeSize size = [](double x, double) { return 1.0 + x / 100.0; };
    const WaterMesh a = mesh_water(beach, size), b = mesh_water(beach, size);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.triangles, b.triangles);
    WaterMeshOptions small;
    small.max_vertices = 100;
    EXPECT_THROW(mesh_water(beach, size, small), LimitError);
    WaterMeshOptions steep;
    steep.min_angle_deg = 30.0;
    EXPECT_THROW(mesh_water(beach, size, steep), InputError);
    const Seafloor land = grid_seafloor(50.0, 50.0, 5.0, [](double, double) { return -1.0; });
    EXPECT_THROW(mesh_water(land, size), InputError);
}

}  // namespace

namespace {

TEST(WaterMesh, TheWaterlineHidesTheShorelineUnderTheSandAndKeepsAFilmInTheTroughs) {
    // h = 10 − x/10: the shore at x = 100. A trough 2 h deep everywhere (the swash's
    // troughs reached 1.1–1.9 h on the default bay): every wet vertex keeps 0.3 h of
    // water, eased; the shoreline's vertices stand a twentieth of the amplitude under the
    // sand; water well above the floor is left as it is.
    const wave::Seafloor beach = wave::test::grid_seafloor(200.0, 80.0, 2.0, [](double x, double) { return 10.0 - x / 10.0; });
    const wave::WaterMesh m = wave::mesh_water(beach, [](double, double) { return 4.0; });
    const wave::WaterlinePlan plan = wave::plan_waterline(m, beach, 0.4);
    ASSERT_EQ(plan.depth.size(), m.vertex_count());
    EXPECT_FLOAT_EQ(plan.under_sand, 0.02f);
    std::size_t on_shore = 0;
    for (const std::uint32_t v : plan.shore) {
        EXPECT_NEAR(m.x[v], 100.0, 1e-6);  // the sides are not shore
        ++on_shore;
    }
    EXPECT_GT(on_shore, 10u);
    std::vector<float> trough(3 * m.vertex_count()), calm(3 * m.vertex_count(), 0.0f);
    for (std::size_t v = 0; v < m.vertex_count(); ++v) trough[3 * v + 2] = -2.0f * plan.depth[v];
    wave::keep_waterline(plan, trough);
    wave::keep_waterline(plan, calm);
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const float h = plan.depth[v];
        if (h > 0.0f) {
            EXPECT_NEAR(trough[3 * v + 2] + h, 0.3f * h, 1e-5f * (1.0f + h)) << v;
        }
        if (h > 0.1f) {
            EXPECT_EQ(calm[3 * v + 2], 0.0f) << v;  // 0.3 h is far below still water: untouched
        }
    }
    for (const std::uint32_t v : plan.shore) EXPECT_EQ(calm[3 * v + 2], -0.02f);
    std::vector<float> short_frame(3);
    EXPECT_THROW(wave::keep_waterline(plan, short_frame), wave::InputError);
}

}  // namespace
