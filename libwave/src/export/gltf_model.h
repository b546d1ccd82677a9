// The glTF writer's parts (gltf.cpp, gltf_model.cpp, gltf_precision.cpp): the buffer and
// its accessors, a frame's arrays, the quantisation and Draco lattices, and ModelWriter,
// the model one file is built in. Internal: tinygltf's types do not reach a public header.
#pragma once

#include "gltf_library.h"
#include <nlohmann/json.hpp>

#include "draco_encode.h"
#include "libwave/errors.h"
#include "libwave/export.h"
#include "meshopt_codec.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace wave::detail {

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
inline void to_y_up(const float* in, float* out) {
    out[0] = in[0];
    out[1] = in[2];
    out[2] = -in[1];
}

// Everything one frame contributes to a primitive, in glTF axes: (attribute, accessor
// type, floats) for POSITION, NORMAL and the shading.
struct FrameArrays {
    std::vector<std::tuple<std::string, int, std::vector<float>>> attributes;
};

// Floats per element of an accessor type (SCALAR, VEC2, VEC3).
inline std::size_t components_of(int type) noexcept { return type == TINYGLTF_TYPE_VEC3 ? 3 : type == TINYGLTF_TYPE_VEC2 ? 2 : 1; }

// Frame f of `a` as its attributes (gltf_model.cpp).
FrameArrays frame_arrays(const MorphAnimationView& a, std::size_t f);

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

// A Draco frame's two lattices, in the file's units: a metre over `unit`, which the
// frame's node scales back. Draco takes no step finer than 2^-6 of a file unit, so a
// domain whose step should be finer (a laboratory basin, a small bay) is written in
// units of a power of two below the metre: its lattice decodes exactly, and the node's
// power-of-two scale is exact too.
struct DracoLattice {
    double domain = 0.0, skirt = 0.0;  // steps (file units)
    double unit = 1.0;                 // metres per file unit: a power of two, at most 1
};

// gltf_precision.cpp

// Draco's grids span a primitive's whole extent. A far-field skirt reaches tens of km
// beyond the domain (docs/far-field.md), whose rest positions TEXCOORD_0 spans [0, 1]²:
// positions gain the bits that keep the domain's vertices on the step the options give
// over the domain's own extent, and the UV maps the bits that keep [0, 1]'s step (at
// most Draco's 30). Without a skirt nothing changes.
DracoOptions draco_bits_for_reach(const DracoOptions& o, std::span<const float> texcoords,
    const std::vector<detail::DracoInput>& inputs);

// The domain's part (a triangle whose corners' rest positions, TEXCOORD_0, all lie in
// [0, 1]²) and the skirt's (every other triangle). None without a skirt.
std::optional<std::array<SkirtPart, 2>> split_skirt(std::span<const float> texcoords,
    std::span<const std::uint32_t> triangles, std::size_t n);

// The two parts' steps: the domain's the largest power of two at most its extent over
// 2^bits − 1 (the options' step), in units that make it at least 2^-6; the skirt's the
// smallest that keeps its reach under 2^23 steps and never finer than the domain's, so
// that the seam's points lie on both.
DracoLattice split_steps(std::span<const float> positions, const std::array<SkirtPart, 2>& parts, int bits);

// Puts a part's positions (3 per vertex) on the lattice of `step` (the seam's on the
// lattice of `seam_step`, a multiple of it) and returns the grid that holds them.
detail::DracoGrid snap_to_lattice(std::span<float> positions, const std::vector<char>& seam, double step,
    double seam_step);

// `domain`: the vertices whose frames the grid spans (empty: all of them). Frames of
// their own with a far-field skirt span the domain's part only: the skirt's positions
// are floats in the same node frame (docs/far-field.md, "Quantised frames").
Quantization quantization_for(const MorphAnimationView& a, bool morph_targets,
    std::span<const std::uint32_t> domain = {});

// EXT_meshopt_compression's exponential filter: the step (log2 of metres) of each
// POSITION component in glTF axes. Horizontally the largest power of two at most
// 1/256 of the shortest horizontal edge of the view's first frame (the error, half a
// step, under 0.2 % of any edge); heights the finer of 2^-16 m and that step. A value
// too large for 24 bits at its step gets a coarser exponent of its own (a far skirt).
std::array<int, 3> meshopt_position_steps(const MorphAnimationView& a);

