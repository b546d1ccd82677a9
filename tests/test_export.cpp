// Export and shade kernels: key times, input checks, and vertex normals.
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/io.h"
#include "libwave/scene.h"
#include "libwave/shade.h"
#include "libwave/surface.h"

#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <numbers>
#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <span>
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
        MorphAnimationView v;
        v.triangles = tri;
        v.vertex_count = 4;
        v.frame_count = 3;
        v.positions = pos;
        v.normals = nrm;
        v.texcoords = uv;
        return v;
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
    // A frame file checks its own frame (the files form writes them one by one).
    EXPECT_THROW(gltf_frame_glb(nan.view(), 1), InputError);
    EXPECT_NO_THROW(gltf_frame_glb(nan.view(), 0));
    EXPECT_THROW(gltf_frame_glb(nan.view(), 3), InputError);  // no such frame
    Quad bad;
    bad.tri[4] = 7;
    EXPECT_THROW(gltf_morph_glb(bad.view()), InputError);
    MorphAnimationView short_view = q.view();
    short_view.frame_count = 4;
    EXPECT_THROW(gltf_morph_glb(short_view), InputError);
}

// The JSON chunk of a .glb (the writer's layout: header, JSON, BIN).
std::string glb_json(const std::string& glb) {
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    return glb.substr(20, json_length);
}

TEST(GltfMorph, ShadingScalarsInBothLayoutsAndTheirChecks) {
    Quad q;
    std::vector<float> r(12), t(12), foam(12, 0.0f), rgb(36, 0.5f);
    for (std::size_t i = 0; i < 12; ++i) r[i] = 0.02f * static_cast<float>(i), t[i] = 1.0f - r[i];
    foam[5] = 1.0f;  // frame 1, vertex 1
    MorphAnimationView v = q.view();
    v.reflect = r;
    v.refract = t;
    v.foam = foam;
    v.colors = rgb;
    const std::string custom = glb_json(gltf_morph_glb(v));
    for (const char* name : {"\"_REFLECT\"", "\"_REFRACT\"", "\"_FOAM\"", "\"COLOR_0\""})
        EXPECT_NE(custom.find(name), std::string::npos) << name;
    EXPECT_EQ(custom.find("TEXCOORD_1"), std::string::npos);
    v.layout = ScalarLayout::blender34;
    const std::string compat = glb_json(gltf_morph_glb(v));
    EXPECT_NE(compat.find("TEXCOORD_1"), std::string::npos);
    EXPECT_NE(compat.find("TEXCOORD_2"), std::string::npos);
    EXPECT_EQ(compat.find("_FOAM"), std::string::npos);
    // Partial or mis-sized shading, and NaN scalars, are refused.
    MorphAnimationView partial = q.view();
    partial.reflect = r;
    EXPECT_THROW(gltf_morph_glb(partial), InputError);
    v.foam = std::span<const float>(foam).subspan(0, 8);
    EXPECT_THROW(gltf_morph_glb(v), InputError);
    foam[3] = std::numeric_limits<float>::quiet_NaN();
    v.foam = foam;
    EXPECT_THROW(gltf_morph_glb(v), InputError);
}

// A coarse bay (rays 4 m apart, about 1 500 vertices): the first `frames` frames.
SceneAnimation coarse_bay(std::size_t frames, Scene::Attributes attributes = Scene::Attributes::uv_maps) {
    // The built-in default scene until issue 66: Gonzato's bay, ray strips on the water mesh.
    Scene scene = parse_scene(R"({"seafloor": {"source": "gonzato-bay"}, "waves": [{"period": 5, "amplitude": 0.3, "direction": [0, 1]}],
    "trace": {"ray_spacing": 1}, "fronts": {"step": 0.4, "split_distance": 1.2}})", "the bay", ".");
    scene.quantize = false;  // float frames: the tests below choose their encoding
    scene.trace.ray_spacing = 4.0;
    scene.fronts.step = 1.6;
    scene.fronts.split_distance = 4.8;
    scene.attributes = attributes;
    // The tests below Draco-encode the frames as one primitive each: without the far
    // field (with it, a Draco frame is two primitives, docs/far-field.md).
    scene.far_field.reset();
    return animate_scene(scene, plan_scene(scene), 2e9, FrameRange{0, frames});
}

// The Draco bitstream a primitive's extension points at (a bufferView of the BIN
// chunk), decoded by Draco's decoder; null if it does not decode.
std::unique_ptr<draco::Mesh> decode_draco(const std::string& glb, const nlohmann::json& doc, const nlohmann::json& ext) {
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    const auto& bv = doc["bufferViews"][ext["bufferView"].get<int>()];
    draco::DecoderBuffer buffer;
    buffer.Init(glb.data() + 20 + json_length + 8 + bv.value("byteOffset", 0), bv["byteLength"].get<std::size_t>());
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    return decoded.ok() ? std::move(decoded).value() : nullptr;
}

TEST(Draco, FramesDecodeToTheSameVerticesWithinTheQuantisation) {
    // Two frames of the coarse bay, Draco on the files form.
    const SceneAnimation anim = coarse_bay(2, Scene::Attributes::named);
    MorphAnimationView view = anim.view();
    view.draco = DracoOptions{};
    const std::string glb = gltf_frame_glb(view, 1);
    const auto doc = nlohmann::json::parse(glb_json(glb));
    ASSERT_EQ(doc["extensionsRequired"][0], "KHR_draco_mesh_compression");
    const auto& prim = doc["meshes"][0]["primitives"][0];
    const auto& ext = prim["extensions"]["KHR_draco_mesh_compression"];
    for (const char* name : {"POSITION", "NORMAL", "TEXCOORD_0", "_REFLECT", "_REFRACT", "_FOAM"})
        EXPECT_TRUE(ext["attributes"].contains(name)) << name;
    const std::unique_ptr<draco::Mesh> mesh = decode_draco(glb, doc, ext);
    ASSERT_TRUE(mesh);
    const std::size_t n = anim.vertex_count;
    ASSERT_EQ(mesh->num_points(), n);
    ASSERT_EQ(mesh->num_faces(), anim.triangles.size() / 3);
    const draco::PointAttribute* pos = mesh->GetAttributeByUniqueId(ext["attributes"]["POSITION"].get<std::uint32_t>());
    ASSERT_NE(pos, nullptr);
    // The original frame 1 in glTF axes (x, z, −y), and its extent for the error bound.
    std::vector<std::array<float, 3>> original(n);
    float extent = 0.0f;
    std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (std::size_t v = 0; v < n; ++v) {
        const float* p = &anim.positions[3 * (n + v)];
        original[v] = {p[0], p[2], -p[1]};
        for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], original[v][i]), hi[i] = std::max(hi[i], original[v][i]);
    }
    for (int i = 0; i < 3; ++i) extent = std::max(extent, hi[i] - lo[i]);
    const double tolerance = extent / double(1 << 14);  // 14 position bits
    // The decoder reorders points: every decoded point must have an original within
    // the quantisation error, and every original must be matched once.
    std::vector<int> matched(n, 0);
    double worst = 0.0;
    for (draco::PointIndex i(0); i < mesh->num_points(); ++i) {
        std::array<float, 3> q{};
        pos->GetMappedValue(i, q.data());
        double best = 1e30;
        std::size_t arg = 0;
        for (std::size_t v = 0; v < n; ++v) {
            const double d = std::hypot(q[0] - original[v][0], q[1] - original[v][1], q[2] - original[v][2]);
            if (d < best) best = d, arg = v;
        }
        worst = std::max(worst, best);
        ++matched[arg];
    }
    EXPECT_LE(worst, tolerance);
    EXPECT_EQ(std::count(matched.begin(), matched.end(), 1), static_cast<long>(n));
}

