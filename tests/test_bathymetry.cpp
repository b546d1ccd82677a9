// Bathymetry: bicubic queries, procedural seafloors, and every reader on real data
// and on broken files.
#include "libwave/bathymetry.h"
#include "libwave/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <unistd.h>

namespace {

using namespace wave;
namespace fs = std::filesystem;

const std::string kData = LIBWAVE_DATA_DIR;

// A scratch folder per test, removed afterwards.
class Scratch : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("libwave-test-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                "-" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& text) {
        const auto p = (dir_ / name).string();
        std::ofstream(p) << text;
        return p;
    }
    fs::path dir_;
};

// Runs f, expects InputError whose message contains every one of `parts`.
template <class F>
void expect_input_error(F&& f, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "no InputError thrown";
    } catch (const InputError& e) {
        for (const auto& p : parts)
            EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << "'" << p << "' not in: " << e.what();
    }
}

ElevationGrid grid_of(std::size_t nx, std::size_t ny, double dx, auto&& f) {
    ElevationGrid g;
    g.nx = nx;
    g.ny = ny;
    g.x0 = -3.0;
    g.y0 = 2.0;
    g.dx = dx;
    g.dy = 0.5 * dx;
    g.z.resize(nx * ny);
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i)
            g.at(i, j) = f(g.x0 + static_cast<double>(i) * g.dx, g.y0 + static_cast<double>(j) * g.dy);
    return g;
}

TEST(Bicubic, ReproducesPlanesExactlyUpToTheBorder) {
    auto plane = [](double x, double y) { return -2.0 + 0.3 * x - 0.15 * y; };
    const ElevationGrid g = grid_of(9, 7, 1.0, plane);
    for (double x = g.x0; x <= g.x_max(); x += 0.37)
        for (double y = g.y0; y <= g.y_max(); y += 0.29) {
            const DepthSample s = sample_depth(g, x, y);
            EXPECT_NEAR(s.depth, -plane(x, y), 1e-12);
            EXPECT_NEAR(s.dh_dx, -0.3, 1e-12);
            EXPECT_NEAR(s.dh_dy, 0.15, 1e-12);
            EXPECT_TRUE(s.inside);
        }
}

TEST(Bicubic, InterpolatesNodesAndQuadratics) {
    auto quad = [](double x, double y) { return 0.1 * x * x - 0.2 * x * y + 0.05 * y * y + x; };
    const ElevationGrid g = grid_of(12, 12, 0.5, quad);
    for (std::size_t j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < g.nx; ++i)
            EXPECT_NEAR(depth_at(g, g.x0 + double(i) * g.dx, g.y0 + double(j) * g.dy), -g.at(i, j), 1e-12);
    // Keys' a = −½ kernel is exact for quadratics away from the border cells.
    for (double x = g.x0 + 1.0; x < g.x_max() - 1.0; x += 0.13)
        for (double y = g.y0 + 0.5; y < g.y_max() - 0.5; y += 0.11) {
            const DepthSample s = sample_depth(g, x, y);
            EXPECT_NEAR(s.depth, -quad(x, y), 1e-11);
            EXPECT_NEAR(s.dh_dx, -(0.2 * x - 0.2 * y + 1.0), 1e-10);
            EXPECT_NEAR(s.dh_dy, -(-0.2 * x + 0.1 * y), 1e-10);
        }
}

TEST(Bicubic, OutsideTheGridIsClampedAndFlagged) {
    auto plane = [](double x, double y) { return 0.3 * x + 0.1 * y; };
    const ElevationGrid g = grid_of(5, 5, 1.0, plane);
    const DepthSample s = sample_depth(g, g.x0 - 10.0, g.y0 + 0.5);
    EXPECT_FALSE(s.inside);
    EXPECT_NEAR(s.depth, -plane(g.x0, g.y0 + 0.5), 1e-12);
    EXPECT_EQ(s.dh_dx, 0.0);           // across the clamped border
    EXPECT_NEAR(s.dh_dy, -0.1, 1e-12); // along it, unchanged
    EXPECT_FALSE(sample_depth(g, 0.0, 1e9).inside);
    EXPECT_FALSE(sample_depth(g, NAN, 3.0).inside);
}

TEST(Procedural, PlanarBeachSlopeAndShoreline) {
    PlanarBeachParams p;
    const Seafloor s = make_planar_beach(p);
    // Sea to the south: the shoreline is y = 100 + 60 = 160.
    EXPECT_NEAR(depth_at(s.grid, 50.0, 160.0), 0.0, 1e-12);
    const DepthSample d = sample_depth(s.grid, 80.0, 120.0);
    EXPECT_NEAR(d.depth, 0.05 * 40.0, 1e-12);
    EXPECT_NEAR(d.dh_dy, -0.05, 1e-12);
    EXPECT_NEAR(d.dh_dx, 0.0, 1e-12);
    EXPECT_THROW(make_planar_beach({.slope = -1.0}), InputError);
}

TEST(Procedural, BerkhoffShoalCrestAndShelf) {
    const Seafloor s = make_berkhoff_shoal();
    EXPECT_NEAR(depth_at(s.grid, 0.0, 0.0), 0.45 - 0.02 * 5.82 - 0.2, 1e-12);  // 0.1336 m
    EXPECT_NEAR(depth_at(s.grid, -9.0, 0.0), 0.45, 1e-12);
    // On the 1:50 slope away from the shoal, |∇h| = 0.02 along the rotated x'.
    const DepthSample d = sample_depth(s.grid, 8.0, -8.0);
    // h = 0.45 − 0.02 (5.82 + x') so ∇h = −0.02 ∇x' = −0.02 (cos 20°, −sin 20°).
    EXPECT_NEAR(d.dh_dx, -0.02 * std::cos(20 * std::numbers::pi / 180), 1e-9);
    EXPECT_NEAR(d.dh_dy, 0.02 * std::sin(20 * std::numbers::pi / 180), 1e-9);
}

