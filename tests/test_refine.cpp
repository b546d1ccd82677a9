// OpenSubdiv refinement: counts, affine invariance (a plane stays a plane), the
// domain's boundary kept, orientation, determinism, limits and scene wiring.
#include <gtest/gtest.h>

#include "libwave/errors.h"
#include "libwave/scene.h"
#include "libwave/surface.h"
#include "libwave/beta_spline.h"

#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

using namespace wave;

namespace {

struct Grid {
    std::vector<float> p;  // 3 per vertex
    std::vector<std::uint32_t> tris;
    std::size_t nx, ny;
};

// A tilted plane z = 0.3x − 0.2y + 1 sampled on an nx × ny grid of spacing 2 m.
Grid plane(std::size_t nx, std::size_t ny) {
    Grid g{{}, grid_triangles(nx, ny), nx, ny};
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
            const float x = 2.0f * static_cast<float>(i), y = 2.0f * static_cast<float>(j);
            g.p.insert(g.p.end(), {x, y, 0.3f * x - 0.2f * y + 1.0f});
        }
    return g;
}

}  // namespace

TEST(Refine, LoopCountsAndAPlaneStaysAPlane) {
    const Grid g = plane(9, 7);
    for (int level : {1, 2, 3}) {
        const Refinement r = plan_refinement(g.nx * g.ny, g.tris, {RefineScheme::loop, level});
        const std::size_t s = std::size_t{1} << level;
        // Loop on a triangulated grid: every edge gets a midpoint each level.
        EXPECT_EQ(r.fine_vertices, (s * (g.nx - 1) + 1) * (s * (g.ny - 1) + 1));
        EXPECT_EQ(r.triangle_count(), g.tris.size() / 3 * s * s);
        for (std::size_t v = 0; v < r.fine_vertices; ++v) {
            double w = 0.0;
            for (std::uint32_t i = r.stencil_offsets[v]; i < r.stencil_offsets[v + 1]; ++i) w += r.stencil_weights[i];
            ASSERT_NEAR(w, 1.0, 1e-6) << "stencil " << v;  // affine: weights sum to one
        }
        std::vector<float> fine(3 * r.fine_vertices);
        apply_refinement(r, g.p, 3, fine);
        for (std::size_t v = 0; v < r.fine_vertices; ++v)
            ASSERT_NEAR(fine[3 * v + 2], 0.3f * fine[3 * v] - 0.2f * fine[3 * v + 1] + 1.0f, 2e-5) << "vertex " << v;
        // Counter-clockwise from +z like the coarse grid, no degenerate triangle.
        for (std::size_t t = 0; t < r.triangle_count(); ++t) {
            const auto a = 3 * r.triangles[3 * t], b = 3 * r.triangles[3 * t + 1], c = 3 * r.triangles[3 * t + 2];
            ASSERT_GT((fine[b] - fine[a]) * (fine[c + 1] - fine[a + 1]) - (fine[c] - fine[a]) * (fine[b + 1] - fine[a + 1]), 1e-6f);
        }
        // The domain's corners stay where they are (boundary edges and corners sharp).
        float xmax = 0, ymax = 0;
        for (std::size_t v = 0; v < r.fine_vertices; ++v) {
            xmax = std::max(xmax, fine[3 * v]);
            ymax = std::max(ymax, fine[3 * v + 1]);
        }
        EXPECT_FLOAT_EQ(xmax, 16.0f);
        EXPECT_FLOAT_EQ(ymax, 12.0f);
    }
}

TEST(Refine, CatmullClarkSplitsTrianglesIntoQuadsThenTwoTriangles) {
    const Grid g = plane(5, 4);
    const std::size_t V = g.nx * g.ny, F = g.tris.size() / 3;
    const std::size_t E = (g.nx - 1) * g.ny + g.nx * (g.ny - 1) + (g.nx - 1) * (g.ny - 1);  // + one diagonal per cell
    const Refinement r = plan_refinement(V, g.tris, {RefineScheme::catmull_clark, 1});
    EXPECT_EQ(r.fine_vertices, V + E + F);  // a point per vertex, edge and face
    EXPECT_EQ(r.triangle_count(), 3 * F * 2);
    std::vector<float> fine(3 * r.fine_vertices);
    apply_refinement(r, g.p, 3, fine);
    for (std::size_t v = 0; v < r.fine_vertices; ++v)
        ASSERT_NEAR(fine[3 * v + 2], 0.3f * fine[3 * v] - 0.2f * fine[3 * v + 1] + 1.0f, 2e-5);
}