// `glb` with its JSON chunk replaced by `json` (the BIN chunk unchanged).
std::string with_json(const std::string& glb, const nlohmann::json& doc) {
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    std::string json = doc.dump();
    json.append((4 - json.size() % 4) % 4, ' ');
    std::string out = glb.substr(0, 12);
    const auto u32 = [&](std::size_t v) {
        const auto x = static_cast<std::uint32_t>(v);
        out.append(reinterpret_cast<const char*>(&x), 4);
    };
    u32(json.size());
    out += "JSON" + json + glb.substr(20 + json_length);
    const auto total = static_cast<std::uint32_t>(out.size());
    std::memcpy(&out[8], &total, 4);
    return out;
}

TEST(GltfRead, AFramesPrimitivesAreJoinedAndTheSeamWelded) {
    // A frame's mesh of several primitives (a Draco frame and its far-field skirt,
    // docs/far-field.md) is read as one mesh: a later primitive's vertex at a first
    // primitive's bit-equal position is welded onto it. Here a plain frame lists its
    // primitive twice: every vertex of the copy welds, so the frame keeps its vertices
    // and holds each triangle twice. A copy without the shading scalars is refused.
    const SceneAnimation anim = coarse_bay(1, Scene::Attributes::named);
    const std::string glb = gltf_frame_glb(anim.view(), 0);
    const auto doc = nlohmann::json::parse(glb_json(glb));
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "libwave-two-primitives.glb";
    const auto read_with = [&](const std::function<void(nlohmann::json&)>& edit) {
        nlohmann::json edited = doc;
        nlohmann::json copy = edited["meshes"][0]["primitives"][0];
        edit(copy);
        edited["meshes"][0]["primitives"].push_back(copy);
        write_file_atomic(file.string(), with_json(glb, edited));
        StoredAnimation back = read_animation(file.string());
        std::filesystem::remove(file);
        return back;
    };
    const StoredAnimation back = read_with([](nlohmann::json&) {});
    ASSERT_EQ(back.vertex_count, anim.vertex_count);
    EXPECT_EQ(back.positions, anim.positions);
    EXPECT_EQ(back.foam, anim.foam);
    const std::size_t t = anim.triangles.size();
    ASSERT_EQ(back.triangles.size(), 2 * t);
    EXPECT_TRUE(std::equal(back.triangles.begin(), back.triangles.begin() + static_cast<std::ptrdiff_t>(t), anim.triangles.begin()));
    EXPECT_TRUE(std::equal(back.triangles.begin() + static_cast<std::ptrdiff_t>(t), back.triangles.end(), anim.triangles.begin()));
    try {
        read_with([](nlohmann::json& p) { p["attributes"].erase("_FOAM"), p["attributes"].erase("_REFLECT"), p["attributes"].erase("_REFRACT"); });
        ADD_FAILURE() << "a copy without the shading scalars was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("different attributes"), std::string::npos) << e.what();
    }
    std::filesystem::remove(file);
}

TEST(Draco, MorphBaseKeepsTheVertexOrderOfItsTargets) {
    // The morph form compresses only the base; its float targets are in our vertex
    // order, so the decoded base must be in that order too (Draco's sequential method).
    const SceneAnimation anim = coarse_bay(3);
    MorphAnimationView view = anim.view();
    view.draco = DracoOptions{};
    const std::string glb = gltf_morph_glb(view);
    const auto doc = nlohmann::json::parse(glb_json(glb));
    const auto& prim = doc["meshes"][0]["primitives"][0];
    ASSERT_EQ(prim["targets"].size(), 3u);
    const auto& ext = prim["extensions"]["KHR_draco_mesh_compression"];
    const std::unique_ptr<draco::Mesh> mesh = decode_draco(glb, doc, ext);
    ASSERT_TRUE(mesh);
    const std::size_t n = anim.vertex_count;
    ASSERT_EQ(mesh->num_points(), n);
    const draco::PointAttribute* pos = mesh->GetAttributeByUniqueId(ext["attributes"]["POSITION"].get<std::uint32_t>());
    double worst = 0.0;
    for (std::size_t v = 0; v < n; ++v) {
        std::array<float, 3> q{};
        pos->GetMappedValue(draco::PointIndex(static_cast<std::uint32_t>(v)), q.data());
        const float* p = &anim.positions[3 * v];
        worst = std::max({worst, std::abs(double{q[0]} - p[0]), std::abs(double{q[1]} - p[2]), std::abs(double{q[2]} + p[1])});
    }
    EXPECT_LE(worst, 120.0 / double(1 << 14));  // point v is vertex v, within the 14-bit step of the ~110 m extent
}

