// glTF 2.0 (.glb) through tinygltf: a morph-target animation with a one-hot STEP
// weights channel, as Blender and three.js read it (docs/conventions.md, "Export conventions").
// tinygltf is compiled here and nowhere else (docs/build-notes.md: never link Debian's
// libtinygltf.so, whose symbols clash with the copy inside libdraco).
// nlohmann/json first: tinygltf's implementation would include it with hidden visibility,
// and the writer's types (gltf_model.h), which hold its values, are not hidden.
#include <nlohmann/json.hpp>
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_ENABLE_DRACO  // the reader (gltf_read.cpp) decodes Draco bases
#include "gltf_library.h"
#undef TINYGLTF_IMPLEMENTATION  // the parts below see the declarations only

#include "core/format.h"
#include "gltf_model.h"
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/io.h"

#include <cmath>
#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <tuple>

namespace wave {

using detail::FrameArrays;
using detail::ModelWriter;
using detail::frame_arrays;

namespace {

// Sizes, indices and options always; the NaN/Inf scan only over the frames that will
// be written (`first` … `first + count − 1`): the files form writes one frame per call.
void check(const MorphAnimationView& a, std::size_t first = 0, std::size_t count = static_cast<std::size_t>(-1)) {
    const std::size_t n = a.vertex_count, f = a.frame_count;
    count = std::min(count, f > first ? f - first : 0);
    if (n == 0 || f == 0) throw InputError("glTF export: nothing to export (no vertices or no frames)");
    if (a.positions.size() != f * n * 3 || a.normals.size() != f * n * 3 || a.texcoords.size() != n * 2)
        throw InputError("glTF export: array sizes do not match " + std::to_string(f) + " frames of " +
                         std::to_string(n) + " vertices");
    for (const auto& [channel, name, width] : {std::tuple{a.reflect, "reflect", 1}, std::tuple{a.refract, "refract", 1},
                                               std::tuple{a.foam, "foam", 1}, std::tuple{a.colors, "colors", 3}}) {
        if (!channel.empty() && channel.size() != f * n * static_cast<std::size_t>(width))
            throw InputError(std::string("glTF export: ") + name + " holds " + std::to_string(channel.size()) +
                             " floats, expected " + std::to_string(f * n * static_cast<std::size_t>(width)));
        const std::size_t per_frame = n * static_cast<std::size_t>(width);
        for (std::size_t i = first * per_frame; i < std::min(channel.size(), (first + count) * per_frame); ++i)
            if (!std::isfinite(channel[i]))
                throw InputError(std::string("glTF export: ") + name + " of frame " + std::to_string(i / (n * static_cast<std::size_t>(width))) +
                                 " is NaN or infinite; refusing to write it");
    }
    if ((a.reflect.empty() || a.refract.empty() || a.foam.empty()) && !(a.reflect.empty() && a.refract.empty() && a.foam.empty()))
        throw InputError("glTF export: give reflect, refract and foam together (or none)");
    if (a.quantize && a.draco)
        throw InputError("glTF export: choose Draco or KHR_mesh_quantization, not both (Draco quantises itself)");
    if (a.meshopt && (a.draco || a.quantize))
        throw InputError("glTF export: EXT_meshopt_compression goes with neither Draco nor KHR_mesh_quantization (it filters the floats itself)");
    if (a.triangles.empty() || a.triangles.size() % 3) throw InputError("glTF export: the index list is not whole triangles");
    for (std::uint32_t v : a.triangles)
        if (v >= n) throw InputError("glTF export: triangle index " + std::to_string(v) + " >= vertex count " + std::to_string(n));
    if (!(a.fps > 0.0) || !std::isfinite(a.fps)) throw InputError("glTF export: fps must be > 0, got " + detail::format_number(a.fps));
    for (std::size_t i = 3 * n * first; i < 3 * n * (first + count); ++i)
        if (!std::isfinite(a.positions[i]) || !std::isfinite(a.normals[i]))
            throw InputError("glTF export: frame " + std::to_string(i / (3 * n)) + ", vertex " + std::to_string((i / 3) % n) +
                             " has a NaN or infinite position or normal; refusing to write it");
}

}  // namespace

MorphAnimationView frame_subview(const MorphAnimationView& v, std::size_t first, std::size_t count) {
    MorphAnimationView out = v;
    const std::size_t n = v.vertex_count;
    const auto cut = [&](std::span<const float> a, std::size_t width) {
        return a.empty() ? a : a.subspan(width * n * first, width * n * count);
    };
    out.positions = cut(v.positions, 3);
    out.normals = cut(v.normals, 3);
    out.reflect = cut(v.reflect, 1);
    out.refract = cut(v.refract, 1);
    out.foam = cut(v.foam, 1);
    out.colors = cut(v.colors, 3);
    out.first_frame = v.first_frame + first;
    out.frame_count = count;
    return out;
}

float key_time(std::size_t k, double fps) noexcept {
    const double exact = static_cast<double>(k) / fps;
    float t = static_cast<float>(exact);
    if (static_cast<double>(t) > exact) t = std::nextafter(t, -std::numeric_limits<float>::infinity());
    return t;
}

namespace {

// A node rotation (quaternion x, y, z, w, glTF axes) whose local +Z points along `z`
// (z up in, converted to glTF's y up), its +Y as close to up as it can be.
std::array<double, 4> rotation_with_z(std::array<double, 3> z_up) {
    std::array<double, 3> z{z_up[0], z_up[2], -z_up[1]};
    const double len = std::hypot(z[0], z[1], z[2]);
    for (double& c : z) c /= len;
    std::array<double, 3> up{0.0, 1.0, 0.0};
    if (std::abs(z[1]) > 0.999) up = {0.0, 0.0, -1.0};
    std::array<double, 3> x{up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]};
    const double lx = std::hypot(x[0], x[1], x[2]);
    for (double& c : x) c /= lx;
    const std::array<double, 3> y{z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    // Rotation matrix with columns x, y, z → quaternion.
    const double m00 = x[0], m11 = y[1], m22 = z[2], trace = m00 + m11 + m22;
    double qw, qx, qy, qz;
    if (trace > 0.0) {
        const double s = 0.5 / std::sqrt(trace + 1.0);
        qw = 0.25 / s, qx = (y[2] - z[1]) * s, qy = (z[0] - x[2]) * s, qz = (x[1] - y[0]) * s;
    } else if (m00 > m11 && m00 > m22) {
        const double s = 2.0 * std::sqrt(1.0 + m00 - m11 - m22);
        qw = (y[2] - z[1]) / s, qx = 0.25 * s, qy = (y[0] + x[1]) / s, qz = (z[0] + x[2]) / s;
    } else if (m11 > m22) {
        const double s = 2.0 * std::sqrt(1.0 + m11 - m00 - m22);
        qw = (z[0] - x[2]) / s, qx = (y[0] + x[1]) / s, qy = 0.25 * s, qz = (z[1] + y[2]) / s;
    } else {
        const double s = 2.0 * std::sqrt(1.0 + m22 - m00 - m11);
        qw = (x[1] - y[0]) / s, qx = (z[0] + x[2]) / s, qy = (z[1] + y[2]) / s, qz = 0.25 * s;
    }
    return {qx, qy, qz, qw};
}

constexpr std::uint32_t kGlbJson = 0x4E4F534Au, kGlbBin = 0x004E4942u;

// The 12-byte GLB header, the JSON chunk (padded with spaces) and the BIN chunk's
// 8-byte header for `bin_bytes` of buffer: what precedes the buffer's bytes in a .glb.
std::string glb_head(const std::string& json, std::size_t bin_bytes) {
    const std::size_t json_chunk = (json.size() + 3) / 4 * 4, bin_chunk = (bin_bytes + 3) / 4 * 4;
    const std::size_t total = 12 + 8 + json_chunk + (bin_bytes ? 8 + bin_chunk : 0);
    if (total > 0xFFFFFFFFu)
        throw LimitError("glTF export: the .glb would hold " + std::to_string(total) +
                         " bytes, more than its 4 GiB length field allows; write the gltf container (.gltf + .bin, "
                         "/outputs/container) or the files form");
    std::string out;
    const auto u32 = [&](std::size_t v) {
        const auto x = static_cast<std::uint32_t>(v);
        out.append(reinterpret_cast<const char*>(&x), 4);
    };
    out += "glTF";
    u32(2);
    u32(total);
    u32(json_chunk);
    u32(kGlbJson);
    out += json;
    out.append(json_chunk - json.size(), ' ');
    if (bin_bytes) {
        u32(bin_chunk);
        u32(kGlbBin);
    }
    return out;
}

// A whole .glb in memory: the head, the buffer, the BIN chunk's zero padding.
std::string glb_bytes(ModelWriter& w, std::vector<int> roots) {
    const std::string json = w.finish(std::move(roots));
    std::string out = glb_head(json, w.memory.size());
    out.append(reinterpret_cast<const char*>(w.memory.data()), w.memory.size());
    out.append((4 - w.memory.size() % 4) % 4, '\0');
    return out;
}

std::string frame_name(std::size_t f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu", f);
    return name;
}

// What a single-file form knows of its whole range before the frames arrive.
struct RangeInfo {
    std::size_t first_frame = 0, frame_count = 0;
    double fps = 24.0;
    std::string name;
};

// The STEP key times of every frame of the range, as an accessor.
int key_times(ModelWriter& w, const RangeInfo& r, std::vector<float>& times) {
    times.resize(r.frame_count);
    for (std::size_t f = 0; f < r.frame_count; ++f) times[f] = key_time(r.first_frame + f, r.fps);
    return w.b.accessor(w.b.view(times.data(), times.size() * sizeof(float), 0), TINYGLTF_COMPONENT_TYPE_FLOAT,
                        times.size(), TINYGLTF_TYPE_SCALAR, {double{times.front()}}, {double{times.back()}});
}

// The morph form a chunk of frames at a time: the base (the range's first frame) when
// made, a target per frame as the frames come, the mesh, node and animation at the end.
struct MorphBuilder {
    ModelWriter& w;
    RangeInfo range;
    FrameArrays base;
    tinygltf::Primitive prim;
    std::vector<tinygltf::Value> names;
    std::vector<double> weights;
    // Quantised normals' excess beyond ±1: (frame, NORMAL-only target), after the frames'.
    std::vector<std::pair<std::size_t, int>> overflow;

