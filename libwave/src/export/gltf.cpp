// glTF 2.0 (.glb) through tinygltf: a morph-target animation with a one-hot STEP
// weights channel, as Blender and three.js read it (DESIGN.md, "Export conventions").
// tinygltf is compiled here and nowhere else (BUILD-NOTES: never link Debian's
// libtinygltf.so, whose symbols clash with the copy inside libdraco).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/export.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

namespace wave {
namespace {

// Appends raw floats or ints to the single buffer, 4-byte aligned, as one bufferView,
// and an accessor over it. Returns the accessor index.
struct GlbBuilder {
    tinygltf::Model& model;
    std::vector<unsigned char>& bytes;

    int view(const void* data, std::size_t size, int target) {
        while (bytes.size() % 4) bytes.push_back(0);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = bytes.size();
        v.byteLength = size;
        v.target = target;
        const auto* b = static_cast<const unsigned char*>(data);
        bytes.insert(bytes.end(), b, b + size);
        model.bufferViews.push_back(v);
        return static_cast<int>(model.bufferViews.size() - 1);
    }

    int accessor(int view_index, int component, std::size_t count, int type, std::vector<double> min = {},
                 std::vector<double> max = {}) {
        tinygltf::Accessor a;
        a.bufferView = view_index;
        a.componentType = component;
        a.count = count;
        a.type = type;
        a.minValues = std::move(min);
        a.maxValues = std::move(max);
        model.accessors.push_back(a);
        return static_cast<int>(model.accessors.size() - 1);
    }