// An accessor of a .glb as doubles: float or normalised int16, dense (any stride),
// without a view (zeros), or sparse (a view, or zeros, then the listed elements).
std::vector<double> accessor_values(const nlohmann::json& doc, const char* bin, int index) {
    const auto& acc = doc["accessors"][index];
    const std::size_t width = acc["type"] == "VEC3" ? 3 : acc["type"] == "VEC2" ? 2 : 1;
    const std::size_t count = acc["count"].get<std::size_t>();
    const int type = acc["componentType"].get<int>();
    const std::size_t size = type == 5126 ? 4 : 2;
    const auto value = [&](const char* p) {
        if (type == 5126) {
            float f = 0;
            std::memcpy(&f, p, 4);
            return double{f};
        }
        std::int16_t q = 0;
        std::memcpy(&q, p, 2);
        return std::max(q / 32767.0, -1.0);
    };
    std::vector<double> out(width * count, 0.0);
    if (acc.contains("bufferView")) {
        const auto& bv = doc["bufferViews"][acc["bufferView"].get<int>()];
        const std::size_t stride = bv.value("byteStride", width * size);
        for (std::size_t e = 0; e < count; ++e)
            for (std::size_t c = 0; c < width; ++c)
                out[width * e + c] = value(bin + bv.value("byteOffset", 0) + acc.value("byteOffset", 0) + stride * e + size * c);
    }
    if (acc.contains("sparse")) {
        const auto& sp = acc["sparse"];
        const auto& iv = doc["bufferViews"][sp["indices"]["bufferView"].get<int>()];
        const auto& vv = doc["bufferViews"][sp["values"]["bufferView"].get<int>()];
        EXPECT_EQ(sp["indices"]["componentType"], 5123);  // uint16: fewer than 65 536 vertices
        for (std::size_t i = 0; i < sp["count"].get<std::size_t>(); ++i) {
            std::uint16_t k = 0;
            std::memcpy(&k, bin + iv.value("byteOffset", 0) + 2 * i, 2);
            for (std::size_t c = 0; c < width; ++c)
                out[width * k + c] = value(bin + vv.value("byteOffset", 0) + width * size * i + size * c);
        }
    }
    return out;
}

TEST(Quantization, MorphFramesDecodeWithinTheInt16StepOfTheMotion) {
    // KHR_mesh_quantization in the morph form: frame k = node scale · (base + target k),
    // the base float, the deltas normalised int16 with the largest delta as the range.
    // One vertex moved 50 km away in every frame (a far-field skirt's outer corner)
    // must not coarsen the others' steps, as a range over the extent would (to 1.5 m).
    SceneAnimation anim = coarse_bay(4);
    const std::size_t n = anim.vertex_count;
    for (std::size_t f = 0; f < anim.frame_count; ++f) anim.positions[3 * (f * n)] += 50000.0f;
    MorphAnimationView view = anim.view();
    view.quantize = true;
    const std::string glb = gltf_morph_glb(view);
    const auto doc = nlohmann::json::parse(glb_json(glb));
    ASSERT_EQ(doc["extensionsRequired"][0], "KHR_mesh_quantization");
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    const char* bin = glb.data() + 20 + json_length + 8;
    const auto& prim = doc["meshes"][0]["primitives"][0];
    const auto& node = doc["nodes"][0];
    EXPECT_FALSE(node.contains("translation"));  // float base positions keep the run's coordinates
    const double scale = node["scale"][0].get<double>();
    double largest = 0.0;  // the largest delta from frame 0, any axis
    for (std::size_t i = 0; i < anim.positions.size(); ++i)
        largest = std::max(largest, std::abs(double{anim.positions[i]} - anim.positions[i % (3 * n)]));
    EXPECT_NEAR(scale, largest, 1e-6 * largest);
    EXPECT_EQ(doc["accessors"][prim["attributes"]["POSITION"].get<int>()]["componentType"], 5126);
    const std::vector<double> base = accessor_values(doc, bin, prim["attributes"]["POSITION"].get<int>());
    for (std::size_t f = 0; f < 4; ++f) {
        const auto& target = doc["accessors"][prim["targets"][f]["POSITION"].get<int>()];
        EXPECT_EQ(target["componentType"], 5122);  // SHORT
        EXPECT_TRUE(target["normalized"].get<bool>());
        const std::vector<double> delta = accessor_values(doc, bin, prim["targets"][f]["POSITION"].get<int>());
        double worst = 0.0, far = 0.0;
        for (std::size_t v = 0; v < n; ++v) {
            const float* p = &anim.positions[3 * (f * n + v)];
            const double expected[3] = {p[0], p[2], -p[1]};  // glTF axes
            for (std::size_t c = 0; c < 3; ++c) {
                const double error = std::abs(scale * (base[3 * v + c] + delta[3 * v + c]) - expected[c]);
                (v == 0 ? far : worst) = std::max(v == 0 ? far : worst, error);
            }
        }
        // Half a step of the delta plus the float base's rounding (relative 2^-24 of
        // the ~100 m coordinates, twice: p / scale, then scale times it).
        EXPECT_LE(worst, 0.5 * scale / 32767.0 + 1.2e-5) << "frame " << f;
        EXPECT_LT(0.5 * scale / 32767.0 + 1.2e-5, 1e-4);  // a range over the 50 km extent: 0.76 m
        EXPECT_LE(far, 0.5 * scale / 32767.0 + 50000.0 * 1.2e-7) << "frame " << f;
    }
    view.draco = DracoOptions{};
    EXPECT_THROW(gltf_frame_glb(view, 0), InputError);  // Draco or quantisation, not both
}