TEST(Procedural, ConicalIslandOfBriggs) {
    const Seafloor s = make_conical_island();
    EXPECT_NEAR(depth_at(s.grid, 12.5, 15.0), 0.32 - 0.625, 1e-12);
    EXPECT_NEAR(depth_at(s.grid, 0.5, 0.5), 0.32, 1e-12);
    const DepthSample d = sample_depth(s.grid, 12.5 + 2.35, 15.0);  // mid-flank
    EXPECT_NEAR(d.dh_dx, 0.25, 1e-9);  // 1:4
}

TEST(Procedural, BarredBeachBarTroughChannelAndShore) {
    const Seafloor s = make_barred_beach();
    // The plane slope 6 m → 0 at x = 180 m, minus the bar (2 m at x = 70 m, σ = 10 m).
    EXPECT_NEAR(depth_at(s.grid, 0.0, 20.0), 6.0 - 2.0 * std::exp(-0.5 * 49.0), 1e-6);
    EXPECT_NEAR(depth_at(s.grid, 70.0, 20.0), 6.0 * 110.0 / 180.0 - 2.0, 1e-6);  // crest ≈ 1.67 m
    EXPECT_GT(depth_at(s.grid, 95.0, 20.0), 2.6);                                  // the trough behind it
    EXPECT_NEAR(depth_at(s.grid, 70.0, 80.0), 6.0 * 110.0 / 180.0 - 0.6, 1e-6);   // the rip channel: 30 % of the bar
    EXPECT_NEAR(depth_at(s.grid, 180.0, 20.0), 0.0, 1e-6);                        // the shoreline
    EXPECT_NEAR(depth_at(s.grid, 200.0, 20.0), -2.0 / 3.0, 1e-6);                 // land, rising at the slope
    EXPECT_THROW(make_barred_beach({.bar_width = 0.0}), InputError);
}

TEST(Procedural, BayIslandAndTsoContours) {
    const Seafloor bay = make_gonzato_bay();
    EXPECT_EQ(bay.grid.nx, 201u);
    EXPECT_NEAR(bay.grid.x_max(), 100.0, 1e-12);
    EXPECT_NEAR(depth_at(bay.grid, 50.0, 90.0), 0.0, 1e-12);   // bay head on the shoreline
    EXPECT_NEAR(depth_at(bay.grid, 0.0, 55.0), 0.0, 1e-12);    // headland
    EXPECT_NEAR(depth_at(bay.grid, 50.0, 0.0), 5.0, 1e-12);    // open sea, capped
    const Seafloor island = make_gonzato_island();
    EXPECT_LT(depth_at(island.grid, 50.0, 55.0), 0.0);
    EXPECT_NEAR(depth_at(island.grid, 65.0, 55.0), 0.0, 1e-12);  // end of the major axis
    const Seafloor tso = make_tso_contours();
    ASSERT_EQ(tso.contours.size(), 10u);
    EXPECT_EQ(tso.contours.depth.front(), 2.0);
    // Gridding passes through each contour: the grid depth on a contour point equals its depth
    // within the grid's interpolation error.
    const auto& c = tso.contours;
    for (std::size_t p = 0; p < 7; ++p) {
        const std::size_t k = (c.offsets[p] + c.offsets[p + 1]) / 2;
        EXPECT_NEAR(depth_at(tso.grid, c.xy[2 * k], c.xy[2 * k + 1]), c.depth[p], 0.03) << p;
    }
    EXPECT_THROW(make_named_seafloor("atlantis"), InputError);
    for (const auto& n : procedural_seafloor_names()) EXPECT_GE(make_named_seafloor(n).grid.nx, 2u) << n;
}

// --- GDAL rasters --------------------------------------------------------------

TEST(ReadGdal, OkushiriAsciiGrid) {
    const Seafloor s = read_seafloor(kData + "/bathymetry/okushiri_monai_lab1to400_1p4cm.asc");
    EXPECT_EQ(s.grid.nx, 393u);
    EXPECT_EQ(s.grid.ny, 244u);
    EXPECT_DOUBLE_EQ(s.grid.dx, 0.014);
    EXPECT_NEAR(s.grid.x0, 0.007, 1e-12);  // node = cell centre
    EXPECT_NEAR(s.grid.y0, 0.007, 1e-12);
    // The file's first value (north-west cell) is −0.13535 m: elevation under water.
    // (GDAL's AAIGrid driver stores decimal grids as Float32: 1e-7 tolerance.)
    EXPECT_NEAR(s.grid.at(0, s.grid.ny - 1), -0.13535, 1e-7);
    const SeafloorStats st = seafloor_stats(s);
    EXPECT_NEAR(st.depth_max, 0.13535, 1e-6);
    EXPECT_NEAR(st.depth_min, -0.125, 1e-3);
    EXPECT_NEAR(st.land_fraction, 0.10, 0.02);  // "about 10 % land"
    EXPECT_EQ(st.nodata_count, 0u);
}

TEST(ReadGdal, IcelandNetcdfIsReprojectedToLocalMetres) {
    const Seafloor s = read_seafloor(kData + "/bathymetry/iceland_etopo2_gmt.nc");
    EXPECT_NE(s.frame.find("azimuthal equidistant"), std::string::npos) << s.frame;
    // 2 arc-minutes of longitude at 65° N.
    EXPECT_NEAR(s.grid.dx, 2.0 / 60.0 * 6371008.8 * std::numbers::pi / 180.0 * std::cos(65.0 * std::numbers::pi / 180.0), 1.0);
    EXPECT_LT(s.grid.x0, -250e3);  // ≈ ±300 km east–west
    EXPECT_GT(s.grid.x_max(), 250e3);
    EXPECT_GT(-depth_at(s.grid, 0.0, 0.0), 200.0);       // 65° N 19° W: Iceland's highlands
    EXPECT_GT(depth_at(s.grid, 0.0, 210e3), 50.0);        // ~66.9° N: the shelf north of the coast
}

