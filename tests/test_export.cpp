// Export and shade kernels: key times, input checks, and vertex normals.
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/shade.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace {

using namespace wave;

TEST(KeyTime, LargestFloatNotAfterTheFrame) {
    for (double fps : {24.0, 25.0, 30.0, 29.97, 60.0})
        for (std::size_t k = 0; k < 5000; ++k) {
            const float t = key_time(k, fps);
            const double exact = static_cast<double>(k) / fps;
            ASSERT_LE(static_cast<double>(t), exact) << k << " @ " << fps;
            ASSERT_GT(static_cast<double>(std::nextafter(t, std::numeric_limits<float>::infinity())), exact);
        }
}

struct Quad {  // two triangles, 3 frames rising by 0.1 m
    std::vector<std::uint32_t> tri{0, 1, 2, 0, 2, 3};
    std::vector<float> pos, nrm, uv{0, 1, 1, 1, 1, 0, 0, 0};
    Quad() {
        const float corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int f = 0; f < 3; ++f)
            for (const auto& c : corners) pos.insert(pos.end(), {c[0], c[1], 0.1f * static_cast<float>(f)});
        nrm.assign(pos.size(), 0.0f);
        vertex_normals(std::span(pos).subspan(0, 12), tri, std::span(nrm).subspan(0, 12));
        for (int f = 1; f < 3; ++f) std::copy_n(nrm.begin(), 12, nrm.begin() + 12 * f);
    }
    MorphAnimationView view() const {
        return {.triangles = tri, .vertex_count = 4, .frame_count = 3, .positions = pos, .normals = nrm, .texcoords = uv};
    }
};

TEST(GltfMorph, WritesAGlbAndRefusesBadInput) {
    Quad q;
    ASSERT_EQ(q.pos.size(), 36u);
    const std::string glb = gltf_morph_glb(q.view());
    ASSERT_GT(glb.size(), 20u);
    EXPECT_EQ(glb.substr(0, 4), "glTF");
    std::uint32_t version = 0, length = 0;
    std::memcpy(&version, glb.data() + 4, 4);
    std::memcpy(&length, glb.data() + 8, 4);
    EXPECT_EQ(version, 2u);
    EXPECT_EQ(length, glb.size());

    Quad nan;
    nan.pos[3 * 4 + 2] = std::numeric_limits<float>::quiet_NaN();  // frame 1, vertex 0
    try {
        gltf_morph_glb(nan.view());
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("frame 1, vertex 0"), std::string::npos) << e.what();
    }
    Quad bad;
    bad.tri[4] = 7;
    EXPECT_THROW(gltf_morph_glb(bad.view()), InputError);
    MorphAnimationView short_view = q.view();
    short_view.frame_count = 4;
    EXPECT_THROW(gltf_morph_glb(short_view), InputError);
}

TEST(Normals, PlanesGiveTheirAnalyticNormal) {
    // z = 0.5 x − 0.25 y over a 3 × 3 vertex grid: n ∝ (−0.5, 0.25, 1).
    std::vector<float> p;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) p.insert(p.end(), {float(i), float(j), 0.5f * float(i) - 0.25f * float(j)});
    std::vector<std::uint32_t> t;
    for (std::uint32_t j = 0; j < 2; ++j)
        for (std::uint32_t i = 0; i < 2; ++i) {
            const std::uint32_t a = 3 * j + i;
            t.insert(t.end(), {a, a + 1, a + 4, a, a + 4, a + 3});
        }
    std::vector<float> n(p.size());
    vertex_normals(p, t, n);
    const double len = std::sqrt(0.25 + 0.0625 + 1.0);
    for (std::size_t v = 0; v < 9; ++v) {
        EXPECT_NEAR(n[3 * v], -0.5 / len, 1e-6);
        EXPECT_NEAR(n[3 * v + 1], 0.25 / len, 1e-6);
        EXPECT_NEAR(n[3 * v + 2], 1.0 / len, 1e-6);
    }
    // A vertex used only by a degenerate triangle falls back to +z.
    std::vector<float> q{0, 0, 0, 1, 0, 0, 2, 0, 0};
    std::vector<std::uint32_t> line{0, 1, 2};
    std::vector<float> m(9);
    vertex_normals(q, line, m);
    EXPECT_EQ(m[2], 1.0f);
}

}  // namespace