TEST(MorphTargets, StillVerticesAreStoredSparseAndReadBack) {
    // Half the bay still in every frame (a dry beach, a skirt beyond the swell): each
    // target's moving half only, as a sparse accessor; a still foam channel has no
    // data at all. The library's reader gives the same frames back bit for bit.
    SceneAnimation anim = coarse_bay(3);
    const std::size_t n = anim.vertex_count;
    for (std::size_t f = 1; f < anim.frame_count; ++f)
        for (std::size_t v = n / 2; v < n; ++v) {
            for (std::size_t c = 0; c < 3; ++c) {
                anim.positions[3 * (f * n + v) + c] = anim.positions[3 * v + c];
                anim.normals[3 * (f * n + v) + c] = anim.normals[3 * v + c];
            }
            anim.reflect[f * n + v] = anim.reflect[v];
            anim.refract[f * n + v] = anim.refract[v];
        }
    std::fill(anim.foam.begin(), anim.foam.end(), 0.0f);
    const std::string glb = gltf_morph_glb(anim.view());
    const auto doc = nlohmann::json::parse(glb_json(glb));
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    const char* bin = glb.data() + 20 + json_length + 8;
    const auto& targets = doc["meshes"][0]["primitives"][0]["targets"];
    for (std::size_t f = 1; f < anim.frame_count; ++f) {
        const auto& position = doc["accessors"][targets[f]["POSITION"].get<int>()];
        ASSERT_TRUE(position.contains("sparse")) << "frame " << f;
        EXPECT_FALSE(position.contains("bufferView"));
        EXPECT_LE(position["sparse"]["count"].get<std::size_t>(), n / 2 + 1);
        const std::vector<double> delta = accessor_values(doc, bin, targets[f]["POSITION"].get<int>());
        for (std::size_t v = 0; v < n; ++v) {
            const float* p = &anim.positions[3 * (f * n + v)];
            const float* p0 = &anim.positions[3 * v];
            ASSERT_EQ(delta[3 * v], double{p[0] - p0[0]}) << "frame " << f << " vertex " << v;
            ASSERT_EQ(delta[3 * v + 2], double{-p[1] - -p0[1]}) << "frame " << f << " vertex " << v;
        }
        const auto& foam = doc["accessors"][targets[f]["TEXCOORD_2"].get<int>()];
        EXPECT_FALSE(foam.contains("bufferView") || foam.contains("sparse"));  // all zeros
    }
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "libwave-sparse-targets.glb";
    write_file_atomic(file.string(), glb);
    const StoredAnimation back = read_animation(file.string());
    std::filesystem::remove(file);
    ASSERT_EQ(back.frame_count, anim.frame_count);
    // base + delta in float: within a rounding of the values (the bay spans ~100 m).
    const auto worst = [](const std::vector<float>& a, const std::vector<float>& b) {
        EXPECT_EQ(a.size(), b.size());
        double w = 0.0;
        for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) w = std::max(w, std::abs(double{a[i]} - b[i]));
        return w;
    };
    EXPECT_LE(worst(back.positions, anim.positions), 2e-5);
    EXPECT_LE(worst(back.normals, anim.normals), 2e-7);
    EXPECT_EQ(back.foam, anim.foam);
    EXPECT_LE(worst(back.reflect, anim.reflect), 2e-7);

    // Hostile sparse accessors are refused by name, never read out of bounds: the same
    // file with one target's JSON edited (the BIN chunk unchanged).
    const int sparse_target = targets[1]["POSITION"].get<int>();
    const auto refused = [&](const std::function<void(nlohmann::json&)>& edit, const std::string& message) {
        nlohmann::json bad = doc;
        edit(bad["accessors"][sparse_target]);
        write_file_atomic(file.string(), with_json(glb, bad));
        try {
            read_animation(file.string());
            ADD_FAILURE() << "accepted: " << message;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << message << ": " << e.what();
        }
        std::filesystem::remove(file);
    };
    refused([](nlohmann::json& a) { a["sparse"]["count"] = a["count"].get<int>() + 1; }, "bad sparse count");
    refused([](nlohmann::json& a) { a["sparse"]["indices"]["componentType"] = 5126; }, "bad sparse index type");
    refused([](nlohmann::json& a) { a["sparse"]["values"]["byteOffset"] = 1 << 30; }, "runs past its buffer");
    refused([](nlohmann::json& a) {
        a.erase("sparse");
        a["count"] = 1 << 30;
    }, "claims");
}

// The largest |a − b| over `count` values of each, from the given offsets.
double worst_difference(std::span<const float> a, std::span<const float> b) {
    EXPECT_EQ(a.size(), b.size());
    double w = 0.0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) w = std::max(w, std::abs(double{a[i]} - b[i]));
    return w;
}

// Each triangle rotated so that its smallest index comes first (the winding kept).
std::vector<std::uint32_t> canonical_triangles(std::vector<std::uint32_t> t) {
    for (std::size_t i = 0; i + 2 < t.size(); i += 3)
        while (t[i] > t[i + 1] || t[i] > t[i + 2]) std::rotate(t.begin() + static_cast<std::ptrdiff_t>(i), t.begin() + static_cast<std::ptrdiff_t>(i + 1), t.begin() + static_cast<std::ptrdiff_t>(i + 3));
    return t;
}

