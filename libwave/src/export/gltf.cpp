// glTF 2.0 (.glb) through tinygltf: a morph-target animation with a one-hot STEP
// weights channel, as Blender and three.js read it (docs/conventions.md, "Export conventions").
// tinygltf is compiled here and nowhere else (docs/build-notes.md: never link Debian's
// libtinygltf.so, whose symbols clash with the copy inside libdraco).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_ENABLE_DRACO  // the reader (gltf_read.cpp) decodes Draco bases
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/export.h"
#include "draco_encode.h"
#include "meshopt_codec.h"
#include "normalised.h"
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
namespace {

// Where the single buffer's bytes go: memory (the whole-file functions) or a file
// written as the frames come (AnimationFileWriter), its size counted either way.
struct BinSink {
    std::vector<unsigned char>* memory = nullptr;
    std::FILE* file = nullptr;
    std::string path;  // the file's, for errors
    std::size_t size = 0;

    void append(const void* data, std::size_t n) {
        if (memory) {
            const auto* b = static_cast<const unsigned char*>(data);
            memory->insert(memory->end(), b, b + n);
        } else if (n > 0 && std::fwrite(data, 1, n, file) != n) {
            throw RuntimeError(path + ": cannot write: " + std::strerror(errno));
        }
        size += n;
    }
    void pad4() {
        static constexpr unsigned char zeros[4] = {};
        if (size % 4) append(zeros, 4 - size % 4);
    }
};

// Appends raw floats or ints to the single buffer, 4-byte aligned, as one bufferView,
// and an accessor over it. Returns the accessor index.
struct GlbBuilder {
    tinygltf::Model& model;
    BinSink& bytes;
    // EXT_meshopt_compression: compressed views' bytes go to buffer 0 and the views
    // themselves lie in buffer 1, the extension's fallback buffer, which has no data.
    bool meshopt = false;
    std::size_t fallback = 0;  // buffer 1's length so far
    std::vector<std::pair<int, nlohmann::json>> view_extensions{};  // tinygltf writes no bufferView extensions

    // `count` elements of `stride` bytes compressed by meshoptimizer (`encoded`) as a view.
    int compressed_view(const std::string& encoded, std::size_t count, std::size_t stride, int target,
                        detail::MeshoptMode mode, detail::MeshoptFilter filter) {
        bytes.pad4();
        tinygltf::BufferView v;
        v.buffer = 1;
        v.byteOffset = fallback;
        v.byteLength = count * stride;
        v.target = target;
        nlohmann::json ext{{"buffer", 0}, {"byteOffset", bytes.size}, {"byteLength", encoded.size()},
                           {"byteStride", stride}, {"count", count}, {"mode", detail::meshopt_mode_name(mode)}};
        if (filter != detail::MeshoptFilter::none) ext["filter"] = detail::meshopt_filter_name(filter);
        bytes.append(encoded.data(), encoded.size());
        fallback += (count * stride + 3) / 4 * 4;
        model.bufferViews.push_back(v);
        view_extensions.emplace_back(static_cast<int>(model.bufferViews.size() - 1), std::move(ext));
        return static_cast<int>(model.bufferViews.size() - 1);
    }