    MorphBuilder(ModelWriter& writer, const MorphAnimationView& first, std::size_t frame_count)
        : w(writer), range{first.first_frame, frame_count, first.fps, first.name}, base(frame_arrays(first, 0)) {
        // With Draco only the base is compressed (KHR_draco_mesh_compression covers a
        // primitive's attributes); the targets stay float, in the decoded point order,
        // which Draco's sequential method keeps equal to ours.
        prim = first.draco ? w.draco_primitive(first, base, true) : w.primitive(base);
    }
    // The frames of `a`, the next ones of the range.
    void add(const MorphAnimationView& a) {
        for (std::size_t f = 0; f < a.frame_count; ++f) {
            // A target holds the differences from the base (frame 0), in glTF axes.
            FrameArrays frame = frame_arrays(a, f);
            std::map<std::string, int> target;
            for (std::size_t i = 0; i < frame.attributes.size(); ++i) {
                auto& [name, type, values] = frame.attributes[i];
                const auto& b = std::get<2>(base.attributes[i]);
                for (std::size_t j = 0; j < values.size(); ++j) values[j] -= b[j];
                target[name] = w.floats(name, type, values, true);
                if (w.quant && name == "NORMAL")
                    if (const int excess = w.normal_overflow(values); excess >= 0) overflow.emplace_back(names.size(), excess);
            }
            prim.targets.push_back(std::move(target));
            weights.push_back(names.empty() ? 1.0 : 0.0);
            names.emplace_back(frame_name(a.first_frame + f));
        }
    }
    std::vector<int> finish() {
        if (names.size() != range.frame_count)
            throw InputError("glTF export: " + std::to_string(names.size()) + " frames written of " + std::to_string(range.frame_count));
        const std::size_t frames = range.frame_count, targets = frames + overflow.size();
        for (const auto& [frame, excess] : overflow) {
            prim.targets.push_back({{"NORMAL", excess}});
            names.emplace_back(frame_name(range.first_frame + frame) + " normals beyond 1");
            weights.push_back(frame == 0 ? 1.0 : 0.0);
        }
        tinygltf::Mesh mesh;
        mesh.name = range.name;
        mesh.weights = std::move(weights);
        mesh.primitives.push_back(std::move(prim));
        tinygltf::Value::Object extras;
        extras["targetNames"] = tinygltf::Value(std::move(names));
        mesh.extras = tinygltf::Value(extras);
        w.model.meshes.push_back(std::move(mesh));
        const int node = w.node(range.name, static_cast<int>(w.model.meshes.size() - 1));

        // One key per frame; weights 0 or 1 (Blender 3.4 clamps them to 0…1): frame f's
        // target and its normals' excess, if any.
        std::vector<float> times, one_hot(frames * targets, 0.0f);
        for (std::size_t f = 0; f < frames; ++f) one_hot[f * targets + f] = 1.0f;
        for (std::size_t j = 0; j < overflow.size(); ++j) one_hot[overflow[j].first * targets + frames + j] = 1.0f;
        tinygltf::AnimationSampler sampler;
        sampler.input = key_times(w, range, times);
        sampler.output = w.b.accessor(w.b.view(one_hot.data(), one_hot.size() * sizeof(float), 0),
                                      TINYGLTF_COMPONENT_TYPE_FLOAT, one_hot.size(), TINYGLTF_TYPE_SCALAR);
        sampler.interpolation = "STEP";
        tinygltf::Animation anim;
        anim.name = range.name + "_frames";
        anim.samplers.push_back(sampler);
        tinygltf::AnimationChannel channel;
        channel.sampler = 0;
        channel.target_node = node;
        channel.target_path = "weights";
        anim.channels.push_back(channel);
        w.model.animations.push_back(anim);
        return {node};
    }
};

// The nodes form a chunk of frames at a time: a parent node holds one child per frame;
// each child's scale is switched between 0 and 1 by STEP keys so that exactly one
// frame shows at a time.
struct NodesBuilder {
    ModelWriter& w;
    RangeInfo range;
    std::vector<int> children;