TEST(Meshopt, EveryFormReadsBackWithinTheFilterSteps) {
    // EXT_meshopt_compression (docs/export.md, "Meshopt compression"): positions through
    // the exponential filter with an exponent per value — heights on 2^-16 m steps,
    // horizontal steps the largest power of two ≤ 1/256 of the shortest horizontal
    // edge — so that one vertex 50 km out (a far skirt's corner) coarsens only itself,
    // and the heights keep their own precision (no terraces: Draco's one step for all
    // axes gave 22 heights on a 2.2 km coast).
    SceneAnimation anim = coarse_bay(4);
    const std::size_t n = anim.vertex_count;
    for (std::size_t f = 0; f < anim.frame_count; ++f) anim.positions[3 * (f * n)] += 50000.0f;
    double shortest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < anim.triangles.size(); t += 3)
        for (std::size_t k = 0; k < 3; ++k) {
            const float* p = &anim.positions[3 * anim.triangles[t + k]];
            const float* q = &anim.positions[3 * anim.triangles[t + (k + 1) % 3]];
            const double d = std::hypot(double{p[0]} - q[0], double{p[1]} - q[1]);
            if (d > 0.0) shortest = std::min(shortest, d);
        }
    const double horizontal_step = std::exp2(std::floor(std::log2(shortest / 256.0)));
    MorphAnimationView view = anim.view();
    view.meshopt = true;
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "libwave-meshopt.glb";
    for (const char* form : {"morph", "nodes", "frame"}) {
        const std::string glb = std::string(form) == "morph"   ? gltf_morph_glb(view)
                                : std::string(form) == "nodes" ? gltf_nodes_glb(view)
                                                               : gltf_frame_glb(view, 2);
        const auto doc = nlohmann::json::parse(glb_json(glb));
        ASSERT_EQ(doc["extensionsRequired"], nlohmann::json::array({"EXT_meshopt_compression"})) << form;
        ASSERT_EQ(doc["buffers"].size(), 2u);
        EXPECT_TRUE(doc["buffers"][1]["extensions"]["EXT_meshopt_compression"]["fallback"].get<bool>());
        EXPECT_FALSE(doc["buffers"][1].contains("uri"));
        if (std::string(form) == "nodes") {
            EXPECT_LT(static_cast<double>(glb.size()), 0.75 * static_cast<double>(gltf_nodes_glb(anim.view()).size()));
        }
        write_file_atomic(file.string(), glb);
        const StoredAnimation back = read_animation(file.string());
        std::filesystem::remove(file);
        const std::size_t first = std::string(form) == "frame" ? 2 : 0, frames = back.frame_count;
        ASSERT_EQ(back.vertex_count, n) << form;
        // The triangle codec may rotate a triangle's corners (its winding kept).
        ASSERT_EQ(canonical_triangles(back.triangles), canonical_triangles(anim.triangles)) << form;
        double height = 0.0, across = 0.0, far = 0.0;
        for (std::size_t f = 0; f < frames; ++f)
            for (std::size_t v = 0; v < n; ++v) {
                const float* p = &anim.positions[3 * ((first + f) * n + v)];
                const float* q = &back.positions[3 * (f * n + v)];
                if (v == 0) {
                    far = std::max(far, std::abs(double{q[0]} - p[0]));
                    continue;
                }
                // The morph form adds two roundings (base and delta) and a float sum.
                height = std::max(height, std::abs(double{q[2]} - p[2]));
                across = std::max({across, std::abs(double{q[0]} - p[0]), std::abs(double{q[1]} - p[1])});
            }
        const double sums = std::string(form) == "morph" ? 2.0 : 1.0;
        EXPECT_LE(height, sums * 0.5 * std::exp2(-16) + 1e-7) << form;
        EXPECT_LE(across, sums * 0.5 * horizontal_step + 1e-5) << form;
        EXPECT_LT(across, 0.01 * shortest) << form;
        EXPECT_LE(far, 50100.0 * std::exp2(-23)) << form;  // its own exponent: 24 bits of its value
        const auto frames_of = [&](const std::vector<float>& all, std::size_t width) {
            return std::span<const float>(all).subspan(width * first * n, width * frames * n);
        };
        EXPECT_LE(worst_difference(back.normals, frames_of(anim.normals, 3)), sums * std::exp2(-16) + 1e-7) << form;
        EXPECT_LE(worst_difference(back.foam, frames_of(anim.foam, 1)), sums * std::exp2(-18) + 1e-7) << form;
        EXPECT_LE(worst_difference(back.reflect, frames_of(anim.reflect, 1)), sums * std::exp2(-18) + 1e-7) << form;
        EXPECT_LE(worst_difference(back.texcoords, anim.texcoords), std::exp2(-22)) << form;
    }
    view.quantize = true;
    EXPECT_THROW(gltf_frame_glb(view, 0), InputError);  // meshopt or quantisation, not both
}

// `glb` with its JSON edited by `edit`, written to `file` and read back: refused with
// InputError naming the file and saying `message`.
void expect_refused(const std::string& glb, const nlohmann::json& doc, const std::filesystem::path& file,
                    const std::function<void(nlohmann::json&)>& edit, const std::string& message) {
    nlohmann::json bad = doc;
    edit(bad);
    write_file_atomic(file.string(), with_json(glb, bad));
    try {
        read_animation(file.string());
        ADD_FAILURE() << "accepted: " << message;
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(message), std::string::npos) << message << ": " << what;
        EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    }
    std::filesystem::remove(file);
}

TEST(Meshopt, HostileStreamsAreRefusedNamingTheFile) {
    // A compressed view whose stream is cut short, whose count is not the stream's, or
    // that declares far more bytes than its stream can hold: InputError naming the file
    // and the view, before anything is decoded out of bounds or allocated for nothing.
    SceneAnimation anim = coarse_bay(1);
    MorphAnimationView view = anim.view();
    view.meshopt = true;
    const std::string glb = gltf_frame_glb(view, 0);
    const auto doc = nlohmann::json::parse(glb_json(glb));
    const int position_view = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()]["bufferView"];
    const int index_view = doc["accessors"][doc["meshes"][0]["primitives"][0]["indices"].get<int>()]["bufferView"];
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "libwave-meshopt-hostile.glb";
    int edit_number = 0;
    const auto refused = [&](int target, const std::function<void(nlohmann::json&, nlohmann::json&)>& edit, const std::string& message) {
        SCOPED_TRACE("edit " + std::to_string(++edit_number));
        expect_refused(glb, doc, file, [&](nlohmann::json& d) {
            auto& v = d["bufferViews"][static_cast<std::size_t>(target)];
            edit(v, v["extensions"]["EXT_meshopt_compression"]);
        }, message);
    };
    refused(position_view, [](nlohmann::json&, nlohmann::json& e) { e["byteLength"] = e["byteLength"].get<int>() / 2; }, "does not decode");
    refused(index_view, [](nlohmann::json&, nlohmann::json& e) { e["byteLength"] = e["byteLength"].get<int>() - 7; }, "does not decode");
    refused(position_view, [](nlohmann::json& v, nlohmann::json& e) {
        // A whole block more than the stream holds (16 more once decoded by chance: the
        // stream's last bytes happened to parse for the bay's heights since issue 66).
        e["count"] = e["count"].get<int>() + 256;
        v["byteLength"] = e["count"].get<int>() * 12;
    }, "does not decode");
    refused(position_view, [](nlohmann::json&, nlohmann::json& e) { e["count"] = e["count"].get<int>() + 1; }, "is not count");
    refused(position_view, [](nlohmann::json& v, nlohmann::json& e) {
        e["count"] = 1 << 28;
        v["byteLength"] = std::int64_t{12} << 28;
    }, "declares");
    refused(position_view, [](nlohmann::json& v, nlohmann::json& e) {
        e["byteStride"] = 6;
        v["byteLength"] = e["count"].get<int>() * 6;
    }, "multiple of 4");
    refused(index_view, [](nlohmann::json&, nlohmann::json& e) { e["mode"] = "STRIPS"; }, "unknown mode");
    refused(position_view, [](nlohmann::json&, nlohmann::json& e) { e["byteOffset"] = 1 << 30; }, "outside its buffer");
    refused(position_view, [](nlohmann::json&, nlohmann::json& e) { e["buffer"] = 1; }, "not in a buffer with data");
}