    int view(const void* data, std::size_t size, int target, std::size_t stride = 0) {
        bytes.pad4();
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteStride = stride;
        v.byteOffset = bytes.size;
        v.byteLength = size;
        v.target = target;
        bytes.append(data, size);
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

    // `count` elements of `element` bytes, `stride` bytes apart in `data`. A morph
    // target (`target`) is stored sparse when its non-zero elements with their indices
    // take under 3/4 of the dense view (the still vertices of a target: land, the far
    // skirt, foam-free water), as no view at all when every element is zero.
    int stored(const void* data, std::size_t element, std::size_t stride, std::size_t count, int component, int type,
               bool normalized, std::vector<double> min, std::vector<double> max, bool target) {
        const auto* in = static_cast<const unsigned char*>(data);
        const auto zero = [&](std::size_t e) {
            return std::all_of(in + e * stride, in + e * stride + element, [](unsigned char c) { return c == 0; });
        };
        std::vector<std::uint32_t> nonzero;
        if (target)
            for (std::size_t e = 0; e < count; ++e)
                if (!zero(e)) nonzero.push_back(static_cast<std::uint32_t>(e));
        const std::size_t index_bytes = count <= 65536 ? 2 : 4;
        const bool sparse = target && 4 * nonzero.size() * (index_bytes + element) < 3 * count * stride;
        int index;
        if (!sparse) {
            index = accessor(view(data, count * stride, TINYGLTF_TARGET_ARRAY_BUFFER, stride == element ? 0 : stride),
                             component, count, type, std::move(min), std::move(max));
        } else {
            index = accessor(-1, component, count, type, std::move(min), std::move(max));
            if (!nonzero.empty()) {
                std::vector<unsigned char> values(nonzero.size() * element), indices(nonzero.size() * index_bytes);
                for (std::size_t i = 0; i < nonzero.size(); ++i) {
                    std::memcpy(&values[i * element], in + nonzero[i] * stride, element);
                    if (index_bytes == 2) {
                        const auto k = static_cast<std::uint16_t>(nonzero[i]);
                        std::memcpy(&indices[2 * i], &k, 2);
                    } else {
                        std::memcpy(&indices[4 * i], &nonzero[i], 4);
                    }
                }
                tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
                a.sparse.isSparse = true;
                a.sparse.count = static_cast<int>(nonzero.size());
                a.sparse.indices.bufferView = view(indices.data(), indices.size(), 0);
                a.sparse.indices.byteOffset = 0;
                a.sparse.indices.componentType =
                    index_bytes == 2 ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
                a.sparse.values.bufferView = view(values.data(), values.size(), 0);
                a.sparse.values.byteOffset = 0;
            }
        }
        model.accessors[static_cast<std::size_t>(index)].normalized = normalized;
        return index;
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

// Everything one frame contributes to a primitive, in glTF axes: (attribute, accessor
// type, floats) for POSITION, NORMAL and the shading.
struct FrameArrays {
    std::vector<std::tuple<std::string, int, std::vector<float>>> attributes;
};

// Floats per element of an accessor type (SCALAR, VEC2, VEC3).
std::size_t components_of(int type) noexcept { return type == TINYGLTF_TYPE_VEC3 ? 3 : type == TINYGLTF_TYPE_VEC2 ? 2 : 1; }

FrameArrays frame_arrays(const MorphAnimationView& a, std::size_t f) {
    const std::size_t n = a.vertex_count;
    FrameArrays out;
    std::vector<float> p(3 * n), q(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        to_y_up(&a.positions[3 * (f * n + v)], &p[3 * v]);
        to_y_up(&a.normals[3 * (f * n + v)], &q[3 * v]);
    }
    out.attributes.emplace_back("POSITION", TINYGLTF_TYPE_VEC3, std::move(p));
    out.attributes.emplace_back("NORMAL", TINYGLTF_TYPE_VEC3, std::move(q));
    const auto slice = [&](std::span<const float> c, std::size_t width) {
        return std::vector<float>(c.begin() + static_cast<std::ptrdiff_t>(width * f * n),
                                  c.begin() + static_cast<std::ptrdiff_t>(width * (f + 1) * n));
    };
    if (!a.colors.empty()) out.attributes.emplace_back("COLOR_0", TINYGLTF_TYPE_VEC3, slice(a.colors, 3));
    if (a.reflect.empty()) return out;
    if (a.layout == ScalarLayout::custom) {
        out.attributes.emplace_back("_REFLECT", TINYGLTF_TYPE_SCALAR, slice(a.reflect, 1));
        out.attributes.emplace_back("_REFRACT", TINYGLTF_TYPE_SCALAR, slice(a.refract, 1));
        out.attributes.emplace_back("_FOAM", TINYGLTF_TYPE_SCALAR, slice(a.foam, 1));
    } else {
        std::vector<float> uv1(2 * n), uv2(2 * n, 0.0f);
        for (std::size_t v = 0; v < n; ++v) {
            uv1[2 * v] = a.reflect[f * n + v];
            uv1[2 * v + 1] = a.refract[f * n + v];
            uv2[2 * v] = a.foam[f * n + v];
        }
        out.attributes.emplace_back("TEXCOORD_1", TINYGLTF_TYPE_VEC2, std::move(uv1));
        out.attributes.emplace_back("TEXCOORD_2", TINYGLTF_TYPE_VEC2, std::move(uv2));
    }
    return out;
}

// KHR_mesh_quantization. Frames of their own (nodes, files): positions as normalised
// int16 around `origin` (glTF axes) with half-range `scale`, undone by the mesh node's
// transform. Morph targets: the base's positions stay float, p / scale, and
// the deltas are normalised int16 with `scale` the largest delta, so that their step
// follows the motion, not the mesh's extent (a far-field skirt spans tens of km).
// Normals as normalised int8 (morph deltas of normals stay float: they can exceed 1);
// UV maps as normalised uint16, their morph deltas as normalised int16.
struct Quantization {
    std::array<double, 3> origin{};
    double scale = 1.0;
    bool float_base = false;  // morph targets: base positions float, deltas int16
    // A position's component c (glTF axes) in the node's frame, and as int16 steps
    // before rounding.
    double in_node(double p, std::size_t c) const noexcept { return (p - origin[c]) / scale; }
    double steps(double p, std::size_t c) const noexcept { return in_node(p, c) * 32767.0; }
};

// Draco's grids span a primitive's whole extent. A far-field skirt reaches tens of km
// beyond the domain (docs/far-field.md), whose rest positions TEXCOORD_0 spans [0, 1]²:
// positions gain the bits that keep the domain's vertices on the step the options give
// over the domain's own extent, and the UV maps the bits that keep [0, 1]'s step (at
// most Draco's 30). Without a skirt nothing changes.
DracoOptions draco_bits_for_reach(const DracoOptions& o, std::span<const float> texcoords,
                                  const std::vector<detail::DracoInput>& inputs) {
    std::array<double, 2> uv_lo{0.0, 0.0}, uv_hi{1.0, 1.0};
    for (std::size_t i = 0; i < texcoords.size(); ++i)
        uv_lo[i % 2] = std::min(uv_lo[i % 2], double{texcoords[i]}), uv_hi[i % 2] = std::max(uv_hi[i % 2], double{texcoords[i]});
    const double uv_span = std::max(uv_hi[0] - uv_lo[0], uv_hi[1] - uv_lo[1]);
    if (!(uv_span > 1.0)) return o;
    const auto position = std::find_if(inputs.begin(), inputs.end(), [](const detail::DracoInput& in) { return in.name == "POSITION"; });
    double all = 0.0, domain = 0.0;  // the largest side of the bounding box: of every vertex, of the domain's
    if (position != inputs.end()) {
        std::array<double, 3> lo, hi, dlo, dhi;
        lo.fill(std::numeric_limits<double>::infinity()), dlo = lo;
        hi.fill(-std::numeric_limits<double>::infinity()), dhi = hi;
        for (std::size_t v = 0; 3 * v + 2 < position->values.size() && 2 * v + 1 < texcoords.size(); ++v) {
            const bool inside = texcoords[2 * v] >= 0.0f && texcoords[2 * v] <= 1.0f && texcoords[2 * v + 1] >= 0.0f &&
                                texcoords[2 * v + 1] <= 1.0f;
            for (std::size_t c = 0; c < 3; ++c) {
                const double x = position->values[3 * v + c];
                lo[c] = std::min(lo[c], x), hi[c] = std::max(hi[c], x);
                if (inside) dlo[c] = std::min(dlo[c], x), dhi[c] = std::max(dhi[c], x);
            }
        }
        for (std::size_t c = 0; c < 3; ++c) all = std::max(all, hi[c] - lo[c]), domain = std::max(domain, dhi[c] - dlo[c]);
    }
    const auto widen = [](int bits, double ratio) {
        return ratio > 1.0 ? std::min(30, bits + static_cast<int>(std::ceil(std::log2(ratio)))) : bits;
    };
    DracoOptions wide = o;
    wide.texcoord_bits = widen(o.texcoord_bits, uv_span);
    if (domain > 0.0) wide.position_bits = widen(o.position_bits, all / domain);
    return wide;
}

// A Draco frame of its own with a skirt is written as two primitives, the domain and
// the skirt, each on a lattice of its own (docs/far-field.md, "Draco frames"). Draco
// quantises q = (p − origin) · (1 / step) + ½ and decodes origin + q · step in float32:
// with a power-of-two step, an origin on the lattice and q < 2^23 every one of these
// operations is exact, so a point of the lattice decodes to itself, whatever the
// frame's extent. A vertex at rest stays put from frame to frame, and the seam's
// vertices, on the coarser lattice in both primitives, decode bit-equal in both.
struct SkirtPart {
    std::vector<std::uint32_t> vertices;   // the frame's vertex of each of the part's
    std::vector<std::uint32_t> triangles;  // indices into `vertices`
    std::vector<char> seam;                // per part vertex: a vertex of the other part too
};

// The domain's part (a triangle whose corners' rest positions, TEXCOORD_0, all lie in
// [0, 1]²) and the skirt's (every other triangle). None without a skirt.
std::optional<std::array<SkirtPart, 2>> split_skirt(std::span<const float> texcoords, std::span<const std::uint32_t> triangles,
                                                    std::size_t n) {
    std::vector<char> inside(n);
    for (std::size_t v = 0; v < n; ++v)
        inside[v] = texcoords[2 * v] >= 0.0f && texcoords[2 * v] <= 1.0f && texcoords[2 * v + 1] >= 0.0f && texcoords[2 * v + 1] <= 1.0f;
    std::array<std::vector<char>, 2> used{std::vector<char>(n, 0), std::vector<char>(n, 0)};
    std::vector<char> part_of(triangles.size() / 3);
    for (std::size_t t = 0; t < part_of.size(); ++t) {
        const std::uint32_t* c = &triangles[3 * t];
        part_of[t] = inside[c[0]] && inside[c[1]] && inside[c[2]] ? 0 : 1;
        for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(part_of[t])][c[k]] = 1;
    }
    if (std::find(part_of.begin(), part_of.end(), 1) == part_of.end()) return std::nullopt;
    for (std::size_t v = 0; v < n; ++v)  // a vertex no triangle uses goes where its rest position lies
        if (!used[0][v] && !used[1][v]) used[inside[v] ? 0 : 1][v] = 1;
    std::array<SkirtPart, 2> parts;
    std::vector<std::uint32_t> local(n);
    for (std::size_t k = 0; k < 2; ++k) {
        for (std::size_t v = 0; v < n; ++v)
            if (used[k][v]) {
                local[v] = static_cast<std::uint32_t>(parts[k].vertices.size());
                parts[k].vertices.push_back(static_cast<std::uint32_t>(v));
                parts[k].seam.push_back(used[1 - k][v]);
            }
        for (std::size_t t = 0; t < part_of.size(); ++t)
            if (static_cast<std::size_t>(part_of[t]) == k)
                for (int c = 0; c < 3; ++c) parts[k].triangles.push_back(local[triangles[3 * t + static_cast<std::size_t>(c)]]);
    }
    return parts;
}

// The largest power of two ≤ x, the smallest ≥ x (x > 0), exactly.
double power_of_two_below(double x) {
    int e = 0;
    std::frexp(x, &e);  // x = m · 2^e, m in [½, 1)
    return std::ldexp(1.0, e - 1);
}
double power_of_two_above(double x) {
    int e = 0;
    const double m = std::frexp(x, &e);
    return std::ldexp(1.0, m == 0.5 ? e - 1 : e);
}

constexpr double kExactSteps = 8388607.0;  // 2^23 − 1: Draco's float32 `q + ½` stays exact below it
// Draco hands an explicit grid's origin and range through text with six decimals
// (std::to_string in its Options): multiples of 2^-6 print exactly, finer steps do not.
constexpr double kDecimalStep = 0.015625;

// A Draco frame's two lattices, in the file's units: a metre over `unit`, which the
// frame's node scales back. Draco takes no step finer than 2^-6 of a file unit, so a
// domain whose step should be finer (a laboratory basin, a small bay) is written in
// units of a power of two below the metre: its lattice decodes exactly, and the node's
// power-of-two scale is exact too.
struct DracoLattice {
    double domain = 0.0, skirt = 0.0;  // steps (file units)
    double unit = 1.0;                 // metres per file unit: a power of two, at most 1
};

// The two parts' steps: the domain's the largest power of two at most its extent over
// 2^bits − 1 (the options' step), in units that make it at least 2^-6; the skirt's the
// smallest that keeps its reach under 2^23 steps and never finer than the domain's, so
// that the seam's points lie on both.
DracoLattice split_steps(std::span<const float> positions, const std::array<SkirtPart, 2>& parts, int bits) {
    std::array<double, 2> span{}, magnitude{};
    for (std::size_t k = 0; k < 2; ++k) {
        std::array<double, 3> lo, hi;
        lo.fill(std::numeric_limits<double>::infinity());
        hi.fill(-std::numeric_limits<double>::infinity());
        for (const std::uint32_t v : parts[k].vertices)
            for (std::size_t c = 0; c < 3; ++c) {
                const double x = positions[3 * v + c];
                lo[c] = std::min(lo[c], x), hi[c] = std::max(hi[c], x);
                magnitude[k] = std::max(magnitude[k], std::abs(x));
            }
        for (std::size_t c = 0; c < 3; ++c) span[k] = std::max(span[k], hi[c] - lo[c]);
    }
    DracoLattice l;
    const double wanted = power_of_two_below(std::max(span[0], 1e-6) / (std::ldexp(1.0, std::clamp(bits, 1, 30)) - 1.0));
    l.unit = std::min(1.0, wanted / kDecimalStep);
    for (std::size_t k = 0; k < 2; ++k) span[k] /= l.unit, magnitude[k] /= l.unit;
    l.domain = std::max(kDecimalStep, wanted / l.unit);
    l.skirt = std::max(l.domain, power_of_two_above(std::max(span[1], magnitude[1]) / (kExactSteps - 2.0)));
    // Snapping the seam to the skirt's step widens the domain's extent by up to one of them.
    while ((std::max(span[0], magnitude[0]) + l.skirt) / l.domain >= kExactSteps - 1.0) {
        l.domain *= 2.0;
        l.skirt = std::max(l.skirt, l.domain);
    }
    return l;
}

// Puts a part's positions (3 per vertex) on the lattice of `step` (the seam's on the
// lattice of `seam_step`, a multiple of it) and returns the grid that holds them.
detail::DracoGrid snap_to_lattice(std::span<float> positions, const std::vector<char>& seam, double step, double seam_step) {
    std::array<double, 3> lo, hi;
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < seam.size(); ++v) {
        const double s = seam[v] ? seam_step : step;
        for (std::size_t c = 0; c < 3; ++c) {
            const double x = std::round(double{positions[3 * v + c]} / s) * s;
            positions[3 * v + c] = static_cast<float>(x);  // exact: fewer than 2^24 steps from 0
            lo[c] = std::min(lo[c], x), hi[c] = std::max(hi[c], x);
        }
    }
    detail::DracoGrid grid;
    double steps = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
        grid.origin[c] = static_cast<float>(lo[c]);
        steps = std::max(steps, (hi[c] - lo[c]) / step);
    }
    grid.bits = 1;
    while (std::ldexp(1.0, grid.bits) - 1.0 < steps) ++grid.bits;
    if (grid.bits > 23) throw RuntimeError("glTF export: a Draco lattice needs more than 23 bits");  // split_steps prevents it
    grid.range = static_cast<float>((std::ldexp(1.0, grid.bits) - 1.0) * step);
    return grid;
}

// `domain`: the vertices whose frames the grid spans (empty: all of them). Frames of
// their own with a far-field skirt span the domain's part only: the skirt's positions
// are floats in the same node frame (docs/far-field.md, "Quantised frames").
Quantization quantization_for(const MorphAnimationView& a, bool morph_targets, std::span<const std::uint32_t> domain = {}) {
    std::array<double, 3> lo{}, hi{};
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    const std::size_t n = a.vertex_count;
    float p[3], p0[3];
    double delta = a.quantize_range.value_or(0.0);
    const bool scan_deltas = morph_targets && !a.quantize_range;
    const std::size_t per_frame = domain.empty() ? n : domain.size();
    for (std::size_t k = 0; n > 0 && k < a.positions.size() / 3 / n * per_frame; ++k) {
        const std::size_t i = domain.empty() ? k : k / per_frame * n + domain[k % per_frame];
        to_y_up(&a.positions[3 * i], p);
        for (std::size_t c = 0; c < 3; ++c) lo[c] = std::min(lo[c], double{p[c]}), hi[c] = std::max(hi[c], double{p[c]});
        if (scan_deltas && i >= n) {
            to_y_up(&a.positions[3 * (i % n)], p0);  // the base is the range's first frame
            for (std::size_t c = 0; c < 3; ++c) delta = std::max(delta, std::abs(double{p[c]} - double{p0[c]}));
        }
    }
    Quantization q;
    double half = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
        q.origin[c] = 0.5 * (lo[c] + hi[c]);
        half = std::max(half, 0.5 * (hi[c] - lo[c]));
    }
    q.float_base = morph_targets;
    // Float base positions keep the run's own coordinates (an extent's centre can lie
    // tens of km from the coast when a skirt reaches out on the sea side only).
    if (morph_targets) q.origin = {0.0, 0.0, 0.0};
    // A still animation keeps a 1 mm range (its deltas are all 0).
    q.scale = morph_targets ? std::max(delta, 1e-3) : std::max(half, 1e-6);
    return q;
}