TEST_F(Scratch, AsciiGridNodataSignScaleAndPolicies) {
    const std::string asc = write("g.asc",
        "ncols 3\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 2\nNODATA_value -9999\n"
        "1 2 -9999\n4 5 6\n");
    ReadOptions o;
    o.sign = ValueSign::depth;
    o.vertical_scale = 0.5;
    const Seafloor s = read_seafloor(asc, o);
    EXPECT_EQ(s.nodata_count, 1u);
    EXPECT_DOUBLE_EQ(s.grid.at(0, 0), -2.0);  // south row "4 5 6", depth 4·0.5
    EXPECT_DOUBLE_EQ(s.grid.at(2, 1), 1.0);   // NODATA -> land at +1 m
    EXPECT_DOUBLE_EQ(s.grid.x0, 11.0);
    o.nodata_policy = NodataPolicy::error;
    expect_input_error([&] { read_seafloor(asc, o); }, {asc, "row 1, column 3", "NODATA"});
}

TEST_F(Scratch, BrokenRastersGiveClearErrors) {
    expect_input_error([&] { read_seafloor((dir_ / "nope.asc").string()); }, {"nope.asc", "not found"});
    const std::string nan = write("nan.asc", "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1.5 nan\n3 4\n");
    expect_input_error([&] { read_seafloor(nan); }, {nan, "row 1, column 2", "not a finite"});
    const std::string trunc = write("t.asc", "ncols 4\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3 4\n5 6\n");
    expect_input_error([&] { read_seafloor(trunc); }, {trunc});
    const std::string empty = write("e.asc", "");
    expect_input_error([&] { read_seafloor(empty); }, {empty, "GDAL cannot read"});
    const std::string one = write("one.asc", "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n7\n");
    expect_input_error([&] { read_seafloor(one); }, {one, "at least 2 x 2"});
    ReadOptions small;
    small.max_nodes = 10;
    expect_input_error([&] { read_seafloor(kData + "/bathymetry/okushiri_monai_lab1to400_1p4cm.asc", small); },
                       {"393 x 244", "max_nodes"});
}

// --- SWAN .bot -----------------------------------------------------------------

ReadOptions haringvliet_options() {
    ReadOptions o;
    o.swan_nx = 88;
    o.swan_ny = 117;
    o.swan_dx = 250.0;
    o.nodata_value = -99.0;
    return o;
}

TEST(ReadSwan, Haringvliet) {
    const Seafloor s = read_seafloor(kData + "/bathymetry/haringvliet_swan_f31hari_250m.bot", haringvliet_options());
    EXPECT_EQ(s.grid.nx, 88u);
    EXPECT_EQ(s.grid.ny, 117u);
    EXPECT_DOUBLE_EQ(s.grid.dy, 250.0);
    EXPECT_DOUBLE_EQ(s.grid.at(0, 0), -22.5);  // first value: depth 22.5 m at y = 0
    EXPECT_DOUBLE_EQ(s.grid.at(1, 0), -22.2);
    EXPECT_GT(s.nodata_count, 0u);             // −99 marks dry cells
    const SeafloorStats st = seafloor_stats(s);
    EXPECT_LE(st.depth_max, 30.0);
}

TEST_F(Scratch, SwanErrors) {
    const std::string bot = write("b.bot", "1 2 3\n4 5 x6\n");
    ReadOptions o;
    expect_input_error([&] { read_seafloor(bot, o); }, {bot, "--swan-grid"});
    o.swan_nx = 3;
    o.swan_ny = 2;
    o.swan_dx = 10.0;
    expect_input_error([&] { read_seafloor(bot, o); }, {bot, "line 2", "'x6' is not a number"});
    const std::string shorter = write("s.bot", "1 2 3\n4 5\n");
    expect_input_error([&] { read_seafloor(shorter, o); }, {shorter, "truncated", "3 x 2 = 6", "found 5"});
    const std::string longer = write("l.bot", "1 2 3\n4 5 6 7\n");
    expect_input_error([&] { read_seafloor(longer, o); }, {longer, "more values"});
    const std::string inf = write("i.bot", "1 2 3\n4 inf 6\n");
    expect_input_error([&] { read_seafloor(inf, o); }, {inf, "row 2, value 2", "not a finite"});
}

// --- meshes --------------------------------------------------------------------

TEST_F(Scratch, MeshIsKeptAndResampled) {
    // A 10 m × 6 m plane z = −1 − 0.2 x as two triangles (OFF), and the same as OBJ quads.
    const std::string off = write("plane.off",
        "OFF\n4 2 0\n0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 2\n3 0 2 3\n");
    ReadOptions o;
    o.resample_spacing = 0.5;
    const Seafloor s = read_seafloor(off, o);
    EXPECT_EQ(s.mesh.triangles.size(), 6u);
    EXPECT_EQ(s.grid.nx, 21u);
    EXPECT_EQ(s.grid.ny, 13u);
    EXPECT_EQ(s.nodata_count, 0u);
    for (double x = 0.3; x < 9.7; x += 0.9)
        EXPECT_NEAR(depth_at(s.grid, x, 2.7), 1.0 + 0.2 * x, 1e-12);
    const std::string obj = write("quad.obj", "v 0 0 -1\nv 10 0 -3\nv 10 6 -3\nv 0 6 -1\nf 1 2 3 4\n");
    EXPECT_EQ(read_seafloor(obj, o).mesh.triangles.size(), 6u);
}