    NodesBuilder(ModelWriter& writer, const MorphAnimationView& first, std::size_t frame_count)
        : w(writer), range{first.first_frame, frame_count, first.fps, first.name} {}
    void add(const MorphAnimationView& a) {
        for (std::size_t f = 0; f < a.frame_count; ++f) {
            const std::string name = frame_name(a.first_frame + f);
            tinygltf::Mesh mesh;
            mesh.name = name;
            mesh.primitives = w.frame_primitives(a, f);
            w.model.meshes.push_back(std::move(mesh));
            const int mesh_index = static_cast<int>(w.model.meshes.size() - 1);
            if (w.quant || w.frame_unit != 1.0) {
                // The switched node holds the mesh node, whose transform undoes the quantisation
                // (or the Draco frame's unit).
                const int inner = w.node(name + "_mesh", mesh_index);
                tinygltf::Node outer;
                outer.name = name;
                outer.children = {inner};
                w.model.nodes.push_back(outer);
                children.push_back(static_cast<int>(w.model.nodes.size() - 1));
            } else {
                children.push_back(w.node(name, mesh_index));
            }
            if (children.size() > 1) w.model.nodes.back().scale = {0.0, 0.0, 0.0};
        }
    }
    std::vector<int> finish() {
        const std::size_t frames = range.frame_count;
        if (children.size() != frames)
            throw InputError("glTF export: " + std::to_string(children.size()) + " frames written of " + std::to_string(frames));
        tinygltf::Node parent;
        parent.name = range.name;
        parent.children = children;
        w.model.nodes.push_back(parent);
        const int root = static_cast<int>(w.model.nodes.size() - 1);
        std::vector<float> times;
        const int input = key_times(w, range, times);
        tinygltf::Animation anim;
        anim.name = range.name + "_frames";
        std::vector<float> scales(3 * frames);
        for (std::size_t f = 0; f < frames; ++f) {
            for (std::size_t k = 0; k < frames; ++k) {
                const float on = k == f ? 1.0f : 0.0f;
                scales[3 * k] = scales[3 * k + 1] = scales[3 * k + 2] = on;
            }
            tinygltf::AnimationSampler sampler;
            sampler.input = input;
            sampler.output = w.b.accessor(w.b.view(scales.data(), scales.size() * sizeof(float), 0),
                                          TINYGLTF_COMPONENT_TYPE_FLOAT, frames, TINYGLTF_TYPE_VEC3);
            sampler.interpolation = "STEP";
            anim.samplers.push_back(sampler);
            tinygltf::AnimationChannel channel;
            channel.sampler = static_cast<int>(anim.samplers.size() - 1);
            channel.target_node = children[f];
            channel.target_path = "scale";
            anim.channels.push_back(channel);
        }
        w.model.animations.push_back(anim);
        return {root};
    }
};

}  // namespace

std::string gltf_morph_glb(const MorphAnimationView& a) {
    check(a);
    ModelWriter w(a, a.frame_count + 1, nullptr, {}, true);
    MorphBuilder morph(w, a, a.frame_count);
    morph.add(a);
    return glb_bytes(w, morph.finish());
}

std::string gltf_nodes_glb(const MorphAnimationView& a) {
    check(a);
    ModelWriter w(a, a.draco ? 0 : a.frame_count);
    NodesBuilder nodes(w, a, a.frame_count);
    nodes.add(a);
    return glb_bytes(w, nodes.finish());
}

std::string gltf_frame_glb(const MorphAnimationView& a, std::size_t f) {
    check(a, f, 1);
    if (f >= a.frame_count)
        throw InputError("glTF export: frame " + std::to_string(f) + " of " + std::to_string(a.frame_count));
    // The file describes its own frame (so a slice's frame file is the whole run's, byte for byte).
    MorphAnimationView one = a;
    one.first_frame = a.first_frame + f;
    if (one.first_frame != 0) one.dressing.reset();  // the loop's frame 0 carries the scene, the others the water only
    ModelWriter w(one, a.draco ? 0 : 1);
    tinygltf::Mesh mesh;
    mesh.name = a.name;
    mesh.primitives = w.frame_primitives(a, f);
    w.model.meshes.push_back(std::move(mesh));
    return glb_bytes(w, {w.node(a.name, 0)});
}

struct AnimationFileWriter::State {
    std::string path, bin_path, bin_uri;  // the file; its buffer while streaming (the .bin with the gltf container)
    bool gltf_container = false, finished = false;
    std::FILE* bin = nullptr;
    MorphAnimationView header;  // the first chunk's settings; its spans are not kept
    // The dressing's arrays, owned: the chunks' own are gone when the file is finished.
    std::vector<float> seafloor_positions, seafloor_colors, seafloor_texcoords;
    std::vector<std::uint32_t> seafloor_triangles;
    std::optional<ModelWriter> writer;
    std::optional<MorphBuilder> morph;
    std::optional<NodesBuilder> nodes;