// The triangles through meshoptimizer's index codec, encoded once for the frames of a
// files form that share them (the last list seen by this thread, compared whole).
const std::string& encoded_triangles(std::span<const std::uint32_t> triangles);

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
    ModelWriter(const MorphAnimationView& a, std::size_t frames, std::FILE* file = nullptr,
        std::string path = {}, bool morph_targets = false);
    // `width` components per vertex of `source`, for the vertices listed.
    static std::vector<float> gather(std::span<const float> source, std::size_t width,
        const std::vector<std::uint32_t>& vertices);
    // Normalised integers of `width` components padded to `stride` components (vertex
    // elements must start on 4-byte boundaries).
    template <class Int>
    int normalised(const std::vector<float>& values, std::size_t width, std::size_t stride, int component,
        int type, const std::function<double(std::size_t, std::size_t)>& encode, bool bounds, bool target);
    // An attribute through EXT_meshopt_compression: the exponential filter at the
    // attribute's steps (positions: position_steps), then the vertex codec; a position's
    // bounds are those of the values as they decode. Morph targets stay dense.
    int meshopt_floats(const std::string& name, int type, const std::vector<float>& values);
    // An attribute's accessor; `target` = a morph delta.
    int floats(const std::string& name, int type, const std::vector<float>& values, bool target = false);
    // Floats as they are, without bounds (not a position).
    int plain(int type, const std::vector<float>& values, bool target = false);
    // The skirt's positions (glTF axes) as floats in the quantised node's frame; a seam
    // vertex's exactly as the domain's int16 decodes (the same rounding, the same
    // division), so that the two primitives meet bit-equal.
    int skirt_positions(std::vector<float> values, const std::vector<char>& seam);
    // A quantised normal delta beyond ±1 (a normal turned by more than 60°): the excess
    // as a NORMAL-only target of its own, sparse, or -1 when no component exceeds 1.
    int normal_overflow(const std::vector<float>& delta);
    // A primitive of one frame (its own accessors; indices and TEXCOORD_0 shared).
    tinygltf::Primitive primitive(const FrameArrays& frame);
    // The same primitive compressed by Draco: the accessors keep count, type and
    // bounds but no bufferView; the extension points at the Draco bitstream. Every
    // attribute is compressed, TEXCOORD_0 too (the decoder reorders points).
    tinygltf::Primitive draco_primitive(const MorphAnimationView& a, const FrameArrays& frame,
        bool keep_order = false);
    tinygltf::Primitive draco_primitive(std::span<const std::uint32_t> triangles, std::size_t vertex_count,
        const std::vector<detail::DracoInput>& inputs, const DracoOptions& options, bool keep_order = false,
        const detail::DracoGrid* grid = nullptr);
    // A Draco frame of its own with a far-field skirt: the domain and the skirt as two
    // primitives, each on a lattice of its own (docs/far-field.md, "Draco frames").
    std::vector<tinygltf::Primitive> draco_split_primitives(const MorphAnimationView& a,
        const FrameArrays& frame, const std::array<SkirtPart, 2>& parts);
    // A quantised frame with a skirt: the domain's part on the int16 grid, the skirt's
    // positions and rest positions as floats (docs/far-field.md, "Quantised frames").
    std::vector<tinygltf::Primitive> split_primitives(const FrameArrays& frame);
    // A frame of its own (nodes, files): one primitive, or two for a frame with a skirt
    // on grids of its own (Draco, quantised).
    std::vector<tinygltf::Primitive> frame_primitives(const MorphAnimationView& a, std::size_t f);
    int node(const std::string& name, int mesh);
    // The seafloor, camera, sun and water material beside the water (SceneDressing).
    void dress(const SceneDressing& d, std::vector<int>& roots);
    // The glTF JSON of the model (its buffer 0 the sink's bytes): tinygltf serialises
    // it without the bytes, the buffer's length is set from the sink.
    std::string finish(std::vector<int> roots);
};

}  // namespace wave::detail