// A seafloor from arrays in memory (a DCC's terrain): an analytic plane z = a + b x + c y
// handed over as a grid and as triangles gives the plane's depth everywhere inside,
// with the water level as a vertical offset; the grid's node (0, 0) is at the origin,
// the convention the ESRI reader lands on (a cell's value at its centre).
TEST_F(Scratch, SeafloorFromArraysHoldsAnAnalyticPlane) {
    const auto plane = [](double x, double y) { return -4.0 + 0.03 * x + 0.05 * y; };
    ElevationGrid g = grid_of(41, 61, 0.5, plane);  // origin (−3, 2), dx 0.5, dy 0.25
    ReadOptions level;
    level.vertical_offset = -0.7;  // still water at z = 0.7
    const Seafloor from_grid = seafloor_from_grid(g, {}, level, "plane grid");
    const Seafloor from_mesh = seafloor_from_mesh(
        std::vector<double>{-3, 2, plane(-3, 2), 17, 2, plane(17, 2), 17, 17, plane(17, 17), -3, 17, plane(-3, 17)},
        std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}, [&] { ReadOptions o = level; o.resample_spacing = 0.4; return o; }(),
        "plane mesh");
    EXPECT_EQ(from_grid.source, "plane grid");
    EXPECT_EQ(from_mesh.mesh.triangles.size(), 6u);
    EXPECT_EQ(from_mesh.nodata_count, 0u);
    for (double x = -2.9; x < 16.9; x += 1.37)
        for (double y = 2.1; y < 16.9; y += 1.91) {
            const double h = 0.7 - plane(x, y);
            if (y <= g.y_max()) {
                EXPECT_NEAR(depth_at(from_grid.grid, x, y), h, 1e-12) << x << ", " << y;
            }
            EXPECT_NEAR(depth_at(from_mesh.grid, x, y), h, 1e-12) << x << ", " << y;
        }
    // An ESRI grid of the same values: its first cell's centre is node (0, 0), so the
    // grid read from the file and the one from arrays at that origin agree to the node.
    std::string asc = "ncols 3\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 2\n";
    asc += "-1 -2 -3\n-4 -5 -6\n";  // north row first
    const Seafloor read = read_seafloor(write("g.asc", asc));
    ElevationGrid mine;
    mine.nx = 3, mine.ny = 2, mine.x0 = read.grid.x0, mine.y0 = read.grid.y0, mine.dx = 2.0, mine.dy = 2.0;
    mine.z = {-4, -5, -6, -1, -2, -3};  // south row first
    const Seafloor same = seafloor_from_grid(mine);
    EXPECT_DOUBLE_EQ(read.grid.x0, 11.0);
    EXPECT_DOUBLE_EQ(read.grid.y0, 21.0);
    for (double x : {11.0, 12.3, 15.0})
        for (double y : {21.0, 22.2, 23.0}) EXPECT_DOUBLE_EQ(depth_at(same.grid, x, y), depth_at(read.grid, x, y));
    // The plane as a DCC holds a terrain object turned by 90° about z, in float32: a 40 × 40
    // grid of quads whose turned coordinates carry the rounding of cos 90° in float32
    // (−4.4e-8 · 100 m: its border vertices up to 4.4 µm inside the bounding box the grid
    // spans). Nodes a rounding outside a border triangle take its plane: no node is left
    // without data (the whole border was, a ring of land round the sea).
    {
        std::vector<double> xyz;
        std::vector<std::uint32_t> tri;
        const float c = std::cos(static_cast<float>(std::numbers::pi / 2)), s = 1.0f;
        for (int j = 0; j <= 40; ++j)
            for (int i = 0; i <= 40; ++i) {
                const float u = 2.5f * static_cast<float>(i), v = 2.5f * static_cast<float>(j);
                const double x = 37.0f + (c * u - s * v), y = -11.0f + (s * u + c * v);
                xyz.insert(xyz.end(), {x, y, static_cast<float>(plane(x, y))});
            }
        for (std::uint32_t j = 0; j < 40; ++j)
            for (std::uint32_t i = 0; i < 40; ++i) {
                const std::uint32_t a = j * 41 + i;
                tri.insert(tri.end(), {a, a + 1, a + 42, a, a + 42, a + 41});
            }
        ASSERT_NE(c, 0.0f);
        ReadOptions o;
        o.resample_spacing = 0.5;
        const Seafloor turned = seafloor_from_mesh(xyz, tri, o, "turned terrain");
        EXPECT_EQ(turned.nodata_count, 0u);
        const ElevationGrid& t = turned.grid;
        for (double x : {t.x0, t.x_max()})
            for (double y : {t.y0, t.y_max()}) EXPECT_NEAR(depth_at(t, x, y), -plane(x, y), 1e-4) << x << ", " << y;
    }
    expect_input_error([&] { ElevationGrid bad = mine; bad.dy = 0.0; seafloor_from_grid(bad, {}, {}, "terrain"); },
                       {"terrain", "spacing along y"});
    expect_input_error([&] { seafloor_from_mesh(std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0},
                                                std::vector<std::uint32_t>{0, 1, 3}, {}, "terrain"); },
                       {"terrain", "triangle 1 names vertex 4 of 3"});
}

