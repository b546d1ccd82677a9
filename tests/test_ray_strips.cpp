// Gonzato's ray strips (fig. 11): counts, orientation, validity on every seafloor we
// ship, and the PLY file with its per-vertex properties.
#include "libwave/errors.h"
#include "libwave/surface.h"
#include "planar_beach_wave.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <filesystem>

namespace {

using namespace wave;

// Twice the signed area of triangle t at rest.
double doubled_area(const RayStrips& s, std::size_t t) {
    const std::uint32_t a = s.triangles[3 * t], b = s.triangles[3 * t + 1], c = s.triangles[3 * t + 2];
    return (s.x[b] - s.x[a]) * (s.y[c] - s.y[a]) - (s.y[b] - s.y[a]) * (s.x[c] - s.x[a]);
}

void expect_valid(const RayStrips& s, const char* what) {
    ASSERT_GT(s.triangle_count(), 0u) << what;
    for (std::size_t v = 0; v < s.vertex_count(); ++v)
        ASSERT_TRUE(std::isfinite(s.x[v]) && std::isfinite(s.y[v]) && std::isfinite(s.phase[v]) &&
                    std::isfinite(s.amplitude[v]))
            << what << " vertex " << v;
    for (std::size_t t = 0; t < s.triangle_count(); ++t) {
        const std::uint32_t a = s.triangles[3 * t], b = s.triangles[3 * t + 1], c = s.triangles[3 * t + 2];
        ASSERT_TRUE(a != b && b != c && a != c) << what << " triangle " << t;
        ASSERT_NE(doubled_area(s, t), 0.0) << what << " triangle " << t;
    }
}

TEST(RayStrips, PlaneWaveOverFlatBottomGivesTwoTrianglesPerCellFacingUp) {
    // 20 m deep everywhere: rays stay parallel, no insertion, no removal.
    ElevationGrid g;
    g.nx = g.ny = 11;
    g.dx = g.dy = 5.0;
    g.z.assign(121, -20.0);
    Seafloor flat;
    flat.grid = g;
    FrontOptions o;
    o.ray_spacing = 2.0;
    o.step = 1.0;
    o.split_distance = 3.0;
    const FrontSet f = trace_fronts(flat, WaveTrain{.period = 4.0, .amplitude = 0.2, .direction_x = 0.0, .direction_y = 1.0}, o);
    const RayStrips s = build_ray_strips(f);
    EXPECT_EQ(f.inserted_rays, 0u);
    std::size_t cells = 0;
    for (std::size_t fr = 1; fr < f.front_count(); ++fr) {
        const std::size_t a = f.front_offsets[fr] - f.front_offsets[fr - 1];
        const std::size_t b = f.front_offsets[fr + 1] - f.front_offsets[fr];
        if (b == 0) break;  // every ray has left the domain
        ASSERT_EQ(a, b) << fr;
        cells += a - 1;
    }
    EXPECT_EQ(s.triangle_count(), 2 * cells);
    EXPECT_EQ(s.vertex_count(), f.x.size());
    for (std::size_t t = 0; t < s.triangle_count(); ++t) EXPECT_GT(doubled_area(s, t), 0.0) << t;  // counter-clockwise
    // The properties follow their vertices through OpenMesh.
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        EXPECT_EQ(s.ray[v], f.ray[v]);
        EXPECT_EQ(s.phase[v], f.phase[v]);
        EXPECT_EQ(s.flag[v], f.flag[v]);
    }
}