TEST(GltfRead, AccessorsStayInsideTheirViewsAndTheExtrasAreChecked) {
    // A byteStride that runs an accessor past its view (it read the next view's bytes), a
    // negative one (tinygltf took it for none) and asset extras beyond any loop (tinygltf
    // casts them to int: 2^40 frames became 0): InputError naming the file.
    Quad q;
    const std::string glb = gltf_morph_glb(q.view());
    const auto doc = nlohmann::json::parse(glb_json(glb));
    const std::size_t position = doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
    const std::size_t view = doc["accessors"][position]["bufferView"];
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "libwave-gltf-bounds.glb";
    const auto refused = [&](const std::function<void(nlohmann::json&)>& edit, const std::string& message) {
        expect_refused(glb, doc, file, edit, message);
    };
    refused([&](nlohmann::json& d) { d["bufferViews"][view]["byteStride"] = 16; }, "runs past its bufferView");
    refused([&](nlohmann::json& d) { d["bufferViews"][view]["byteStride"] = -12; }, "byteStride -12");
    refused([&](nlohmann::json& d) { d["bufferViews"][view]["byteStride"] = 6; }, "multiple of 4");
    refused([](nlohmann::json& d) { d["asset"]["extras"]["libwave"]["loop_frames"] = std::uint64_t{1} << 40; }, "loop_frames");
    refused([](nlohmann::json& d) { d["asset"]["extras"]["libwave"]["loop_frames"] = -3; }, "loop_frames");
    refused([](nlohmann::json& d) { d["asset"]["extras"]["libwave"]["fps"] = 0; }, "fps");
    // The stride libwave's own views would have (none, or the element's 12 bytes) is read.
    write_file_atomic(file.string(), glb);
    const std::vector<float> plain = read_animation(file.string()).positions;
    nlohmann::json fine = doc;
    fine["bufferViews"][view]["byteStride"] = 12;
    write_file_atomic(file.string(), with_json(glb, fine));
    EXPECT_EQ(read_animation(file.string()).positions, plain);
    std::filesystem::remove(file);
}