TEST_F(Scratch, BrokenMeshes) {
    const std::string none = write("none.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
    expect_input_error([&] { read_seafloor(none); }, {none, "no triangles"});
    const std::string junk = write("junk.ply", "this is not a mesh\n");
    expect_input_error([&] { read_seafloor(junk); }, {junk, "not a readable"});
    expect_input_error([&] { read_seafloor((dir_ / "gone.stl").string()); }, {"gone.stl", "not found"});
    // A directory opens as an empty stream: it is named for what it is, not as a malformed file.
    for (const char* name : {"d.ply", "d.off", "d.obj", "d.json", "d.bot"}) {
        const auto d = dir_ / name;
        std::filesystem::create_directory(d);
        ReadOptions o;
        o.swan_nx = o.swan_ny = 2;
        o.swan_dx = 1.0;
        expect_input_error([&] { read_seafloor(d.string(), o); }, {d.string(), "a directory, not a file"});
    }
}

// CGAL's OFF scanner casts what it reads to size_t (tests/fuzz): the OFF family is
// checked first. Spellings of the family read as the plain file; anything else is
// refused by line.
TEST_F(Scratch, OffIsPlainlyOffBeforeCgalReadsIt) {
    const char* body = "0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 2\n3 0 2 3\n";
    const std::string plain = write("p.off", std::string("OFF\n4 2 0\n") + body);
    const std::size_t triangles = read_seafloor(plain).mesh.triangles.size();
    ASSERT_EQ(triangles, 6u);
    // Counts on the keyword's line, comments, and colours per vertex and facet (COFF).
    const std::string inline_counts = write("i.off", std::string("# a plane\nOFF 4 2 0 # counts\n") + body);
    EXPECT_EQ(read_seafloor(inline_counts).mesh.triangles.size(), triangles);
    const std::string coloured = write("c.off", "COFF\n4 2 0\n0 0 -1 255 0 0 255\n10 0 -3 0 255 0 255\n"
                                                "10 6 -3 0 0 255 255\n0 6 -1 9 9 9 255\n3 0 1 2 1 0 0\n3 0 2 3 0 0 1\n");
    EXPECT_EQ(read_seafloor(coloured).mesh.triangles.size(), triangles);
    const struct {
        const char *name, *text, *named;
    } refused[] = {
        {"word.off", "OFFICE\n4 2 0\n", "'OFFICE' is not an OFF header keyword"},
        {"glued.off", "STOFF#01\n0 0 33\n", "line 1: 'STOFF' must be followed by a space or the end of the line"},
        {"two.off", "OFF\n4 2\n", "line 2: expected the vertex, facet and edge counts"},
        {"float.off", "OFF\n4.5 2 0\n", "line 2: expected the vertex, facet and edge counts"},
        {"huge.off", "OFF\n4 99999999 0\n", "line 2: expected the vertex, facet and edge counts"},
        {"edges.off", "OFF\n4 2 0001557324494\n", "line 2: expected the vertex, facet and edge counts"},
        {"short.off", "OFF\n4 2 0\n0 0 -1\n10 0\n", "line 4: vertex 2 has 2 numbers where OFF needs 3"},
        {"texture.off", "STCOFF\n4 2 0\n0 0 -1 0.5\n", "line 3: vertex 1 has 4 numbers where STCOFF needs 5"},
        {"st.off", "STOFF\n4 2 0\n0 0 -1 0.5 0.5\n", "line 1: 'STOFF': CGAL 5.5 cannot read texture coordinates without colours"},
        {"colour.off", "COFF\n4 2 0\n0 0 -1 1 2\n", "line 3: vertex 1 has 5 numbers where COFF needs 3 (+ a colour of 1, 3 or 4)"},
        {"cmap.off", "COFF\n4 2 0\n0 0 -1 -3\n", "line 3: vertex 1: the colour is neither a colour-map index 0 … 148"},
        {"rgb.off", "COFF\n4 2 0\n0 0 -1 300 0 0\n", "line 3: vertex 1: the colour is neither"},
        {"some.off", "COFF\n4 2 0\n0 0 -1 7\n10 0 -3\n", "line 4: vertex 2 has no colour, unlike vertex 1"},
        {"facet.off", "COFF\n4 2 0\n0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 2 1 0 0\n3 0 2 3 4 4\n",
         "line 8: facet 2: a colour of 2 numbers"},
        {"index.off", "OFF\n4 2 0\n0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 4\n3 0 2 3\n",
         "line 7: facet vertex index '4' is not a whole number in [0, 4)"},
        {"negative.off", "OFF\n4 2 0\n0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 2\n3 -1 2 3\n",
         "line 8: facet vertex index '-1'"},
        {"fraction.off", "OFF\n4 2 0\n0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 2\n3 0 2.5 3\n",
         "line 8: facet vertex index '2.5'"},
        {"ends.off", "OFF\n4 2 0\n0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 2\n", "the file ends before facet 2 of 2"},
    };
    for (const auto& r : refused) {
        const std::string path = write(r.name, r.text);
        expect_input_error([&] { read_seafloor(path); }, {path, r.named});
    }
    // The fuzzer's finding: a NUL before the keyword, which CGAL read on regardless.
    static constexpr char kNulFirst[] = "\0OFF 0 2-0 -30  2\n3 ";
    const std::string nul = write("nul.off", std::string(kNulFirst, sizeof kNulFirst - 1));
    expect_input_error([&] { read_seafloor(nul); }, {nul, "line 1:", "is not an OFF header keyword"});
    // Binary OFF: CGAL 5.5 reads no facet's colour count and so read this two-triangle
    // plane as one triangle; counts near 2^31 overflowed its header (the fuzzer). Refused
    // by name, with the formats that do read.
    std::string binary = "OFF BINARY\n";
    const auto put = [&](std::uint32_t bits) {
        for (int shift = 24; shift >= 0; shift -= 8) binary += static_cast<char>((bits >> shift) & 0xFFu);
    };
    for (const std::uint32_t count : {4u, 2u, 0u}) put(count);
    for (const float c : {0.f, 0.f, -1.f, 10.f, 0.f, -3.f, 10.f, 6.f, -3.f, 0.f, 6.f, -1.f}) put(std::bit_cast<std::uint32_t>(c));
    for (const std::uint32_t i : {3u, 0u, 1u, 2u, 0u, 3u, 0u, 2u, 3u, 0u}) put(i);  // each facet ends with 0 colours
    const std::string bin = write("binary.off", binary);
    expect_input_error([&] { read_seafloor(bin); }, {bin, "line 1: binary OFF is not read", "PLY"});
}

// CGAL's PLY reader sizes each list from a count it reads unchecked (tests/fuzz): the
// data is walked first, as CGAL reads it. ASCII and both binary byte orders read; a
// count or value that is not there or does not fit is refused, named by element, item
// and property.
TEST_F(Scratch, PlyIsWalkedBeforeCgalReadsIt) {
    const std::string header = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                               "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string ascii = write("a.ply", "ply\nformat ascii 1.0\ncomment a plane\n" + header +
                                             "0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n3 0 1 2\n3 0 2 3\n");
    const Seafloor plane = read_seafloor(ascii);
    ASSERT_EQ(plane.mesh.triangles.size(), 6u);
    // The same plane in binary, both byte orders (x y z float32, then uint8 count and int32 indices).
    const auto binary = [&](bool little) {
        std::string data = "ply\nformat " + std::string(little ? "binary_little_endian" : "binary_big_endian") + " 1.0\n" + header;
        const auto put = [&](const void* v, std::size_t n) {
            const auto* b = static_cast<const char*>(v);
            for (std::size_t k = 0; k < n; ++k) data += b[little ? k : n - 1 - k];  // the host is little-endian
        };
        for (const float f : {0.f, 0.f, -1.f, 10.f, 0.f, -3.f, 10.f, 6.f, -3.f, 0.f, 6.f, -1.f}) put(&f, 4);
        for (const std::array<std::int32_t, 3> face : {std::array{0, 1, 2}, std::array{0, 2, 3}}) {
            data += '\3';
            for (const std::int32_t i : face) put(&i, 4);
        }
        return data;
    };
    for (const bool little : {true, false}) {
        const std::string path = write(little ? "le.ply" : "be.ply", binary(little));
        const Seafloor s = read_seafloor(path);
        EXPECT_EQ(s.mesh.triangles, plane.mesh.triangles) << path;
        EXPECT_EQ(s.mesh.xyz, plane.mesh.xyz) << path;
    }
    // What other tools write: CRLF lines, obj_info, normals, colours, texture coordinates,
    // a leading '+', an edge element, 'vertex_index' with uint32 indices (MeshLab, Blender).
    const std::string rich = write("rich.ply",
        "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info a plane\r\nelement vertex 4\r\n"
        "property float x\r\nproperty float y\r\nproperty float z\r\nproperty float nx\r\nproperty float ny\r\n"
        "property float nz\r\nproperty uchar red\r\nproperty uchar green\r\nproperty uchar blue\r\n"
        "property float s\r\nproperty float t\r\nelement face 2\r\nproperty list uint8 uint32 vertex_index\r\n"
        "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\nend_header\r\n"
        "0 0 -1 0 0 1 255 0 0 0 0\r\n10 0 -3 0 0 1 0 255 0 1 0\r\n+10 6 -3 0 0 1 0 0 255 1 1\r\n"
        "0 6 -1.0e0 0 0 1 9 9 9 0 1\r\n3 0 1 2\r\n3 0 2 3\r\n0 1\r\n");
    const Seafloor from_rich = read_seafloor(rich);
    EXPECT_EQ(from_rich.mesh.triangles, plane.mesh.triangles);
    EXPECT_EQ(from_rich.mesh.xyz, plane.mesh.xyz);
    const std::string vertices = "0 0 -1\n10 0 -3\n10 6 -3\n0 6 -1\n";
    const std::string int_counts = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                                   "element face 2\nproperty list int int vertex_indices\nend_header\n";
    std::string truncated = binary(true);
    truncated.resize(truncated.size() - 3);
    std::string huge_count = binary(true);
    huge_count[huge_count.size() - 13] = '\xFF';  // the second face's uint8 count: 255 indices, 3 there
    const struct {
        const char *name;
        std::string text;
        const char* named;
    } refused[] = {
        {"format.ply", "ply\nformat text 1.0\n" + header, "line 2: the PLY format 'text' is none of ascii"},
        // Types CGAL would dereference as others (a segfault in release builds).
        {"int.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty int x\nproperty int y\nproperty int z\nend_header\n",
         "PLY element 'vertex': property 'x' must be a float or double (a coordinate)"},
        {"colour.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                       "property uchar red\nproperty float green\nproperty uchar g\nproperty uchar blue\nend_header\n",
         "PLY element 'vertex': property 'green' must be a uchar, as red is (a colour channel)"},
        {"halfedge.ply", "ply\nformat ascii 1.0\nelement halfedge 1\nproperty float source\nproperty uint target\nend_header\n0 1\n",
         "PLY element 'halfedge': property 'source' must be a uint (a vertex number)"},
        {"blank.ply", "ply\nformat ascii 1.0\n\n" + header, "line 3: an empty line in the PLY header"},
        {"ends.ply", "ply\nformat ascii 1.0\n" + header + vertices + "3 0 1 2\n",
         "PLY element 'face' 2 of 2, property 'vertex_indices': the file ends before its data"},
        {"short.ply", "ply\nformat ascii 1.0\n" + header + vertices + "3 0 1 2\n3 0 2\n",
         "PLY element 'face' 2 of 2, property 'vertex_indices': the file ends"},
        {"uchar.ply", "ply\nformat ascii 1.0\n" + header + vertices + "3 0 1 2\n-3 0 2 3\n",
         "'face' 2 of 2, property 'vertex_indices': '-3' is not a whole number of type uchar (0 … 255)"},
        {"negative.ply", "ply\nformat ascii 1.0\n" + int_counts + vertices + "3 0 1 2\n-3 0 2 3\n",
         "'face' 2 of 2, property 'vertex_indices': the list count -3 is negative"},
        {"value.ply", "ply\nformat ascii 1.0\n" + header + "0 0 -1\n10 zero -3\n", "'vertex' 2 of 4, property 'y': 'zero' is not a number"},
        {"index.ply", "ply\nformat ascii 1.0\n" + header + vertices + "3 0 1 2\n3 0 2.5 3\n",
         "'face' 2 of 2, property 'vertex_indices': '2.5' is not a whole number of type int"},
        {"truncated.ply", truncated, "PLY element 'face' 2 of 2, property 'vertex_indices': the file ends"},
        {"count.ply", huge_count, "PLY element 'face' 2 of 2, property 'vertex_indices': the file ends"},
    };
    for (const auto& r : refused) {
        const std::string path = write(r.name, r.text);
        expect_input_error([&] { read_seafloor(path); }, {path, r.named});
    }
}