// EXT_meshopt_compression's exponential filter: the step (log2 of metres) of each
// POSITION component in glTF axes. Horizontally the largest power of two at most
// 1/256 of the shortest horizontal edge of the view's first frame (the error, half a
// step, under 0.2 % of any edge); heights the finer of 2^-16 m and that step. A value
// too large for 24 bits at its step gets a coarser exponent of its own (a far skirt).
std::array<int, 3> meshopt_position_steps(const MorphAnimationView& a) {
    double shortest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t + 2 < a.triangles.size(); t += 3)
        for (std::size_t k = 0; k < 3; ++k) {
            const float* p = &a.positions[3 * std::size_t{a.triangles[t + k]}];
            const float* q = &a.positions[3 * std::size_t{a.triangles[t + (k + 1) % 3]}];
            const double dx = double{p[0]} - q[0], dy = double{p[1]} - q[1], d2 = dx * dx + dy * dy;
            if (d2 > 0.0) shortest = std::min(shortest, d2);
        }
    shortest = std::sqrt(shortest);
    const int h = std::isfinite(shortest) ? std::clamp(static_cast<int>(std::floor(std::log2(shortest / 256.0))), -60, 40) : -12;
    const int z = std::min(-16, h);
    return {h, z, h};
}

// The triangles through meshoptimizer's index codec, encoded once for the frames of a
// files form that share them (the last list seen by this thread, compared whole).
const std::string& encoded_triangles(std::span<const std::uint32_t> triangles) {
    thread_local std::vector<std::uint32_t> last;
    thread_local std::string encoded;
    if (last.size() != triangles.size() || !std::equal(last.begin(), last.end(), triangles.begin())) {
        encoded = detail::meshopt_encode_triangles(triangles);
        last.assign(triangles.begin(), triangles.end());
    }
    return encoded;
}