TEST(Refine, SmoothsACreaseAndIsIndependentOfTheThreadCount) {
    Grid g = plane(21, 21);
    for (std::size_t v = 0; v < g.p.size() / 3; ++v) g.p[3 * v + 2] = (v % 21 == 10) ? 1.0f : 0.0f;  // a ridge
    const Refinement r = plan_refinement(21 * 21, g.tris, {RefineScheme::loop, 2});
    std::vector<float> many(3 * r.fine_vertices), one(3 * r.fine_vertices);
    apply_refinement(r, g.p, 3, many);
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        apply_refinement(r, g.p, 3, one);
    }
    EXPECT_EQ(std::memcmp(many.data(), one.data(), many.size() * sizeof(float)), 0);
    float top = 0.0f;
    for (std::size_t v = 0; v < r.fine_vertices; ++v) top = std::max(top, many[3 * v + 2]);
    EXPECT_LT(top, 1.0f) << "an approximating scheme rounds the ridge";
    EXPECT_GT(top, 0.3f);
}

TEST(Refine, RefusesBadLevelsAndHugeResultsBeforeAllocating) {
    const Grid g = plane(101, 101);
    EXPECT_THROW(plan_refinement(101 * 101, g.tris, {RefineScheme::loop, 0}), InputError);
    EXPECT_THROW(plan_refinement(101 * 101, g.tris, {RefineScheme::loop, 7}), InputError);
    try {
        plan_refinement(101 * 101, g.tris, {RefineScheme::loop, 6}, 1'000'000);
        FAIL() << "no LimitError";
    } catch (const LimitError& e) {
        EXPECT_NE(std::string(e.what()).find("use level 3"), std::string::npos) << e.what();
    }
    const std::vector<std::uint32_t> bad{0, 1, 99};
    EXPECT_THROW(plan_refinement(3, bad, {}), InputError);
}