// --- contour files -------------------------------------------------------------

TEST_F(Scratch, ContoursAreGriddedLinearlyBetweenIsobaths) {
    const std::string json = write("c.json", R"({"contours": [
        {"depth": 4.0, "points": [[0, 0], [20, 0]]},
        {"depth": 1.0, "points": [[0, 10], [20, 10]]},
        {"depth": 0.0, "points": [[0, 15], [10, 15], [20, 15]]}]})");
    ReadOptions o;
    o.resample_spacing = 0.5;
    const Seafloor s = read_seafloor(json, o);
    ASSERT_EQ(s.contours.size(), 3u);
    for (double y = 0.0; y <= 10.0; y += 0.5) EXPECT_NEAR(depth_at(s.grid, 7.0, y), 4.0 - 0.3 * y, 1e-9) << y;
    for (double y = 10.0; y <= 15.0; y += 0.5) EXPECT_NEAR(depth_at(s.grid, 7.0, y), 1.0 - 0.2 * (y - 10.0), 1e-9) << y;
}

TEST_F(Scratch, BrokenContourFiles) {
    const std::string bad_depth = write("d.json", R"({"contours": [
        {"depth": 1, "points": [[0,0],[1,0]]}, {"depth": "deep", "points": [[0,1],[1,1]]}]})");
    expect_input_error([&] { read_seafloor(bad_depth); }, {bad_depth, "/contours/1/depth", "expected a number", "\"deep\""});
    const std::string bad_point = write("p.json", R"({"contours": [{"depth": 1, "points": [[0,0],[1]]}]})");
    expect_input_error([&] { read_seafloor(bad_point); }, {"/contours/0/points/1"});
    const std::string empty = write("e.json", R"({"contours": []})");
    expect_input_error([&] { read_seafloor(empty); }, {empty, "empty"});
    const std::string broken = write("b.json", R"({"contours": [)");
    expect_input_error([&] { read_seafloor(broken); }, {broken, "not valid JSON"});
}