    ~State() {
        if (bin) std::fclose(bin);
        if (!finished) {  // failed or abandoned: nothing half-written stays
            std::remove(bin_path.c_str());
            std::remove(path.c_str());
        }
    }
};

AnimationFileWriter::AnimationFileWriter(std::string path, Form form, bool gltf_container, const MorphAnimationView& first,
                                         std::size_t frame_count)
    : state_(std::make_unique<State>()) {
    State& s = *state_;
    check(first);
    if (first.quantize && (form != Form::morph || !first.quantize_range))
        throw InputError("glTF export: a streamed file is quantised only as morph targets whose delta range is given "
                         "(quantize_range: KHR_mesh_quantization's range spans every frame); write it whole "
                         "(gltf_morph_glb, gltf_nodes_glb)");
    if (frame_count < first.frame_count) throw InputError("glTF export: the first chunk holds more frames than the range");
    // Float positions and normals alone: refused at once rather than after every frame.
    if (!gltf_container && !first.draco && 24.0 * static_cast<double>(frame_count) * static_cast<double>(first.vertex_count) > 4294967295.0)
        glb_head({}, static_cast<std::size_t>(24.0 * static_cast<double>(frame_count) * static_cast<double>(first.vertex_count)));
    s.path = std::move(path);
    s.gltf_container = gltf_container;
    const std::filesystem::path p(s.path);
    s.bin_path = gltf_container ? (p.parent_path() / (p.stem().string() + ".bin")).string() : s.path + ".bin-part";
    s.bin_uri = std::filesystem::path(s.bin_path).filename().string();
    s.bin = std::fopen(s.bin_path.c_str(), "wb");
    if (!s.bin) throw RuntimeError(s.bin_path + ": cannot create: " + std::strerror(errno));
    s.header = first;
    if (first.dressing) {
        const SceneDressing& d = *first.dressing;
        s.seafloor_positions.assign(d.seafloor_positions.begin(), d.seafloor_positions.end());
        s.seafloor_colors.assign(d.seafloor_colors.begin(), d.seafloor_colors.end());
        s.seafloor_texcoords.assign(d.seafloor_texcoords.begin(), d.seafloor_texcoords.end());
        s.seafloor_triangles.assign(d.seafloor_triangles.begin(), d.seafloor_triangles.end());
        SceneDressing& own = *s.header.dressing;
        own.seafloor_positions = s.seafloor_positions;
        own.seafloor_colors = s.seafloor_colors;
        own.seafloor_texcoords = s.seafloor_texcoords;
        own.seafloor_triangles = s.seafloor_triangles;
    }
    s.writer.emplace(s.header, 0, s.bin, s.bin_path, form == Form::morph);
    s.writer->dressing = s.header.dressing;
    if (form == Form::morph) s.morph.emplace(*s.writer, first, frame_count);
    else s.nodes.emplace(*s.writer, first, frame_count);
}

AnimationFileWriter::~AnimationFileWriter() = default;

void AnimationFileWriter::append(const MorphAnimationView& chunk) {
    State& s = *state_;
    check(chunk);
    if (chunk.vertex_count != s.header.vertex_count || chunk.triangles.size() != s.header.triangles.size())
        throw InputError("glTF export: a chunk of frames whose mesh differs from the first chunk's");
    if (s.morph) s.morph->add(chunk);
    else s.nodes->add(chunk);
}

std::vector<std::pair<std::string, std::size_t>> AnimationFileWriter::finish() {
    State& s = *state_;
    const std::vector<int> roots = s.morph ? s.morph->finish() : s.nodes->finish();
    std::string json = s.writer->finish(roots);
    const std::size_t bin_bytes = s.writer->sink.size;
    const auto close_bin = [&] {
        const int rc = std::fclose(std::exchange(s.bin, nullptr));
        if (rc != 0) throw RuntimeError(s.bin_path + ": cannot write: " + std::strerror(errno));
    };
    std::vector<std::pair<std::string, std::size_t>> written;
    if (s.gltf_container) {  // the buffer is already the .bin; the .gltf names it (as glb_to_gltf writes it)
        close_bin();
        nlohmann::json doc = nlohmann::json::parse(json);
        doc["buffers"][0]["uri"] = s.bin_uri;
        json = doc.dump(1) + "\n";
        write_file_atomic(s.path, json);
        written = {{std::filesystem::path(s.path).filename().string(), json.size()}, {s.bin_uri, bin_bytes}};
    } else {  // the head, then the buffer copied in by the kernel, then the BIN chunk's padding
        s.writer->sink.pad4();
        close_bin();
        const std::string head = glb_head(json, bin_bytes);
        write_file_atomic(s.path, head, s.bin_path);
        std::remove(s.bin_path.c_str());
        written = {{std::filesystem::path(s.path).filename().string(), head.size() + (bin_bytes + 3) / 4 * 4}};
    }
    s.finished = true;
    return written;
}

std::array<double, 4> gltf_look_rotation(const std::array<double, 3>& from, const std::array<double, 3>& to) {
    return rotation_with_z({from[0] - to[0], from[1] - to[1], from[2] - to[2]});  // +Z from the target back to the eye
}

double position_delta_range(std::span<const float> base, std::span<const float> frames, double so_far) noexcept {
    if (base.empty()) return so_far;
    for (std::size_t i = 0; i < frames.size(); ++i)
        so_far = std::max(so_far, std::abs(double{frames[i]} - double{base[i % base.size()]}));
    return so_far;
}

}  // namespace wave