    // vec3 floats with the min/max glTF requires on POSITION accessors.
    int vec3(const std::vector<float>& v, int target, bool bounds) {
        std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
        if (bounds)
            for (std::size_t i = 0; i < v.size(); ++i) {
                lo[i % 3] = std::min(lo[i % 3], double{v[i]});
                hi[i % 3] = std::max(hi[i % 3], double{v[i]});
            }
        return accessor(view(v.data(), v.size() * sizeof(float), target), TINYGLTF_COMPONENT_TYPE_FLOAT, v.size() / 3,
                        TINYGLTF_TYPE_VEC3, bounds ? lo : std::vector<double>{}, bounds ? hi : std::vector<double>{});
    }
};

// z up → glTF y up: (x, y, z) → (x, z, −y).
void to_y_up(const float* in, float* out) {
    out[0] = in[0];
    out[1] = in[2];
    out[2] = -in[1];
}

void check(const MorphAnimationView& a) {
    const std::size_t n = a.vertex_count, f = a.frame_count;
    if (n == 0 || f == 0) throw InputError("glTF export: nothing to export (no vertices or no frames)");
    if (a.positions.size() != f * n * 3 || a.normals.size() != f * n * 3 || a.texcoords.size() != n * 2)
        throw InputError("glTF export: array sizes do not match " + std::to_string(f) + " frames of " +
                         std::to_string(n) + " vertices");
    for (const auto& [channel, name, width] : {std::tuple{a.reflect, "reflect", 1}, std::tuple{a.refract, "refract", 1},
                                               std::tuple{a.foam, "foam", 1}, std::tuple{a.colors, "colors", 3}}) {
        if (!channel.empty() && channel.size() != f * n * static_cast<std::size_t>(width))
            throw InputError(std::string("glTF export: ") + name + " holds " + std::to_string(channel.size()) +
                             " floats, expected " + std::to_string(f * n * static_cast<std::size_t>(width)));
        for (std::size_t i = 0; i < channel.size(); ++i)
            if (!std::isfinite(channel[i]))
                throw InputError(std::string("glTF export: ") + name + " of frame " + std::to_string(i / (n * static_cast<std::size_t>(width))) +
                                 " is NaN or infinite; refusing to write it");
    }
    if ((a.reflect.empty() || a.refract.empty() || a.foam.empty()) && !(a.reflect.empty() && a.refract.empty() && a.foam.empty()))
        throw InputError("glTF export: give reflect, refract and foam together (or none)");
    if (a.triangles.empty() || a.triangles.size() % 3) throw InputError("glTF export: the index list is not whole triangles");
    for (std::uint32_t v : a.triangles)
        if (v >= n) throw InputError("glTF export: triangle index " + std::to_string(v) + " >= vertex count " + std::to_string(n));
    if (!(a.fps > 0.0) || !std::isfinite(a.fps)) throw InputError("glTF export: fps must be > 0, got " + detail::format_number(a.fps));
    for (std::size_t i = 0; i < a.positions.size(); ++i)
        if (!std::isfinite(a.positions[i]) || !std::isfinite(a.normals[i]))
            throw InputError("glTF export: frame " + std::to_string(i / (3 * n)) + ", vertex " + std::to_string((i / 3) % n) +
                             " has a NaN or infinite position or normal; refusing to write it");
}

}  // namespace

float key_time(std::size_t k, double fps) noexcept {
    const double exact = static_cast<double>(k) / fps;
    float t = static_cast<float>(exact);
    if (static_cast<double>(t) > exact) t = std::nextafter(t, -std::numeric_limits<float>::infinity());
    return t;
}

std::string gltf_morph_glb(const MorphAnimationView& a) {
    check(a);
    const std::size_t n = a.vertex_count, frames = a.frame_count;
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "libwave";
    model.buffers.resize(1);
    std::vector<unsigned char>& bytes = model.buffers[0].data;
    GlbBuilder b{model, bytes};

    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.indices = b.accessor(b.view(a.triangles.data(), a.triangles.size_bytes(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, a.triangles.size(), TINYGLTF_TYPE_SCALAR);

    std::vector<float> base_p(3 * n), base_n(3 * n), scratch_p(3 * n), scratch_n(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        to_y_up(&a.positions[3 * v], &base_p[3 * v]);
        to_y_up(&a.normals[3 * v], &base_n[3 * v]);
    }
    prim.attributes["POSITION"] = b.vec3(base_p, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    prim.attributes["NORMAL"] = b.vec3(base_n, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    prim.attributes["TEXCOORD_0"] =
        b.accessor(b.view(a.texcoords.data(), a.texcoords.size_bytes(), TINYGLTF_TARGET_ARRAY_BUFFER),
                   TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC2);

    // The shading scalars of frame f as (attribute name, accessor type, floats): either
    // three FLOAT `_` attributes or the Blender 3.4 pair of UV maps.
    const bool shaded = !a.reflect.empty();
    const auto shading = [&](std::size_t f) {
        std::vector<std::tuple<std::string, int, std::vector<float>>> out;
        if (!a.colors.empty())
            out.emplace_back("COLOR_0", TINYGLTF_TYPE_VEC3,
                             std::vector<float>(a.colors.begin() + static_cast<std::ptrdiff_t>(3 * f * n),
                                                a.colors.begin() + static_cast<std::ptrdiff_t>(3 * (f + 1) * n)));
        if (!shaded) return out;
        const auto frame = [&](std::span<const float> c) {
            return std::vector<float>(c.begin() + static_cast<std::ptrdiff_t>(f * n), c.begin() + static_cast<std::ptrdiff_t>((f + 1) * n));
        };
        if (a.layout == ScalarLayout::custom) {
            out.emplace_back("_REFLECT", TINYGLTF_TYPE_SCALAR, frame(a.reflect));
            out.emplace_back("_REFRACT", TINYGLTF_TYPE_SCALAR, frame(a.refract));
            out.emplace_back("_FOAM", TINYGLTF_TYPE_SCALAR, frame(a.foam));
        } else {
            std::vector<float> uv1(2 * n), uv2(2 * n, 0.0f);
            for (std::size_t v = 0; v < n; ++v) {
                uv1[2 * v] = a.reflect[f * n + v];
                uv1[2 * v + 1] = a.refract[f * n + v];
                uv2[2 * v] = a.foam[f * n + v];
            }
            out.emplace_back("TEXCOORD_1", TINYGLTF_TYPE_VEC2, std::move(uv1));
            out.emplace_back("TEXCOORD_2", TINYGLTF_TYPE_VEC2, std::move(uv2));
        }
        return out;
    };
    const auto add_floats = [&](const std::vector<float>& values, int type, std::size_t count) {
        return b.accessor(b.view(values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER),
                          TINYGLTF_COMPONENT_TYPE_FLOAT, count, type);
    };
    const auto base_shading = shading(0);
    for (const auto& [name, type, values] : base_shading) prim.attributes[name] = add_floats(values, type, n);

    tinygltf::Mesh mesh;
    mesh.name = a.name;
    std::vector<tinygltf::Value> names;
    for (std::size_t f = 0; f < frames; ++f) {
        // A target holds the difference from the base (frame 0), in glTF axes.
        for (std::size_t v = 0; v < n; ++v) {
            float p[3], q[3];
            to_y_up(&a.positions[3 * (f * n + v)], p);
            to_y_up(&a.normals[3 * (f * n + v)], q);
            for (int c = 0; c < 3; ++c) {
                scratch_p[3 * v + static_cast<std::size_t>(c)] = p[c] - base_p[3 * v + static_cast<std::size_t>(c)];
                scratch_n[3 * v + static_cast<std::size_t>(c)] = q[c] - base_n[3 * v + static_cast<std::size_t>(c)];
            }
        }
        std::map<std::string, int> target;
        target["POSITION"] = b.vec3(scratch_p, TINYGLTF_TARGET_ARRAY_BUFFER, true);
        target["NORMAL"] = b.vec3(scratch_n, TINYGLTF_TARGET_ARRAY_BUFFER, false);
        auto frame_shading = shading(f);
        for (std::size_t i = 0; i < frame_shading.size(); ++i) {
            auto& [name, type, values] = frame_shading[i];
            const auto& base = std::get<2>(base_shading[i]);
            for (std::size_t j = 0; j < values.size(); ++j) values[j] -= base[j];
            target[name] = add_floats(values, type, n);
        }
        prim.targets.push_back(std::move(target));
        mesh.weights.push_back(f == 0 ? 1.0 : 0.0);
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04zu", f);
        names.emplace_back(std::string(name));
    }
    mesh.primitives.push_back(std::move(prim));
    tinygltf::Value::Object extras;
    extras["targetNames"] = tinygltf::Value(names);
    mesh.extras = tinygltf::Value(extras);
    model.meshes.push_back(std::move(mesh));

    tinygltf::Node node;
    node.mesh = 0;
    node.name = a.name;
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    // One key per frame; weights one-hot (values stay in 0…1, as Blender clamps them).
    std::vector<float> times(frames), weights(frames * frames, 0.0f);
    for (std::size_t f = 0; f < frames; ++f) {
        times[f] = key_time(f, a.fps);
        weights[f * frames + f] = 1.0f;
    }
    const int input = b.accessor(b.view(times.data(), times.size() * sizeof(float), 0), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                 frames, TINYGLTF_TYPE_SCALAR, {double{times.front()}}, {double{times.back()}});
    const int output = b.accessor(b.view(weights.data(), weights.size() * sizeof(float), 0),
                                  TINYGLTF_COMPONENT_TYPE_FLOAT, weights.size(), TINYGLTF_TYPE_SCALAR);
    tinygltf::Animation anim;
    anim.name = a.name + "_frames";
    tinygltf::AnimationSampler sampler;
    sampler.input = input;
    sampler.output = output;
    sampler.interpolation = "STEP";
    anim.samplers.push_back(sampler);
    tinygltf::AnimationChannel channel;
    channel.sampler = 0;
    channel.target_node = 0;
    channel.target_path = "weights";
    anim.channels.push_back(channel);
    model.animations.push_back(anim);
    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true))
        throw RuntimeError("glTF export: tinygltf could not serialise the model");
    return out.str();
}

}  // namespace wave