// The terrain beyond the data (the exported seafloor's apron): continuous with the
// border, the border's detail fading to its trend, land above still water, sea bottom
// below it away from the shore.
TEST(TerrainBeyond, MeetsTheBorderAndFadesItsDetailWithDistance) {
    const Seafloor bay = make_gonzato_bay();
    const ElevationGrid& g = bay.grid;
    TerrainBeyondOptions flat;
    flat.relief = 1e-9;  // the trend alone
    const TerrainBeyond t = plan_terrain_beyond(g, flat);
    // On the border and a millimetre beyond: the grid's own values.
    for (std::size_t i = 0; i < g.nx; i += 7) {
        const double x = g.x0 + static_cast<double>(i) * g.dx;
        EXPECT_DOUBLE_EQ(terrain_elevation(t, x, g.y0, 1.0), g.at(i, 0));
        EXPECT_NEAR(terrain_elevation(t, x, g.y_max() + 1e-3, 1.0), g.at(i, g.ny - 1), 1e-3);
        EXPECT_NEAR(terrain_elevation(t, x, g.y0 - 1e-3, 1.0), g.at(i, 0), 1e-3);
    }
    // A dip in a border's land (the bay's head dips from 2 m to 1 m: carried unchanged to
    // the horizon, it was the default scene's pale wedge) fades: 200 m back, the window
    // spans the side and the dip is gone. Land all round, 2 m, a 1 m dip 10 m wide.
    ElevationGrid land;
    land.nx = land.ny = 101;
    land.z.assign(101 * 101, 2.0);
    for (std::size_t i = 45; i <= 55; ++i) land.at(i, 100) = 1.0;
    const TerrainBeyond dip = plan_terrain_beyond(land, flat);
    const auto range = [&](double y) {
        double lo = 1e9, hi = -1e9;
        for (double x = 0.0; x <= 100.0; x += 2.5) lo = std::min(lo, terrain_elevation(dip, x, y, 1.0)), hi = std::max(hi, terrain_elevation(dip, x, y, 1.0));
        return hi - lo;
    };
    EXPECT_NEAR(range(100.0), 1.0, 1e-9);
    EXPECT_LT(range(300.0), 0.06);
}