TEST(Refine, SceneRefinesTheExportedSurface) {
    const char* text = R"({"seafloor": {"source": "gonzato-bay"}, "waves": [{"period": 5, "amplitude": 0.3}],
      "trace": {"ray_spacing": 4}, "fronts": {"step": 1.5, "split_distance": 6},
      "refine": {"scheme": "loop", "level": 1}, "animation": {"fps": 4}})";
    const Scene scene = parse_scene(text, "r.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const SceneAnimation a = animate_scene(scene, plan, 2e9, {0, 2});
    EXPECT_EQ(a.vertex_count, plan.refinement.fine_vertices);
    ASSERT_GT(plan.water_mesh.vertex_count(), 0u);  // the exported surface: the water mesh by default
    EXPECT_EQ(a.triangles.size(), 4 * (plan.water_mesh.triangles.size() + plan.skirt.triangles.size()));  // and its far field
    EXPECT_EQ(a.foam.size(), 2 * a.vertex_count);
    // The coarse vertices' refined positions follow the coarse frame: stencils applied
    // to the unrefined frame give the refined one.
    Scene coarse_scene = scene;
    coarse_scene.refine.reset();
    const ScenePlan coarse_plan = plan_scene(coarse_scene);
    const SceneAnimation c = animate_scene(coarse_scene, coarse_plan, 2e9, {1, 2});
    std::vector<float> fine(3 * a.vertex_count);
    apply_refinement(plan.refinement, std::span<const float>(c.positions), 3, fine);
    EXPECT_EQ(std::memcmp(fine.data(), &a.positions[3 * a.vertex_count], fine.size() * sizeof(float)), 0);
    const auto message = [](const char* t) {
        try {
            parse_scene(t, "r.json", ".");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message(R"({"waves": [{"period": 5, "amplitude": 0.3}], "refine": {"level": 9}})").find("/refine/level"), std::string::npos);
    EXPECT_NE(message(R"({"waves": [{"period": 5, "amplitude": 0.3}], "refine": {"scheme": "butterfly"}})").find("expected one of"),
              std::string::npos);
}

namespace {

// Unit normals of a height grid z(x, y) by central differences (one sampled frame).
std::vector<float> grid_normals(const Grid& g) {
    std::vector<float> n(g.p.size());
    for (std::size_t j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < g.nx; ++i) {
            const auto z = [&](std::size_t a, std::size_t b) { return g.p[3 * (b * g.nx + a) + 2]; };
            const float dx = (z(std::min(i + 1, g.nx - 1), j) - z(i > 0 ? i - 1 : 0, j)) / 4.0f;
            const float dy = (z(i, std::min(j + 1, g.ny - 1)) - z(i, j > 0 ? j - 1 : 0)) / 4.0f;
            const float l = std::sqrt(dx * dx + dy * dy + 1.0f);
            const std::size_t v = 3 * (j * g.nx + i);
            n[v] = -dx / l, n[v + 1] = -dy / l, n[v + 2] = 1.0f / l;
        }
    return n;
}

}  // namespace

TEST(RefineAdaptive, RefinesWhereTheSurfaceBendsWithoutCracks) {
    // A plane with one sharp ridge along x = 20 m: only the ridge's neighbourhood is cut.
    Grid g = plane(21, 21);
    std::vector<double> rx, ry;
    for (std::size_t v = 0; v < g.p.size() / 3; ++v) {
        g.p[3 * v + 2] = (v % 21 == 10) ? 1.5f : 0.0f;
        rx.push_back(g.p[3 * v]);
        ry.push_back(g.p[3 * v + 1]);
    }
    const std::vector<float> normals = grid_normals(g);
    AdaptiveCriteria c{normals, rx, ry, {20.0, -100.0, 30.0}};
    RefineOptions o{RefineScheme::loop, 3, true, 4.0, 0.0};
    const Refinement r = plan_refinement(21 * 21, g.tris, o, 50'000'000, &c);
    const Refinement uniform = plan_refinement(21 * 21, g.tris, {RefineScheme::loop, 3});
    EXPECT_GT(r.fine_vertices, 21u * 21u);
    EXPECT_LT(r.fine_vertices, uniform.fine_vertices / 3) << "only near the ridge";
    // Watertight: a disc (V − E + F = 1: a T-junction's slit would open a hole), every
    // edge with one or two triangles, every rim vertex on exactly two rim edges.
    std::vector<float> fine(3 * r.fine_vertices);
    apply_refinement(r, g.p, 3, fine);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (std::size_t t = 0; t < r.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) ++uses[std::minmax(r.triangles[3 * t + k], r.triangles[3 * t + (k + 1) % 3])];
    std::vector<int> rim(r.fine_vertices, 0);
    for (const auto& [e, count] : uses) {
        ASSERT_LE(count, 2);
        if (count == 1) ++rim[e.first], ++rim[e.second];
    }
    for (int k : rim) ASSERT_TRUE(k == 0 || k == 2);
    EXPECT_EQ(static_cast<long long>(r.fine_vertices) - static_cast<long long>(uses.size()) +
                  static_cast<long long>(r.triangle_count()), 1);
    // Counter-clockwise from +z like the coarse grid.
    for (std::size_t t = 0; t < r.triangle_count(); ++t) {
        const auto a = 3 * r.triangles[3 * t], b = 3 * r.triangles[3 * t + 1], e = 3 * r.triangles[3 * t + 2];
        ASSERT_GT((fine[b] - fine[a]) * (fine[e + 1] - fine[a + 1]) - (fine[e] - fine[a]) * (fine[b + 1] - fine[a + 1]), 0.0f);
    }
    // Near the camera everything is cut to the full rate; Catmull-Clark is refused.
    RefineOptions near = o;
    near.max_angle_degrees = 90.0;
    near.near_distance = 1000.0;
    EXPECT_EQ(plan_refinement(21 * 21, g.tris, near, 50'000'000, &c).triangle_count(), uniform.triangle_count());
    EXPECT_THROW(plan_refinement(21 * 21, g.tris, {RefineScheme::catmull_clark, 2, true}, 50'000'000, &c), InputError);
}

TEST(Refine, CrestSharpnessKeepsCrestsAsTsosTensionDoes) {
    // One sampled swell: η = A cos(2πx/L), L = 8 m on a 1 m grid (41 × 9 nodes), A = 0.5 m.
    const double A = 0.5, L = 8.0, kPi = 3.141592653589793;
    Grid g = plane(41, 9);
    for (std::size_t v = 0; v < g.p.size() / 3; ++v) {
        g.p[3 * v] *= 0.5f;  // 1 m spacing
        g.p[3 * v + 1] *= 0.5f;
        g.p[3 * v + 2] = static_cast<float>(A * std::cos(2 * kPi * g.p[3 * v] / L));
    }
    const auto crest = [&](const Refinement& r) {
        std::vector<float> fine(3 * r.fine_vertices);
        apply_refinement(r, g.p, 3, fine);
        float top = -1.0f;
        for (std::size_t v = 0; v < r.fine_vertices; ++v)
            if (fine[3 * v] > 4.0f && fine[3 * v] < 36.0f) top = std::max(top, fine[3 * v + 2]);  // inner crests
        return top / A;
    };
    const RefineOptions loop{RefineScheme::loop, 2};
    const Refinement plain = plan_refinement(g.p.size() / 3, g.tris, loop);
    const Creases c = crest_creases(g.p, g.tris, 8.0, 4.0);
    ASSERT_FALSE(c.sharpness.empty());
    for (std::size_t i = 0; i < c.sharpness.size(); ++i) {
        ASSERT_LE(c.sharpness[i], 4.0f);
        ASSERT_GT(g.p[3 * c.edges[2 * i] + 2], 0.0f);  // only above still water
    }
    const Refinement sharp = plan_refinement(g.p.size() / 3, g.tris, loop, 50'000'000, nullptr, &c);
    EXPECT_EQ(sharp.triangles, plain.triangles) << "creases change the stencils, not the faces";
    const double loop_plain = crest(plain), loop_sharp = crest(sharp);
    // Ts'o's Beta2-spline through the same samples with tension β2 = τ·η at the crest
    // (τ = 20 /m, the height field's default), against the plain cubic B-spline.
    const auto beta_crest = [&](double beta2) {
        double top = -1.0;
        for (int span = 0; span < 2; ++span)  // the two spans around the crest at x = 16
            for (int i = 0; i <= 100; ++i) {
                double w[4];
                beta_spline_basis(i / 100.0, 1.0, beta2, w);
                double z = 0.0;
                for (int j = 0; j < 4; ++j) z += w[j] * A * std::cos(2 * kPi * (16 + span + j - 2) / L);
                top = std::max(top, z);
            }
        return top / A;
    };
    const double beta_plain = beta_crest(0.0), beta_tension = beta_crest(std::min(30.0, 20.0 * A));
    EXPECT_GT(loop_sharp, loop_plain + 0.02) << "sharp crests keep more of their height";
    EXPECT_GT(beta_tension, beta_plain + 0.02);
    EXPECT_LE(loop_sharp, 1.0 + 1e-6);
    EXPECT_LE(beta_tension, 1.0 + 1e-6);
    std::printf("crest height kept: Loop %.3f, Loop + crest sharpness %.3f; B-spline %.3f, Beta2 with tension %.3f\n",
                loop_plain, loop_sharp, beta_plain, beta_tension);
}

TEST(Refine, SceneCrestSharpnessRaisesTheCrestsWithTheSameFaces) {
    const char* base = R"({"seafloor": {"source": "gonzato-bay"}, "waves": [{"period": 5, "amplitude": 0.3}],
      "trace": {"ray_spacing": 4}, "fronts": {"step": 1.5, "split_distance": 6}, "animation": {"fps": 4},
      "refine": {"level": 1)";
    const Scene plain = parse_scene(std::string(base) + "}}", "r.json", ".");
    const Scene sharp = parse_scene(std::string(base) + R"(, "crest_sharpness_per_metre": 10}})", "r.json", ".");
    const SceneAnimation a = animate_scene(plain, plan_scene(plain), 2e9, {0, 4});
    const SceneAnimation b = animate_scene(sharp, plan_scene(sharp), 2e9, {0, 4});
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_GT(b.z_max, a.z_max + 0.005f) << "creased crests keep their height";
    EXPECT_THROW(parse_scene(std::string(base) + R"(, "adaptive": true, "crest_sharpness_per_metre": 10}})", "r.json", "."),
                 InputError);
}