TEST(Files, SpecialFilesAndPathsOutOfTheirFolderAreRefused) {
    namespace fs = std::filesystem;
    const fs::path d = fs::temp_directory_path() / ("libwave-files-" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d / "in" / "frames");
    fs::create_directories(d / "out");
    write_file_atomic((d / "in" / "frames" / "a.glb").string(), "x");
    write_file_atomic((d / "out" / "b.glb").string(), "x");
    ASSERT_EQ(::mkfifo((d / "in" / "fifo.glb").c_str(), 0600), 0);
    fs::create_directory_symlink("../out", d / "in" / "away");
    fs::create_directory_symlink("frames", d / "in" / "here");
    const std::string in = (d / "in").string();
    const auto message = [](const std::function<void()>& f) {
        try {
            f();
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    // One check of the file's type before any open: a FIFO would block its reader.
    EXPECT_NE(message([&] { require_input_file(in + "/fifo.glb"); }).find("a FIFO (named pipe), not a regular file"), std::string::npos);
    EXPECT_NE(message([&] { require_input_file(in + "/frames"); }).find("a directory, not a file"), std::string::npos);
    EXPECT_NE(message([&] { require_input_file(in + "/frames/a.glb", true); }).find("a file, not a folder"), std::string::npos);
    EXPECT_NO_THROW(require_input_file(in + "/frames", true));
    EXPECT_NO_THROW(require_input_file(in + "/frames/a.glb"));
    // One containment rule for a path read from a file.
    for (const auto& [name, why] : std::vector<std::pair<std::string, std::string>>{
             {"../out/b.glb", "goes up a folder"}, {(d / "out" / "b.glb").string(), "an absolute path"},
             {"frames/../../out/b.glb", "goes up a folder"}, {"away/b.glb", "a link leads out of the folder"},
             {"away", "a link leads out of the folder"}, {"", "an empty path"}}) {
        const std::string& named = name;  // a structured binding is not captured (clang 14)
        const std::string m = message([&] { path_inside(in, named, "index.json: frames[0].file"); });
        EXPECT_NE(m.find(why), std::string::npos) << name << ": " << m;
        EXPECT_NE(m.find("index.json: frames[0].file"), std::string::npos) << m;
    }
    EXPECT_EQ(path_inside(in, "frames/a.glb", "x"), in + "/frames/a.glb");
    EXPECT_EQ(path_inside(in, "here/a.glb", "x"), in + "/here/a.glb");  // a link that stays inside
    EXPECT_EQ(path_inside(in, "frames/new/c.glb", "x"), in + "/frames/new/c.glb");  // not there yet: a file to write
    fs::remove_all(d);
}

TEST(Messages, ControlAndBidiCharactersAreShownAsEscapes) {
    // A name read from a file (a scene's /name, a path) reaches the terminal through
    // printable: an escape sequence, a line break or a right-to-left override is shown,
    // not acted on; other text (UTF-8 included) is kept.
    EXPECT_EQ(printable("plain: bay.json, é, 波"), "plain: bay.json, é, 波");
    EXPECT_EQ(printable("a\x1b[2Jb"), "a\\x1B[2Jb");
    EXPECT_EQ(printable("line\nbreak\ttab\x7f"), "line\\x0Abreak\ttab\\x7F");
    EXPECT_EQ(printable("evil\u202Egnp.exe"), "evil\\u{202E}gnp.exe");
    EXPECT_EQ(printable("\u2066x\u2069 \u200F \u061C"), "\\u{2066}x\\u{2069} \\u{200F} \\u{061C}");
    EXPECT_EQ(printable("c1\xC2\x9B"), "c1\\u{009B}");
    EXPECT_EQ(printable("bad\xff\xC0\xAF"), "bad\\xFF\\xC0\\xAF");  // invalid and overlong bytes
    EXPECT_EQ(printable(std::string("nul\0x", 5)), "nul\\x00x");
}

TEST(Quantization, TheMorphFormKeepsAFarSkirtsRestPositions) {
    // TEXCOORD_0 beyond [0, 1]² (a far-field skirt's rest positions) stays float in the
    // quantised morph form: normalised uint16 clamped it onto the domain's edge, and
    // every reader then took the skirt for domain (the viewer framed 160 km of it).
    SceneAnimation anim = coarse_bay(2);
    anim.texcoords[0] = 37.5f;
    anim.texcoords[1] = -12.25f;
    MorphAnimationView view = anim.view();
    view.quantize = true;
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "libwave-quantised-skirt-uv.glb";
    write_file_atomic(file.string(), gltf_morph_glb(view));
    const StoredAnimation back = read_animation(file.string());
    std::filesystem::remove(file);
    EXPECT_EQ(back.texcoords, anim.texcoords);
}

TEST(Fresnel, WeightsMatchTheFormulasAndSumToOne) {
    // One horizontal vertex, camera straight above, at 60° and grazing.
    const std::vector<float> p{0, 0, 0}, n{0, 0, 1};
    std::vector<float> r(1), t(1);
    FresnelOptions o;
    o.camera = {0.0, 0.0, 10.0};
    fresnel_weights(p, n, o, r, t);
    const double normal = std::pow((kWaterRefractiveIndex - 1.0) / (kWaterRefractiveIndex + 1.0), 2);
    EXPECT_NEAR(r[0], normal, 1e-7);  // 0.0204 for n = 1.333
    EXPECT_FLOAT_EQ(r[0] + t[0], 1.0f);
    o.camera = {10.0 * std::sin(1.0471975511965976), 0.0, 10.0 * std::cos(1.0471975511965976)};
    fresnel_weights(p, n, o, r, t);
    EXPECT_NEAR(r[0], fresnel_reflectivity(0.5), 1e-7);
    o.model = FresnelModel::tso;
    fresnel_weights(p, n, o, r, t);
    EXPECT_NEAR(r[0], fresnel_reflectivity_tso(1.0471975511965976), 1e-6);
    // Seen from under a lip (normal facing away): the other side's angle, same weights.
    const std::vector<float> down{0, 0, -1};
    std::vector<float> r2(1), t2(1);
    fresnel_weights(p, down, o, r2, t2);
    EXPECT_FLOAT_EQ(r2[0], r[0]);
    std::vector<float> wrong(2);
    EXPECT_THROW(fresnel_weights(p, n, o, wrong, t), InputError);
}

TEST(Fresnel, WeightsAreTheFormulaInFloat) {
    // Many vertices in every orientation (from under lips too), camera near and far, and
    // a grazing index of 1: each weight is fresnel_reflectivity's value (double) within
    // float arithmetic's 1e-6 (3.8e-7 seen), and R + T = 1.
    std::vector<float> p, n;
    std::uint32_t state = 12345;
    const auto uniform = [&] { return static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) / 16777216.0f; };
    for (int v = 0; v < 20000; ++v) {
        const float a = 6.2831853f * uniform(), z = 2.0f * uniform() - 1.0f, s = std::sqrt(1.0f - z * z);
        p.insert(p.end(), {100.0f * uniform(), 100.0f * uniform(), 2.0f * uniform() - 1.0f});
        n.insert(n.end(), {s * std::cos(a), s * std::sin(a), z});
    }
    double worst = 0.0;
    for (const double index : {kWaterRefractiveIndex, 1.0, 2.4}) {
        FresnelOptions o;
        o.camera = {40.0, -30.0, 12.0};
        o.water_index = index;
        std::vector<float> r(n.size() / 3), t(r.size());
        fresnel_weights(p, n, o, r, t);
        for (std::size_t v = 0; v < r.size(); ++v) {
            const double ex = o.camera[0] - p[3 * v], ey = o.camera[1] - p[3 * v + 1], ez = o.camera[2] - p[3 * v + 2];
            const double len = std::sqrt(ex * ex + ey * ey + ez * ez);
            const double c = std::min(std::abs((ex * n[3 * v] + ey * n[3 * v + 1] + ez * n[3 * v + 2]) / len), 1.0);
            const double expected = fresnel_reflectivity(c, 1.0, index);
            ASSERT_NEAR(r[v], expected, 1e-6) << v << " index " << index;
            ASSERT_EQ(t[v], 1.0f - r[v]) << v;
            worst = std::max(worst, std::abs(r[v] - expected));
        }
    }
    std::printf("Fresnel weights in float: largest difference from the double formula %.2g\n", worst);
}

TEST(Foam, ReleasedAtTheCrestOfBreakingWavesAndFading) {
    // Three vertices on a 1 m deep flat: breaking (H = γh), at 95 % of it, and calm.
    RayStrips s;
    s.x = {0, 1, 2};
    s.y = {0, 0, 0};
    s.dir_x = {1, 1, 1};
    s.dir_y = {0, 0, 0};
    s.phase = {0, 0, 0};
    s.k = {0.4, 0.4, 0.4};
    s.depth = {1, 1, 1};
    s.rise = {0, 0, 0};
    s.amplitude = {0.5 * kBreakerIndex, 0.95 * 0.5 * kBreakerIndex, 0.1};
    s.omega = 2.0 * std::numbers::pi / 5.0;
    const GonzatoMotionPlan m = plan_gonzato_motion(s);
    const double crest = -(m.shape[0].trough_phase + std::numbers::pi) / s.omega;  // Φ(t) = Φ_min + π
    std::vector<float> foam(3);
    FoamOptions o;
    breaking_foam(s, m, crest, o, foam);
    EXPECT_NEAR(foam[0], 1.0, 1e-6);
    EXPECT_NEAR(foam[1], 0.5, 1e-6);  // half-way up the onset ramp (0.9 … 1)
    EXPECT_EQ(foam[2], 0.0f);
    // By default it fades over 0.3 of the 5 s period: τ = 1.5 s.
    breaking_foam(s, m, crest + 1.0, o, foam);
    EXPECT_NEAR(foam[0], std::exp(-1.0 / 1.5), 1e-6);
    // Periodic: one period later it is the same.
    std::vector<float> later(3);
    breaking_foam(s, m, crest + 1.0 + 5.0, o, later);
    EXPECT_NEAR(later[0], foam[0], 1e-6);
    // Froude similarity: the same wave 400 times smaller (periods 20 times shorter)
    // has the same foam at the same share of its period.
    RayStrips small = s;
    for (auto& a : small.amplitude) a /= 400;
    for (auto& d : small.depth) d /= 400;
    for (auto& k : small.k) k *= 400;
    for (auto& x : small.x) x /= 400;
    small.omega = s.omega * 20.0;
    const GonzatoMotionPlan ms = plan_gonzato_motion(small);
    const double small_crest = -(ms.shape[0].trough_phase + std::numbers::pi) / small.omega;
    breaking_foam(small, ms, small_crest + 1.0 / 20.0, o, later);
    EXPECT_NEAR(later[0], foam[0], 1e-5);
    // A fixed time instead: τ = 2 s for any period.
    o.fade_time = 2.0;
    breaking_foam(s, m, crest + 1.0, o, foam);
    EXPECT_NEAR(foam[0], std::exp(-1.0 / 2.0), 1e-6);
    breaking_foam(small, ms, small_crest + 0.1, o, later);  // within its 0.25 s period
    EXPECT_NEAR(later[0], std::exp(-0.1 / 2.0), 1e-5);
    o.fade_time = -1.0;
    EXPECT_THROW(breaking_foam(s, m, 0.0, o, foam), InputError);
    o.fade_time = 0.0;
    o.fade_periods = 0.0;
    EXPECT_THROW(breaking_foam(s, m, 0.0, o, foam), InputError);
}

TEST(Foam, HeightFieldNodesReleaseFoamAndVerticesBlendIt) {
    // 2 × 2 control nodes, 2 samples per span: 3 × 3 vertices. Node 0 carries a
    // breaking train (a = γh/2 at h = 1 m); the others are calm.
    HeightFieldPlan plan;
    plan.nx = plan.ny = 2;
    plan.samples_per_span = 2;
    plan.vertex_nx = plan.vertex_ny = 3;
    plan.term_offsets = {0, 1, 2, 2, 2};
    plan.term_amplitude = {0.5 * kBreakerIndex, 0.1};
    plan.term_phase = {0.0, 0.0};
    plan.term_omega = {1.0, 1.0};
    const std::vector<float> depth{1.0f, 1.0f, 1.0f, 1.0f};
    std::vector<float> nodes(4), foam(9);
    const FoamOptions o;
    const double crest = -0.5 * std::numbers::pi;  // φ − ω t = π/2
    height_field_foam(plan, depth, crest, o, nodes, foam);
    EXPECT_NEAR(nodes[0], 1.0, 1e-6);
    EXPECT_EQ(nodes[1], 0.0f);  // 0.1 m on 1 m: far from breaking
    EXPECT_NEAR(foam[0], 1.0, 1e-6);
    EXPECT_NEAR(foam[1], 0.5, 1e-6);   // half-way to node 1
    EXPECT_NEAR(foam[4], 0.25, 1e-6);  // the centre blends all four
    EXPECT_EQ(foam[8], 0.0f);
    height_field_foam(plan, depth, crest + 1.0, o, nodes, foam);
    EXPECT_NEAR(foam[0], std::exp(-1.0 / (0.3 * 2.0 * std::numbers::pi)), 1e-6);  // τ = 0.3 T, T = 2π s
    std::vector<float> wrong(3);
    EXPECT_THROW(height_field_foam(plan, depth, 0.0, o, nodes, wrong), InputError);
}

TEST(HeightFieldScene, TheWaterStaysBelowTheLandItCovers) {
    // Ts'o and Barsky's beach: the height field spans the whole grid, land included, and
    // its spline's heights spill past the wet control nodes. Over the flat beach at the
    // waterline the water stood level with the sand, or above it (the witness below), and
    // Cycles drew dark wedges of either across the beach. The scene keeps the water a
    // twentieth of the highest amplitude (0.2 m) below the land there.
    Scene scene = read_scene(std::string(LIBWAVE_EXAMPLES_DIR) + "/tso-barsky.json");
    scene.fps = 2.0;
    const ScenePlan plan = plan_scene(scene);
    const SceneAnimation anim = animate_scene(scene, plan, 2e9, FrameRange{0, 6});
    const std::size_t n = anim.vertex_count, own = plan.surface.vertex_count();
    std::vector<float> heights(plan.surface.control_count()), raw(3 * own);
    std::size_t on_land = 0, level_or_above = 0;
    double highest = -1.0;  // the water over land, above its land (m)
    for (std::size_t f = 0; f < anim.frame_count; ++f) {
        evaluate_height_field(plan.surface, static_cast<double>(f) / scene.fps, heights, raw);
        for (std::size_t v = 0; v < own; ++v) {
            const double depth = depth_at(plan.seafloor.grid, plan.rest_x[v], plan.rest_y[v]);
            if (depth > 0.0) continue;
            ++on_land;
            level_or_above += raw[3 * v + 2] >= -depth;
            highest = std::max(highest, anim.positions[3 * (f * n + v) + 2] + depth);
        }
    }
    ASSERT_GT(on_land, 1000u);
    EXPECT_GT(level_or_above, 100u) << "the spline alone";
    EXPECT_LE(highest, -0.05 * 0.2 + 1e-6);
}

TEST(Foam, PlanarBeachHeightFieldFoamsInTheSurfZoneOnly) {
    Scene scene = read_scene(std::string(LIBWAVE_EXAMPLES_DIR) + "/planar-beach.json");
    scene.fps = 2.0;
    const ScenePlan plan = plan_scene(scene);
    const SceneAnimation anim = animate_scene(scene, plan);
    const std::size_t n = anim.vertex_count;
    float surf = 0.0f, offshore = 0.0f;
    for (std::size_t f = 0; f < anim.frame_count; ++f)
        for (std::size_t v = 0; v < n; ++v) {
            const double h = depth_at(plan.seafloor.grid, anim.positions[3 * (f * n + v)], anim.positions[3 * (f * n + v) + 1]);
            float& bucket = h > 3.0 ? offshore : surf;
            bucket = std::max(bucket, anim.foam[f * n + v]);
        }
    EXPECT_GT(surf, 0.5f);      // waves break near the shore
    EXPECT_EQ(offshore, 0.0f);  // and nowhere in deep water
}

TEST(WaterColour, TsoMixOfReflectedAndRefractedWithFoam) {
    const std::vector<float> r{1.0f, 0.0f, 0.0f, 0.5f}, depth{0, 0, 100, 0}, foam{0, 0, 0, 1};
    std::vector<float> rgb(12);
    const WaterColours c;
    water_colour(r, depth, foam, c, rgb);
    for (int i = 0; i < 3; ++i) {
        EXPECT_FLOAT_EQ(rgb[static_cast<std::size_t>(i)], c.reflected[static_cast<std::size_t>(i)]);
        EXPECT_FLOAT_EQ(rgb[3 + static_cast<std::size_t>(i)], c.shallow[static_cast<std::size_t>(i)]);
        EXPECT_NEAR(rgb[6 + static_cast<std::size_t>(i)], c.deep[static_cast<std::size_t>(i)], 1e-6);
        EXPECT_FLOAT_EQ(rgb[9 + static_cast<std::size_t>(i)], 1.0f);  // full foam is white
    }
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