TEST(TerrainBeyond, LandStaysAboveStillWaterAndTheOpenSeaBelowIt) {
    for (const char* name : {"gonzato-bay", "planar-beach", "gonzato-island", "barred-beach"}) {
        const Seafloor s = make_named_seafloor(name);
        const ElevationGrid& g = s.grid;
        const TerrainBeyond t = plan_terrain_beyond(g);
        const double size = std::max(g.x_max() - g.x0, g.y_max() - g.y0);
        // Outward from every border node, at distances from a centimetre to 50 km, on a
        // mesh as coarse as a quarter of the distance (the apron's).
        const auto outward = [&](std::size_t i, std::size_t j, double nx, double ny) {
            const double x = g.x0 + static_cast<double>(i) * g.dx, y = g.y0 + static_cast<double>(j) * g.dy;
            const double z = g.at(i, j);
            // The distance along the border to the shore, where it meets the border.
            double shore = 1e300;
            const double s_here = [&] {
                const double w = g.x_max() - g.x0, h = g.y_max() - g.y0;
                if (ny < 0.0) return x - g.x0;
                if (nx > 0.0) return w + (y - g.y0);
                if (ny > 0.0) return w + h + (g.x_max() - x);
                return 2.0 * w + h + (g.y_max() - y);
            }();
            for (double c : t.shore) shore = std::min({shore, std::abs(s_here - c), t.perimeter - std::abs(s_here - c)});
            for (double d = 0.01; d < 5e4; d *= 1.7) {
                const double e = terrain_elevation(t, x + d * nx, y + d * ny, std::max(0.25 * d, g.dx));
                if (z >= 0.0) {
                    EXPECT_GT(e, 0.0) << name << " land beyond (" << x << ", " << y << ") at " << d << " m";
                } else if (shore > 0.081 * size) {
                    EXPECT_LT(e, 0.0) << name << " sea beyond (" << x << ", " << y << ") at " << d << " m";
                }
                EXPECT_TRUE(std::isfinite(e));
            }
        };
        for (std::size_t i = 0; i < g.nx; i += 3) outward(i, 0, 0.0, -1.0), outward(i, g.ny - 1, 0.0, 1.0);
        for (std::size_t j = 0; j < g.ny; j += 3) outward(0, j, -1.0, 0.0), outward(g.nx - 1, j, 1.0, 0.0);
    }
}

TEST(TerrainBeyond, HillsRiseBehindTheBeachAndFadeWhereTheMeshCannotDrawThem) {
    const Seafloor beach = make_planar_beach();  // land along y = 200 m, 2 m high
    const TerrainBeyond t = plan_terrain_beyond(beach.grid);
    EXPECT_DOUBLE_EQ(t.options.relief, 10.0);  // 5 % of 200 m
    // Behind the beach the land rises by about the relief over rise_distance (100 m).
    double mean = 0.0;
    for (double x = 0.0; x <= 200.0; x += 5.0) mean += terrain_elevation(t, x, 200.0 + 100.0, 1.0) / 41.0;
    EXPECT_GT(mean, 2.0 + 0.4 * t.options.relief);
    // The same seed, the same hills; resolution coarser than every octave: the trend alone.
    const TerrainBeyond again = plan_terrain_beyond(beach.grid);
    EXPECT_EQ(terrain_elevation(t, 37.0, 480.0, 2.0), terrain_elevation(again, 37.0, 480.0, 2.0));
    // A hundred metres back, the side's land (2 m) in the window, the rise complete.
    TerrainBeyondOptions other;
    other.seed = 2;
    EXPECT_NE(terrain_elevation(t, 37.0, 480.0, 2.0), terrain_elevation(plan_terrain_beyond(beach.grid, other), 37.0, 480.0, 2.0));
    const double smooth_a = terrain_elevation(t, 80.0, 300.0, 2000.0), smooth_b = terrain_elevation(t, 120.0, 300.0, 2000.0);
    EXPECT_NEAR(smooth_a, smooth_b, 1e-9);  // no hills: the border's trend (flat land) and the rise
    EXPECT_NEAR(smooth_a, 2.0 + t.options.relief, 1e-9);
}

TEST(TerrainBeyond, FarLandRisesIntoRangesWithABrokenSkylineButNotBesideTheCuts) {
    // The planar beach: land along y = 200 m, the shoreline meeting both x sides (the
    // far field's cuts run out along ∓x there). 20 km out, on the apron's mesh (edges a
    // tenth of the distance), the land north of it stands 0.6–4.6 % of the distance high
    // (a constant angle seen from the grid), and its skyline rises and falls by at least
    // 1 % of it: not the straight top of a plateau (the gallery's "dead-straight line").
    const Seafloor beach = make_planar_beach();
    const ElevationGrid& g = beach.grid;
    const TerrainBeyond t = plan_terrain_beyond(g);
    ASSERT_EQ(t.shore.size(), 2u);
    const double cx = 0.5 * (g.x0 + g.x_max()), cy = 0.5 * (g.y0 + g.y_max()), r = 20000.0;
    double lo = 1e300, hi = -1e300;
    for (double a = 60.0; a <= 120.0; a += 0.5) {
        const double th = a * std::numbers::pi / 180.0;
        const double z = terrain_elevation(t, cx + r * std::cos(th), cy + r * std::sin(th), 0.1 * r);
        lo = std::min(lo, z), hi = std::max(hi, z);
    }
    EXPECT_GT(lo, 0.006 * (r - 0.5 * 200.0) * 0.9);
    EXPECT_LT(hi, 0.046 * r + 2.0 + 2.0 * t.options.relief);
    EXPECT_GT(hi - lo, 0.01 * r);
    // Beside a cut (500 m off the line out from where the shoreline meets x = 0, on the
    // land's side), no range: the land there is the low coast, not a wall along the
    // water's straight edge.
    double cut_y = 0.0;  // where the shoreline meets the side x = x0 (perimeter 2w + h … 2w + 2h)
    for (double c : t.shore)
        if (c > 2.0 * (g.x_max() - g.x0) + (g.y_max() - g.y0) - 1e-9) cut_y = g.y_max() - (c - 2.0 * (g.x_max() - g.x0) - (g.y_max() - g.y0));
    EXPECT_LT(terrain_elevation(t, g.x0 - r, cut_y + 500.0, 0.1 * r), 3.0 + 2.0 * t.options.relief);
    // Resolution coarser than every harmonic: the ranges' mean height alone (0.6 % +
    // half of 4 % of d), the same all round (no aliased crests on a mesh too coarse to
    // draw them).
    const auto far_at = [&](double x) { return std::hypot(x - std::clamp(x, g.x0, g.x_max()), cy + r - g.y_max()); };
    for (const double x : {cx, cx + 0.3 * r})
        EXPECT_NEAR(terrain_elevation(t, x, cy + r, 10.0 * r), 0.026 * far_at(x), 0.002 * r + 3.0 + 2.0 * t.options.relief);
}

}  // namespace