// A model with one buffer, the shared index and TEXCOORD_0 accessors, and helpers.
struct ModelWriter {
    tinygltf::Model model;
    std::vector<unsigned char> memory;
    BinSink sink;
    GlbBuilder b{model, sink};
    int indices = -1, texcoord0 = -1;
    std::optional<Quantization> quant;
    // Quantised frames of their own with a far-field skirt: the domain's part and the
    // skirt's, each a primitive with its own indices and TEXCOORD_0 (split_primitives).
    std::optional<std::array<SkirtPart, 2>> split;
    std::array<int, 2> part_indices{-1, -1}, part_texcoord0{-1, -1};
    std::optional<SceneDressing> dressing;
    double frame_unit = 1.0;  // metres per unit of the last frame's positions (a Draco frame with a skirt)
    std::array<int, 3> position_steps{};  // EXT_meshopt_compression: meshopt_position_steps

    // `frames`: how many frames' attributes the buffer will hold (reserved up front:
    // growing a buffer of hundreds of MB by doubling was a third of the export time).
    // With `file`, the buffer's bytes go there instead (AnimationFileWriter).
    // `morph_targets`: the frames are the morph form's targets (its quantisation).
    ModelWriter(const MorphAnimationView& a, std::size_t frames, std::FILE* file = nullptr, std::string path = {},
                bool morph_targets = false)
        : dressing(a.dressing) {
        model.buffers.emplace_back();
        if (file) {
            sink.file = file;
            sink.path = std::move(path);
        } else {
            sink.memory = &memory;
            const std::size_t per_vertex = 4 * (3 + 3 + 2 + 4 + (a.colors.empty() ? 0 : 3));
            memory.reserve(frames * a.vertex_count * per_vertex + a.triangles.size_bytes() + 8 * a.vertex_count +
                           4 * frames * frames + (1 << 16));
        }
        model.asset.version = "2.0";
        model.asset.generator = "libwave";
        // What a reader (read_animation, `wave convert`) needs that glTF has no field for.
        tinygltf::Value::Object info;
        info["fps"] = tinygltf::Value(a.fps);
        info["first_frame"] = tinygltf::Value(static_cast<int>(a.first_frame));
        info["loop_frames"] = tinygltf::Value(static_cast<int>(a.loop_frames));
        info["name"] = tinygltf::Value(a.name);
        info["scene"] = tinygltf::Value(a.scene);
        if (!a.run_key.empty()) info["run_key"] = tinygltf::Value(a.run_key);
        tinygltf::Value::Object extras;
        extras["libwave"] = tinygltf::Value(info);
        model.asset.extras = tinygltf::Value(extras);
        if (a.draco) return;  // every primitive carries its own compressed indices and UVs
        if (a.meshopt) {
            b.meshopt = true;
            position_steps = meshopt_position_steps(a);
            model.extensionsUsed.push_back("EXT_meshopt_compression");
            model.extensionsRequired.push_back("EXT_meshopt_compression");
            indices = b.accessor(b.compressed_view(encoded_triangles(a.triangles), a.triangles.size(), 4,
                                                   TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, detail::MeshoptMode::triangles,
                                                   detail::MeshoptFilter::none),
                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, a.triangles.size(), TINYGLTF_TYPE_SCALAR);
            texcoord0 = floats("TEXCOORD_0", TINYGLTF_TYPE_VEC2, std::vector<float>(a.texcoords.begin(), a.texcoords.end()));
            return;
        }
        if (a.quantize) {
            if (!morph_targets) split = split_skirt(a.texcoords, a.triangles, a.vertex_count);
            std::span<const std::uint32_t> domain;  // the vertices the grid spans (empty: all)
            if (split) domain = (*split)[0].vertices;
            quant = quantization_for(a, morph_targets, domain);
            model.extensionsUsed.push_back("KHR_mesh_quantization");
            model.extensionsRequired.push_back("KHR_mesh_quantization");
        }
        if (split) {
            for (std::size_t k = 0; k < 2; ++k) {
                const std::vector<std::uint32_t>& t = (*split)[k].triangles;
                part_indices[k] = b.accessor(b.view(t.data(), t.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, t.size(), TINYGLTF_TYPE_SCALAR);
                const std::vector<float> uv = gather(a.texcoords, 2, (*split)[k].vertices);
                // The skirt's rest positions lie beyond [0, 1]², which normalised uint16 cannot hold.
                part_texcoord0[k] = k == 0 ? floats("TEXCOORD_0", TINYGLTF_TYPE_VEC2, uv) : plain(TINYGLTF_TYPE_VEC2, uv);
            }
            return;
        }
        indices = b.accessor(b.view(a.triangles.data(), a.triangles.size_bytes(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, a.triangles.size(), TINYGLTF_TYPE_SCALAR);
        // A far-field skirt's rest positions lie beyond [0, 1]², which normalised uint16
        // would clamp onto the domain's edge (the quantised morph form's skirt then read
        // as domain: the viewer framed 160 km of it): they stay float.
        std::vector<float> uv(a.texcoords.begin(), a.texcoords.end());
        const bool beyond = std::any_of(uv.begin(), uv.end(), [](float t) { return t < 0.0f || t > 1.0f; });
        texcoord0 = quant && beyond ? plain(TINYGLTF_TYPE_VEC2, uv) : floats("TEXCOORD_0", TINYGLTF_TYPE_VEC2, uv);
    }
    // `width` components per vertex of `source`, for the vertices listed.
    static std::vector<float> gather(std::span<const float> source, std::size_t width, const std::vector<std::uint32_t>& vertices) {
        std::vector<float> out(width * vertices.size());
        for (std::size_t i = 0; i < vertices.size(); ++i)
            std::copy_n(source.begin() + static_cast<std::ptrdiff_t>(width * vertices[i]), width, out.begin() + static_cast<std::ptrdiff_t>(width * i));
        return out;
    }
    // Normalised integers of `width` components padded to `stride` components (vertex
    // elements must start on 4-byte boundaries).
    template <class Int>
    int normalised(const std::vector<float>& values, std::size_t width, std::size_t stride, int component, int type,
                   const std::function<double(std::size_t, std::size_t)>& encode, bool bounds, bool target) {
        const std::size_t count = values.size() / width;
        std::vector<Int> q(count * stride, 0);
        std::vector<double> lo(width, std::numeric_limits<double>::infinity()), hi(width, -std::numeric_limits<double>::infinity());
        for (std::size_t v = 0; v < count; ++v)
            for (std::size_t c = 0; c < width; ++c) {
                const Int x = detail::nearest<Int>(encode(v, c));
                q[v * stride + c] = x;
                lo[c] = std::min(lo[c], static_cast<double>(x)), hi[c] = std::max(hi[c], static_cast<double>(x));
            }
        return b.stored(q.data(), width * sizeof(Int), stride * sizeof(Int), count, component, type, true,
                        bounds ? lo : std::vector<double>{}, bounds ? hi : std::vector<double>{}, target);
    }
    // An attribute through EXT_meshopt_compression: the exponential filter at the
    // attribute's steps (positions: position_steps), then the vertex codec; a position's
    // bounds are those of the values as they decode. Morph targets stay dense.
    int meshopt_floats(const std::string& name, int type, const std::vector<float>& values) {
        const std::size_t width = components_of(type), count = values.size() / width;
        std::array<int, 3> steps = position_steps;
        if (name != "POSITION") steps.fill(name == "NORMAL" ? -15 : name == "TEXCOORD_0" ? -21 : -17);
        std::vector<std::uint32_t> words(values.size());
        std::vector<float> decoded(values.size());
        detail::encode_exponential(values, width, std::span<const int>(steps.data(), width), words, decoded);
        std::vector<double> lo, hi;
        if (name == "POSITION") {
            lo.assign(3, std::numeric_limits<double>::infinity());
            hi.assign(3, -std::numeric_limits<double>::infinity());
            for (std::size_t i = 0; i < decoded.size(); ++i)
                lo[i % 3] = std::min(lo[i % 3], double{decoded[i]}), hi[i % 3] = std::max(hi[i % 3], double{decoded[i]});
        }
        const int view = b.compressed_view(detail::meshopt_encode_attributes(words.data(), count, 4 * width), count, 4 * width,
                                           TINYGLTF_TARGET_ARRAY_BUFFER, detail::MeshoptMode::attributes,
                                           detail::MeshoptFilter::exponential);
        return b.accessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, count, type, std::move(lo), std::move(hi));
    }
    // An attribute's accessor; `target` = a morph delta.
    int floats(const std::string& name, int type, const std::vector<float>& values, bool target = false) {
        if (b.meshopt) return meshopt_floats(name, type, values);
        if (quant && name == "POSITION" && quant->float_base && !target) {
            std::vector<float> scaled(values.size());
            for (std::size_t i = 0; i < values.size(); ++i)
                scaled[i] = static_cast<float>((values[i] - quant->origin[i % 3]) / quant->scale);
            return b.vec3(scaled, TINYGLTF_TARGET_ARRAY_BUFFER, true);
        }
        if (quant && name == "POSITION") {
            const Quantization& qz = *quant;
            return normalised<std::int16_t>(values, 3, 4, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3,
                                            [&](std::size_t v, std::size_t c) {
                                                return target ? values[3 * v + c] / qz.scale * 32767.0 : qz.steps(values[3 * v + c], c);
                                            }, true, target);
        }
        if (quant && name == "NORMAL" && !target)
            return normalised<std::int8_t>(values, 3, 4, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_TYPE_VEC3,
                                           [&](std::size_t v, std::size_t c) { return values[3 * v + c] * 127.0; }, false, false);
        if (quant && name == "NORMAL")  // the part within ±1 (normal_overflow holds the rest)
            return normalised<std::int16_t>(values, 3, 4, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3,
                                            [&](std::size_t v, std::size_t c) {
                                                return std::clamp(double{values[3 * v + c]}, -1.0, 1.0) * 32767.0;
                                            }, false, true);
        if (quant && name.rfind("TEXCOORD_", 0) == 0) {
            if (target)
                return normalised<std::int16_t>(values, 2, 2, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC2,
                                                [&](std::size_t v, std::size_t c) { return values[2 * v + c] * 32767.0; }, false, true);
            return normalised<std::uint16_t>(values, 2, 2, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC2,
                                             [&](std::size_t v, std::size_t c) { return values[2 * v + c] * 65535.0; }, false, false);
        }
        if (name == "POSITION" && !target) return b.vec3(values, TINYGLTF_TARGET_ARRAY_BUFFER, true);
        if (name != "POSITION") return plain(type, values, target);
        // A position target's bounds (the validator checks them).
        std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
        for (std::size_t i = 0; i < values.size(); ++i) {
            lo[i % 3] = std::min(lo[i % 3], double{values[i]});
            hi[i % 3] = std::max(hi[i % 3], double{values[i]});
        }
        return b.stored(values.data(), 3 * sizeof(float), 3 * sizeof(float), values.size() / 3, TINYGLTF_COMPONENT_TYPE_FLOAT,
                        type, false, std::move(lo), std::move(hi), target);
    }
    // Floats as they are, without bounds (not a position).
    int plain(int type, const std::vector<float>& values, bool target = false) {
        const std::size_t width = components_of(type);
        return b.stored(values.data(), width * sizeof(float), width * sizeof(float), values.size() / width,
                        TINYGLTF_COMPONENT_TYPE_FLOAT, type, false, {}, {}, target);
    }
    // The skirt's positions (glTF axes) as floats in the quantised node's frame; a seam
    // vertex's exactly as the domain's int16 decodes (the same rounding, the same
    // division), so that the two primitives meet bit-equal.
    int skirt_positions(std::vector<float> values, const std::vector<char>& seam) {
        const Quantization& qz = *quant;
        for (std::size_t i = 0; i < values.size(); ++i) {
            const std::size_t c = i % 3;
            if (!seam[i / 3]) {
                values[i] = static_cast<float>(qz.in_node(values[i], c));
                continue;
            }
            values[i] = static_cast<float>(detail::snorm16(detail::nearest<std::int16_t>(qz.steps(values[i], c))));
        }
        return b.vec3(values, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    }
    // A quantised normal delta beyond ±1 (a normal turned by more than 60°): the excess
    // as a NORMAL-only target of its own, sparse, or -1 when no component exceeds 1.
    int normal_overflow(const std::vector<float>& delta) {
        std::vector<float> excess(delta.size());
        bool any = false;
        for (std::size_t i = 0; i < delta.size(); ++i) {
            excess[i] = delta[i] - std::clamp(delta[i], -1.0f, 1.0f);
            any = any || excess[i] != 0.0f;
        }
        if (!any) return -1;
        return normalised<std::int16_t>(excess, 3, 4, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3,
                                        [&](std::size_t v, std::size_t c) { return excess[3 * v + c] * 32767.0; }, false, true);
    }
    // A primitive of one frame (its own accessors; indices and TEXCOORD_0 shared).
    tinygltf::Primitive primitive(const FrameArrays& frame) {
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.indices = indices;
        prim.attributes["TEXCOORD_0"] = texcoord0;
        for (const auto& [name, type, values] : frame.attributes) prim.attributes[name] = floats(name, type, values);
        return prim;
    }
    // The same primitive compressed by Draco: the accessors keep count, type and
    // bounds but no bufferView; the extension points at the Draco bitstream. Every
    // attribute is compressed, TEXCOORD_0 too (the decoder reorders points).
    tinygltf::Primitive draco_primitive(const MorphAnimationView& a, const FrameArrays& frame, bool keep_order = false) {
        std::vector<detail::DracoInput> inputs{{"TEXCOORD_0", 2, a.texcoords}};
        for (const auto& [name, type, values] : frame.attributes)
            inputs.push_back({name, static_cast<int>(components_of(type)), values});
        return draco_primitive(a.triangles, a.vertex_count, inputs, draco_bits_for_reach(*a.draco, a.texcoords, inputs), keep_order);
    }
    tinygltf::Primitive draco_primitive(std::span<const std::uint32_t> triangles, std::size_t vertex_count,
                                        const std::vector<detail::DracoInput>& inputs, const DracoOptions& options,
                                        bool keep_order = false, const detail::DracoGrid* grid = nullptr) {
        const detail::DracoOutput encoded = detail::draco_encode(triangles, vertex_count, inputs, options, keep_order, grid);
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.indices = b.accessor(-1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, triangles.size(), TINYGLTF_TYPE_SCALAR);
        tinygltf::Value::Object ids;
        for (const detail::DracoInput& in : inputs) {
            std::vector<double> lo, hi;
            if (in.name == "POSITION") {
                lo.assign(3, std::numeric_limits<double>::infinity());
                hi.assign(3, -std::numeric_limits<double>::infinity());
                for (std::size_t i = 0; i < in.values.size(); ++i) {
                    lo[i % 3] = std::min(lo[i % 3], double{in.values[i]});
                    hi[i % 3] = std::max(hi[i % 3], double{in.values[i]});
                }
            }
            const int type = in.components == 3 ? TINYGLTF_TYPE_VEC3 : in.components == 2 ? TINYGLTF_TYPE_VEC2 : TINYGLTF_TYPE_SCALAR;
            prim.attributes[in.name] = b.accessor(-1, TINYGLTF_COMPONENT_TYPE_FLOAT, vertex_count, type, lo, hi);
            ids[in.name] = tinygltf::Value(encoded.ids.at(in.name));
        }
        tinygltf::Value::Object ext;
        ext["bufferView"] = tinygltf::Value(b.view(encoded.bytes.data(), encoded.bytes.size(), 0));
        ext["attributes"] = tinygltf::Value(ids);
        prim.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(ext);
        if (model.extensionsUsed.empty()) {
            model.extensionsUsed.push_back("KHR_draco_mesh_compression");
            model.extensionsRequired.push_back("KHR_draco_mesh_compression");
        }
        return prim;
    }
    // A Draco frame of its own with a far-field skirt: the domain and the skirt as two
    // primitives, each on a lattice of its own (docs/far-field.md, "Draco frames").
    std::vector<tinygltf::Primitive> draco_split_primitives(const MorphAnimationView& a, const FrameArrays& frame,
                                                            const std::array<SkirtPart, 2>& parts) {
        std::span<const float> all;  // POSITION, glTF axes
        for (const auto& [name, type, values] : frame.attributes)
            if (name == "POSITION") all = values;
        const DracoLattice lattice = split_steps(all, parts, a.draco->position_bits);
        frame_unit = lattice.unit;
        std::vector<tinygltf::Primitive> out;
        for (std::size_t k = 0; k < 2; ++k) {
            const SkirtPart& part = parts[k];
            const std::size_t n = part.vertices.size();
            std::vector<std::vector<float>> values;  // per input, the part's vertices
            std::vector<detail::DracoInput> inputs;
            values.reserve(frame.attributes.size() + 1);
            const auto add = [&](std::string name, std::size_t components, std::span<const float> source) {
                values.push_back(gather(source, components, part.vertices));  // reserved: earlier spans stay valid
                inputs.push_back({std::move(name), static_cast<int>(components), values.back()});
            };
            add("TEXCOORD_0", 2, a.texcoords);
            for (const auto& [name, type, source] : frame.attributes) add(name, components_of(type), source);
            std::vector<float>& positions = values[static_cast<std::size_t>(std::distance(
                inputs.begin(), std::find_if(inputs.begin(), inputs.end(), [](const auto& in) { return in.name == "POSITION"; })))];
            for (float& x : positions) x = static_cast<float>(x / lattice.unit);  // exact: a power of two
            const detail::DracoGrid grid =
                snap_to_lattice(positions, part.seam, k == 0 ? lattice.domain : lattice.skirt, lattice.skirt);
            DracoOptions options = *a.draco;
            options.texcoord_bits = draco_bits_for_reach(options, inputs[0].values, inputs).texcoord_bits;
            out.push_back(draco_primitive(part.triangles, n, inputs, options, false, &grid));
        }
        return out;
    }
    // A quantised frame with a skirt: the domain's part on the int16 grid, the skirt's
    // positions and rest positions as floats (docs/far-field.md, "Quantised frames").
    std::vector<tinygltf::Primitive> split_primitives(const FrameArrays& frame) {
        std::vector<tinygltf::Primitive> out(2);
        for (std::size_t k = 0; k < 2; ++k) {
            const SkirtPart& part = (*split)[k];
            tinygltf::Primitive& prim = out[k];
            prim.mode = TINYGLTF_MODE_TRIANGLES;
            prim.indices = part_indices[k];
            prim.attributes["TEXCOORD_0"] = part_texcoord0[k];
            for (const auto& [name, type, values] : frame.attributes) {
                std::vector<float> v = gather(values, components_of(type), part.vertices);
                prim.attributes[name] = k == 1 && name == "POSITION" ? skirt_positions(std::move(v), part.seam) : floats(name, type, v);
            }
        }
        return out;
    }
    // A frame of its own (nodes, files): one primitive, or two for a frame with a skirt
    // on grids of its own (Draco, quantised).
    std::vector<tinygltf::Primitive> frame_primitives(const MorphAnimationView& a, std::size_t f) {
        const FrameArrays frame = frame_arrays(a, f);
        frame_unit = 1.0;
        if (split) return split_primitives(frame);
        if (!a.draco) return {primitive(frame)};
        if (const std::optional<std::array<SkirtPart, 2>> parts = split_skirt(a.texcoords, a.triangles, a.vertex_count))
            return draco_split_primitives(a, frame, *parts);
        return {draco_primitive(a, frame)};
    }
    int node(const std::string& name, int mesh) {
        tinygltf::Node n;
        n.name = name;
        n.mesh = mesh;
        if (quant) {  // undoes the position quantisation
            if (!quant->float_base) n.translation = {quant->origin[0], quant->origin[1], quant->origin[2]};
            n.scale = {quant->scale, quant->scale, quant->scale};
        } else if (frame_unit != 1.0) {  // a Draco frame in units below the metre (DracoLattice)
            n.scale = {frame_unit, frame_unit, frame_unit};
        }
        model.nodes.push_back(n);
        return static_cast<int>(model.nodes.size() - 1);
    }
    // The seafloor, camera, sun and water material beside the water (SceneDressing).
    void dress(const SceneDressing& d, std::vector<int>& roots) {
        const auto add_root = [&](tinygltf::Node n) {
            model.nodes.push_back(std::move(n));
            roots.push_back(static_cast<int>(model.nodes.size() - 1));
        };
        if (d.water_material) {
            tinygltf::Material water;
            water.name = "water";
            water.doubleSided = true;
            water.pbrMetallicRoughness.baseColorFactor = {0.02, 0.12, 0.16, 1.0};
            water.pbrMetallicRoughness.metallicFactor = 0.0;
            water.pbrMetallicRoughness.roughnessFactor = 0.05;
            tinygltf::Value::Object transmission, ior;
            transmission["transmissionFactor"] = tinygltf::Value(1.0);
            ior["ior"] = tinygltf::Value(1.333);
            water.extensions["KHR_materials_transmission"] = tinygltf::Value(transmission);
            water.extensions["KHR_materials_ior"] = tinygltf::Value(ior);
            model.materials.push_back(water);
            for (tinygltf::Mesh& m : model.meshes)
                for (tinygltf::Primitive& prim : m.primitives) prim.material = static_cast<int>(model.materials.size() - 1);
            model.extensionsUsed.push_back("KHR_materials_transmission");
            model.extensionsUsed.push_back("KHR_materials_ior");
        }
        if (!d.seafloor_triangles.empty()) {
            const std::size_t n = d.seafloor_positions.size() / 3;
            std::vector<float> p(3 * n);
            for (std::size_t v = 0; v < n; ++v) to_y_up(&d.seafloor_positions[3 * v], &p[3 * v]);
            tinygltf::Primitive prim;
            prim.mode = TINYGLTF_MODE_TRIANGLES;
            prim.attributes["POSITION"] = b.vec3(p, TINYGLTF_TARGET_ARRAY_BUFFER, true);
            std::vector<float> c(d.seafloor_colors.begin(), d.seafloor_colors.end());
            prim.attributes["COLOR_0"] = b.vec3(c, TINYGLTF_TARGET_ARRAY_BUFFER, false);
            if (d.seafloor_texcoords.size() == 2 * n) {
                std::vector<float> uv(d.seafloor_texcoords.begin(), d.seafloor_texcoords.end());
                prim.attributes["TEXCOORD_0"] = b.accessor(b.view(uv.data(), uv.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER),
                                                           TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC2);
            }
            prim.indices = b.accessor(b.view(d.seafloor_triangles.data(), d.seafloor_triangles.size_bytes(),
                                             TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, d.seafloor_triangles.size(), TINYGLTF_TYPE_SCALAR);
            tinygltf::Material sand;
            sand.name = "seafloor";
            sand.pbrMetallicRoughness.metallicFactor = 0.0;
            sand.pbrMetallicRoughness.roughnessFactor = 0.9;  // base colour white: COLOR_0 is the colour
            tinygltf::Value::Object extras;
            if (!d.caustic_images.empty()) {
                tinygltf::Value::Object caustics;
                caustics["images"] = tinygltf::Value(d.caustic_images);
                caustics["frames"] = tinygltf::Value(static_cast<int>(d.caustic_frames));
                caustics["fps"] = tinygltf::Value(d.caustic_fps);
                caustics["texCoord"] = tinygltf::Value(0);
                caustics["full_scale"] = tinygltf::Value(d.caustic_full_scale);
                extras["libwave_caustics"] = tinygltf::Value(caustics);
            }
            if (!d.sunbeam_volumes.empty()) {
                tinygltf::Value::Object sunbeams;
                sunbeams["volumes"] = tinygltf::Value(d.sunbeam_volumes);
                sunbeams["frames"] = tinygltf::Value(static_cast<int>(d.sunbeam_frames));
                sunbeams["fps"] = tinygltf::Value(d.sunbeam_fps);
                sunbeams["grid"] = tinygltf::Value(std::string("sunlight"));
                sunbeams["attenuation"] = tinygltf::Value(d.sunbeam_attenuation);
                const std::array<double, 3>& t = d.sunbeam_direction;
                sunbeams["direction"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(t[0]), tinygltf::Value(t[2]), tinygltf::Value(-t[1])});
                extras["libwave_sunbeams"] = tinygltf::Value(sunbeams);
            }
            if (!extras.empty()) sand.extras = tinygltf::Value(extras);
            model.materials.push_back(sand);
            prim.material = static_cast<int>(model.materials.size() - 1);
            tinygltf::Mesh mesh;
            mesh.name = "seafloor";
            mesh.primitives.push_back(prim);
            model.meshes.push_back(mesh);
            tinygltf::Node node;
            node.name = "seafloor";
            node.mesh = static_cast<int>(model.meshes.size() - 1);
            add_root(std::move(node));
        }
        if (d.camera) {
            tinygltf::Camera cam;
            cam.name = "camera";
            cam.type = "perspective";
            cam.perspective.yfov = d.camera_yfov;
            cam.perspective.aspectRatio = d.camera_aspect;
            cam.perspective.znear = 0.05;
            cam.perspective.zfar = 1e5;  // tinygltf writes zfar even when 0 (infinite), which the validator refuses
            model.cameras.push_back(cam);
            const std::array<double, 3> eye = d.camera_position;
            tinygltf::Node node;
            node.name = "camera";
            node.camera = static_cast<int>(model.cameras.size() - 1);
            node.rotation.assign(d.camera_rotation.begin(), d.camera_rotation.end());
            node.translation = {eye[0], eye[2], -eye[1]};
            add_root(std::move(node));
        }
        if (d.sun) {
            tinygltf::Light sun;
            sun.name = "sun";
            sun.type = "directional";
            sun.intensity = 3.0;
            sun.color = {1.0, 0.96, 0.9};
            model.lights.push_back(sun);
            tinygltf::Node node;
            node.name = "sun";
            node.rotation.assign(d.sun_rotation.begin(), d.sun_rotation.end());  // a directional light shines along its −Z
            tinygltf::Value::Object light;
            light["light"] = tinygltf::Value(static_cast<int>(model.lights.size() - 1));
            node.extensions["KHR_lights_punctual"] = tinygltf::Value(light);
            add_root(std::move(node));
        }
    }
    // The glTF JSON of the model (its buffer 0 the sink's bytes): tinygltf serialises
    // it without the bytes, the buffer's length is set from the sink.
    std::string finish(std::vector<int> roots) {
        if (dressing) dress(*dressing, roots);
        tinygltf::Scene scene;
        scene.nodes = roots;
        model.scenes.push_back(scene);
        model.defaultScene = 0;
        std::ostringstream out;
        tinygltf::TinyGLTF writer;
        if (!writer.WriteGltfSceneToStream(&model, out, false, true))
            throw RuntimeError("glTF export: tinygltf could not serialise the model");
        const std::string glb = out.str();  // a GLB of the JSON chunk alone (the buffer's data is not in the model)
        std::uint32_t length = 0;
        std::memcpy(&length, glb.data() + 12, 4);
        nlohmann::json doc = nlohmann::json::parse(glb.substr(20, length));
        doc["buffers"][0]["byteLength"] = sink.size;
        if (b.meshopt) {
            for (auto& [view, ext] : b.view_extensions) doc["bufferViews"][static_cast<std::size_t>(view)]["extensions"]["EXT_meshopt_compression"] = ext;
            doc["buffers"].push_back({{"byteLength", b.fallback}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
        }
        return doc.dump();
    }
};

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