TEST(RayStrips, InsertedRayCellsGetThreeTriangles) {
    // Gonzato's bay: rays diverge at the headlands and new rays appear. Every cell with
    // one inserted ray has 3 triangles (fig. 11): the total is 2 per cell plus one per
    // inserted or removed ray between consecutive fronts.
    const FrontSet f = trace_fronts(make_gonzato_bay(), WaveTrain{.period = 5.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0});
    const RayStrips s = build_ray_strips(f);
    std::size_t expected = 0;
    for (std::size_t fr = 1; fr < f.front_count(); ++fr) {
        const std::size_t a = f.front_offsets[fr] - f.front_offsets[fr - 1];
        const std::size_t b = f.front_offsets[fr + 1] - f.front_offsets[fr];
        if (a > 0 && b > 0) expected += a + b - 2;  // zipping two chains: (a − 1) + (b − 1)
    }
    EXPECT_EQ(s.triangle_count() + s.degenerate_skipped, expected);
    EXPECT_LT(s.degenerate_skipped, s.triangle_count() / 100);
    expect_valid(s, "gonzato-bay");
    // Same order as the paper's 39 097 facets for its bay (the shape differs).
    EXPECT_GT(s.triangle_count(), 20'000u);
    EXPECT_LT(s.triangle_count(), 80'000u);
}

TEST(RayStrips, ValidOnTheIslandAndOnARealSeafloor) {
    expect_valid(build_ray_strips(trace_fronts(make_gonzato_island(), WaveTrain{.period = 5.0, .amplitude = 0.3})),
                 "gonzato-island");
    // Okushiri's Monai valley (real terrain, data/) at full scale: 2.2 km × 1.4 km,
    // sea to −x; a 10 s swell, rays 10 m apart, 4 m steps.
    ReadOptions r;
    r.horizontal_scale = 400.0;
    r.vertical_scale = 400.0;
    const Seafloor okushiri = read_seafloor(std::string(LIBWAVE_DATA_DIR) + "/bathymetry/okushiri_monai_lab1to400_1p4cm.asc", r);
    FrontOptions o;
    o.ray_spacing = 10.0;
    o.step = 4.0;
    o.split_distance = 30.0;
    const FrontSet f = trace_fronts(okushiri, WaveTrain{.period = 10.0, .amplitude = 0.5, .direction_x = 1.0, .direction_y = 0.0}, o);
    EXPECT_GT(f.rays_aground, 0u);
    expect_valid(build_ray_strips(f), "okushiri");
}

TEST(RayStrips, EveryPointOfTheBreakingBeachsFrontsIsInATriangle) {
    // The breaking beach's trace (examples/breaking-beach.json). A ray at the end of the
    // front walked 161 m along the shore beside aground neighbours: its 317 points lay on
    // no strip, and the exported surface's indices differed from strips.ply's.
    const RayStrips s = build_ray_strips(test::breaking_beach_fronts());
    expect_valid(s, "breaking beach");
    std::vector<bool> used(s.vertex_count(), false);
    for (const std::uint32_t v : s.triangles) used[v] = true;
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << s.vertex_count() << " points";
}

TEST(RayStrips, PlyKeepsThePropertiesPerVertex) {
    const FrontSet f = trace_fronts(make_gonzato_bay(), WaveTrain{.period = 5.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0});
    const RayStrips s = build_ray_strips(f);
    const auto path = std::filesystem::temp_directory_path() / "libwave-test-strips.ply";
    write_ray_strips_ply(s, path.string());
    OpenMesh::TriMesh_ArrayKernelT<> m;
    OpenMesh::VPropHandleT<double> amplitude;
    OpenMesh::VPropHandleT<int> ray;
    m.add_property(amplitude, "amplitude");
    m.add_property(ray, "ray");
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::Custom;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(m, path.string(), opt));
    std::filesystem::remove(path);
    ASSERT_EQ(m.n_vertices(), s.vertex_count());
    ASSERT_EQ(m.n_faces(), s.triangle_count());
    for (std::size_t v = 0; v < s.vertex_count(); v += 97) {
        const OpenMesh::VertexHandle h(static_cast<int>(v));
        EXPECT_EQ(m.property(amplitude, h), s.amplitude[v]);
        EXPECT_EQ(static_cast<std::uint32_t>(m.property(ray, h)), s.ray[v]);
    }
    EXPECT_THROW(write_ray_strips_ply(s, "/nonexistent-dir/strips.ply"), RuntimeError);
}

}  // namespace
