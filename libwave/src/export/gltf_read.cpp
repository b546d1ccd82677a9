// Reading libwave's own glTF outputs back (`wave convert`): every form, layout,
// quantisation, and Draco-compressed morph bases. Only files libwave wrote: the asset
// carries `extras.libwave` (fps, first frame, loop) that glTF has no field for.
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/io.h"
#include "core/files.h"
#include "core/format.h"
#include "core/json_input.h"
#include "normalised.h"
#include "meshopt_codec.h"

#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <array>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <unordered_map>

namespace wave {
namespace {

// The buffer views a file's frames alone use (morph targets, the nodes form's later
// meshes), left in the file: each is read when its frame is decoded and dropped after
// it, so a reader holds the file's static parts and one frame, not the whole buffer.
// `length` bytes of a file from `at` into `into` (the stream's state cleared first).
void read_at(std::ifstream& in, const std::string& path, std::size_t at, char* into, std::size_t length) {
    in.clear();
    in.seekg(static_cast<std::streamoff>(at));
    if (!in.read(into, static_cast<std::streamsize>(length))) throw InputError(path + ": cannot read the file");
}

// A view compressed by EXT_meshopt_compression, as its extension describes it (the
// view itself then points at the compressed bytes: unpack_meshopt).
struct MeshoptView {
    detail::MeshoptMode mode = detail::MeshoptMode::attributes;
    detail::MeshoptFilter filter = detail::MeshoptFilter::none;
    std::size_t count = 0, stride = 0;
};

// The decoded bytes of a compressed view, or InputError naming the file and the view.
std::vector<unsigned char> decode_meshopt(const std::string& path, int view, const MeshoptView& m, std::span<const unsigned char> compressed) {
    std::vector<unsigned char> out(m.count * m.stride);
    const std::string error = detail::meshopt_decode(m.mode, m.filter, m.count, m.stride, compressed, out);
    if (!error.empty()) throw InputError(path + ": bufferView " + std::to_string(view) + " (EXT_meshopt_compression): " + error);
    return out;
}

// A compressed view decoded once and kept for the next file of a files form (a player's
// FrameReader): the frames' files hold the same triangles and rest positions, so a view
// whose compressed bytes and codec equal the kept ones decodes to the kept bytes (the
// codecs are deterministic) and is not decoded again.
struct KeptView {
    MeshoptView codec;
    std::vector<unsigned char> compressed, decoded;
};
using ViewMemo = std::map<int, KeptView>;

struct LazyViews {
    std::string file;      // where buffer 0's bytes are: the .glb, or a .gltf's .bin
    std::size_t base = 0;  // the file offset of buffer 0's first byte
    std::map<int, std::pair<std::size_t, std::size_t>> where{};  // view → (byteOffset, byteLength) in buffer 0
    std::map<int, MeshoptView> meshopt{};  // the views of `where` that are compressed
    ViewMemo* memo = nullptr;  // kept decodings of the views in `kept` (a FrameReader's), if any
    std::set<int> kept{};
    mutable std::ifstream in{};
    mutable std::map<int, std::vector<unsigned char>> loaded{};

    const std::vector<unsigned char>* bytes(int view, const std::string& path) const {
        const auto it = where.find(view);
        if (it == where.end()) return nullptr;
        const auto m = meshopt.find(view);
        if (memo && m != meshopt.end() && kept.count(view)) {
            std::vector<unsigned char> compressed(it->second.second);
            read_at(in, path, base + it->second.first, reinterpret_cast<char*>(compressed.data()), compressed.size());
            KeptView& k = (*memo)[view];
            const MeshoptView& c = m->second;
            if (k.compressed != compressed || k.codec.mode != c.mode || k.codec.filter != c.filter || k.codec.count != c.count ||
                k.codec.stride != c.stride) {
                k.decoded = decode_meshopt(path, view, c, compressed);
                k.codec = c;
                k.compressed = std::move(compressed);
            }
            return &k.decoded;
        }
        auto [slot, fresh] = loaded.try_emplace(view);
        if (fresh) {
            slot->second.resize(it->second.second);
            read_at(in, path, base + it->second.first, reinterpret_cast<char*>(slot->second.data()), it->second.second);
            if (m != meshopt.end()) slot->second = decode_meshopt(path, view, m->second, slot->second);
        }
        return &slot->second;
    }
};

struct Reader {
    const tinygltf::Model& m;
    const std::string& path;
    const LazyViews* lazy = nullptr;  // views still in the file, if any
    bool normals = true;              // false: frames are read without their normals (a player that has Blender compute them)

    [[noreturn]] void fail(const std::string& what) const { throw InputError(path + ": " + what); }

    // Drops the views read from the file since the last call (a frame is decoded).
    void release() const {
        if (lazy) lazy->loaded.clear();
    }

    // The bytes of a buffer view, from `offset` within it, checked to hold `count`
    // elements of `element` bytes `stride` apart.
    const unsigned char* view_bytes(int view, std::size_t offset, std::size_t count, std::size_t element,
                                    std::size_t stride, const std::string& what) const {
        if (view < 0 || static_cast<std::size_t>(view) >= m.bufferViews.size()) fail(what + " has no data");
        const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(view)];
        if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= m.buffers.size()) fail(what + " has no buffer");
        const std::vector<unsigned char>* in_file = lazy ? lazy->bytes(view, path) : nullptr;
        const std::vector<unsigned char>& data = in_file ? *in_file : m.buffers[static_cast<std::size_t>(v.buffer)].data;
        // Bounded by the view, not by the buffer: an accessor running past its view read
        // the next view's bytes as its own (a byteStride too long for the view).
        if (!in_file && (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset))
            fail("bufferView " + std::to_string(view) + " lies outside its buffer");
        const std::size_t length = in_file ? data.size() : v.byteLength;
        if (offset > length || (count > 0 && (count - 1) * stride + element > length - offset))
            fail(what + " runs past its bufferView " + std::to_string(view) + " (" + std::to_string(count) + " elements of " +
                 std::to_string(element) + " bytes, " + std::to_string(stride) + " apart, from byte " + std::to_string(offset) +
                 " of its " + std::to_string(length) + ")");
        return data.data() + (in_file ? 0 : v.byteOffset) + offset;
    }

    // One component as a float (normalised integers mapped to [-1, 1] / [0, 1]).
    double component(const tinygltf::Accessor& a, const unsigned char* p, const std::string& what) const {
        switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return f; }
            case TINYGLTF_COMPONENT_TYPE_SHORT: { std::int16_t q; std::memcpy(&q, p, 2); return a.normalized ? detail::snorm16(q) : q; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t q; std::memcpy(&q, p, 2); return a.normalized ? q / 65535.0 : q; }
            case TINYGLTF_COMPONENT_TYPE_BYTE: { std::int8_t q; std::memcpy(&q, p, 1); return a.normalized ? std::max(q / 127.0, -1.0) : q; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return a.normalized ? *p / 255.0 : *p;
            default: fail(what + ": unsupported component type");
        }
    }

    // An accessor as floats, `width` components per element: its buffer view (zeros
    // without one), then its sparse substitutions (morph targets of still vertices).
    std::vector<float> floats(int index, std::size_t width) const {
        if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size()) fail("an attribute has no accessor");
        const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
        const std::string what = "accessor " + std::to_string(index);
        const std::size_t comps = a.type == TINYGLTF_TYPE_SCALAR ? 1 : a.type == TINYGLTF_TYPE_VEC2 ? 2
                                  : a.type == TINYGLTF_TYPE_VEC3 ? 3 : a.type == TINYGLTF_TYPE_VEC4 ? 4 : 0;
        if (comps != width) fail(what + " has " + std::to_string(comps) + " components, expected " + std::to_string(width));
        const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
        if (size <= 0) fail(what + ": unknown component type");
        const std::size_t element = comps * static_cast<std::size_t>(size);
        // An accessor without a view (zeros) holds no bytes to bound its count: refuse
        // counts beyond any libwave output rather than allocate them.
        if (a.count > (std::size_t{1} << 28)) fail(what + " claims " + std::to_string(a.count) + " elements");
        std::vector<float> out(a.count * comps, 0.0f);
        const auto decode = [&](const unsigned char* p, std::size_t e) {
            for (std::size_t c = 0; c < comps; ++c) out[e * comps + c] = static_cast<float>(component(a, p + c * static_cast<std::size_t>(size), what));
        };
        if (a.bufferView >= 0) {
            const std::size_t stride = static_cast<std::size_t>(a.bufferView) < m.bufferViews.size() &&
                                               m.bufferViews[static_cast<std::size_t>(a.bufferView)].byteStride
                                           ? m.bufferViews[static_cast<std::size_t>(a.bufferView)].byteStride : element;
            if (stride < element || stride > 256) fail(what + ": byte stride " + std::to_string(stride));
            const unsigned char* p = view_bytes(a.bufferView, a.byteOffset, a.count, element, stride, what);
            if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT && stride == element) {  // the bytes are the floats
                if (!out.empty()) std::memcpy(out.data(), p, out.size() * sizeof(float));
            } else {
                for (std::size_t e = 0; e < a.count; ++e) decode(p + e * stride, e);
            }
        }
        if (a.sparse.isSparse) {
            if (a.sparse.count < 1 || static_cast<std::size_t>(a.sparse.count) > a.count) fail(what + ": bad sparse count");
            const auto n = static_cast<std::size_t>(a.sparse.count);
            const int itype = a.sparse.indices.componentType;
            if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                fail(what + ": bad sparse index type " + std::to_string(itype));
            const int isize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(itype));
            const unsigned char* ip = view_bytes(a.sparse.indices.bufferView, static_cast<std::size_t>(std::max(a.sparse.indices.byteOffset, 0)),
                                                 n, static_cast<std::size_t>(isize), static_cast<std::size_t>(isize), what + "'s sparse indices");
            const unsigned char* vp = view_bytes(a.sparse.values.bufferView, static_cast<std::size_t>(std::max(a.sparse.values.byteOffset, 0)),
                                                 n, element, element, what + "'s sparse values");
            std::uint64_t last = 0;
            for (std::size_t i = 0; i < n; ++i) {
                std::uint32_t k = 0;
                if (isize == 1) k = ip[i];
                else if (isize == 2) { std::uint16_t q; std::memcpy(&q, ip + 2 * i, 2); k = q; }
                else std::memcpy(&k, ip + 4 * i, 4);
                if (k >= a.count || (i > 0 && k <= last)) fail(what + ": sparse indices out of range or not increasing");
                last = k;
                decode(vp + i * element, k);
            }
        }
        return out;
    }

    std::vector<std::uint32_t> indices(int index) const {
        if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size()) fail("the mesh has no indices accessor");
        const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
        if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) fail("indices are not uint32");
        if (a.count > (std::size_t{1} << 30)) fail("the indices claim " + std::to_string(a.count) + " elements");
        const unsigned char* p = view_bytes(a.bufferView, a.byteOffset, a.count, 4, 4, "the indices");
        std::vector<std::uint32_t> out(a.count);
        if (a.count > 0) std::memcpy(out.data(), p, 4 * a.count);
        return out;
    }

    // The static translation and scale of the node showing `mesh` (the quantisation's
    // transform; a switched-off nodes-form frame has scale 0, which is the switch, not
    // the geometry's).
    std::pair<std::array<double, 3>, std::array<double, 3>> transform(int mesh) const {
        std::array<double, 3> t{0, 0, 0}, s{1, 1, 1};
        for (const tinygltf::Node& n : m.nodes) {
            if (n.mesh != mesh) continue;
            if (n.translation.size() == 3) t = {n.translation[0], n.translation[1], n.translation[2]};
            if (n.scale.size() == 3 && (n.scale[0] != 0.0 || n.scale[1] != 0.0 || n.scale[2] != 0.0)) s = {n.scale[0], n.scale[1], n.scale[2]};
        }
        return {t, s};
    }
};

// glTF y up → z up: (X, Y, Z) → (X, −Z, Y), with the node's translation and scale
// (the translation only for positions, not for morph deltas).
void append_z_up(std::vector<float>& out, const std::vector<float>& v, const std::array<double, 3>& t,
                 const std::array<double, 3>& s, bool translate) {
    // Untransformed values are copied as they are (0 + −0.0 would turn −0.0 into +0.0,
    // and the file written again would differ from the original).
    const auto map = [&](float x, std::size_t c) {
        if (s[c] == 1.0 && (!translate || t[c] == 0.0)) return x;
        return static_cast<float>((translate ? t[c] : 0.0) + s[c] * x);
    };
    for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
        out.push_back(map(v[i], 0));
        out.push_back(-map(v[i + 2], 2));
        out.push_back(map(v[i + 1], 1));
    }
}

// One frame's arrays from a primitive's attributes (+ `delta` of a morph target).
struct Frame {
    std::vector<float> position, normal, reflect, refract, foam, color;
};

// Quantised normals (normalised integers, and a morph frame's int8 base plus its int16
// delta) decode a few thousandths off unit length: each is scaled back to 1, as a
// renderer would, so that an output written from them holds unit normals (the glTF
// validator refuses others).
void unit_normals(std::vector<float>& n) noexcept {
    for (std::size_t i = 0; i + 2 < n.size(); i += 3) {
        const double len = std::sqrt(double{n[i]} * n[i] + double{n[i + 1]} * n[i + 1] + double{n[i + 2]} * n[i + 2]);
        if (len > 0.0)
            for (std::size_t c = 0; c < 3; ++c) n[i + c] = static_cast<float>(n[i + c] / len);
    }
}

bool quantised(const Reader& r, int accessor) noexcept {
    return accessor >= 0 && static_cast<std::size_t>(accessor) < r.m.accessors.size() &&
           r.m.accessors[static_cast<std::size_t>(accessor)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT;
}

Frame read_frame(const Reader& r, const std::map<std::string, int>& attrs, int mesh, bool delta, ScalarLayout& layout) {
    Frame f;
    const auto [t, s] = r.transform(mesh);
    const auto has = [&](const char* n) { return attrs.count(n) != 0; };
    const auto at = [&](const char* n) {  // a required attribute
        const auto it = attrs.find(n);
        if (it == attrs.end()) r.fail(std::string("a frame without ") + n);
        return it->second;
    };
    if (!has("POSITION") || !has("NORMAL")) r.fail("a frame without POSITION or NORMAL");
    append_z_up(f.position, r.floats(at("POSITION"), 3), t, s, !delta);
    if (r.normals) {
        append_z_up(f.normal, r.floats(at("NORMAL"), 3), {0, 0, 0}, {1, 1, 1}, false);
        if (!delta && quantised(r, at("NORMAL"))) unit_normals(f.normal);
    }
    if (has("COLOR_0")) f.color = r.floats(at("COLOR_0"), 3);
    if (has("_REFLECT")) {
        if (!has("_REFRACT") || !has("_FOAM")) r.fail("_REFLECT without _REFRACT and _FOAM");
        layout = ScalarLayout::custom;
        f.reflect = r.floats(at("_REFLECT"), 1);
        f.refract = r.floats(at("_REFRACT"), 1);
        f.foam = r.floats(at("_FOAM"), 1);
    } else if (has("TEXCOORD_1") && has("TEXCOORD_2")) {
        layout = ScalarLayout::blender34;  // TEXCOORD_1 = (R, T), TEXCOORD_2 = (foam, 0)
        const auto uv1 = r.floats(at("TEXCOORD_1"), 2), uv2 = r.floats(at("TEXCOORD_2"), 2);
        if (uv1.size() != uv2.size()) r.fail("TEXCOORD_1 and TEXCOORD_2 hold different vertex counts");
        for (std::size_t v = 0; 2 * v < uv1.size(); ++v) {
            f.reflect.push_back(uv1[2 * v]);
            f.refract.push_back(uv1[2 * v + 1]);
            f.foam.push_back(uv2[2 * v]);
        }
    }
    return f;
}

// A frame's mesh of several primitives (a Draco frame and its far-field skirt,
// docs/far-field.md): their vertices in turn, a later primitive's vertex at the
// bit-equal position of a first primitive's vertex (the seam) welded onto it.
constexpr std::uint32_t kUnjoined = std::numeric_limits<std::uint32_t>::max();

struct Joined {
    std::vector<std::uint32_t> triangles;
    std::vector<float> texcoords;
    Frame frame;
};

Joined join_primitives(const Reader& r, const tinygltf::Mesh& mesh, int mesh_index, ScalarLayout& layout) {
    struct Part {
        std::vector<float> uv;
        Frame frame;
        std::vector<std::uint32_t> indices, index;  // the primitive's triangles; its vertices' in the joined mesh
    };
    std::vector<Part> parts(mesh.primitives.size());
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const tinygltf::Primitive& p = mesh.primitives[k];
        if (!p.attributes.count("TEXCOORD_0")) r.fail("the mesh has no TEXCOORD_0 (libwave writes the rest position there)");
        Part& part = parts[k];
        part.uv = r.floats(p.attributes.at("TEXCOORD_0"), 2);
        part.frame = read_frame(r, p.attributes, mesh_index, false, layout);
        part.indices = r.indices(p.indices);
        const std::size_t n = part.uv.size() / 2;
        const Frame& f = part.frame, &f0 = parts[0].frame;  // every primitive holds the first's optional attributes
        if (f.position.size() != 3 * n || f.normal.size() != (r.normals ? 3 * n : 0) || f.foam.size() != (f0.foam.empty() ? 0 : n) ||
            f.reflect.size() != f.foam.size() || f.refract.size() != f.foam.size() || f.color.size() != (f0.color.empty() ? 0 : 3 * n))
            r.fail("the primitives of a frame's mesh hold different attributes or vertex counts");
        for (const std::uint32_t i : part.indices)
            if (i >= n) r.fail("a primitive's index " + std::to_string(i) + " is past its " + std::to_string(n) + " vertices");
        part.index.assign(n, kUnjoined);
    }
    // The later primitives' positions (their bits, −0 as +0), the first vertex at each.
    using Key = std::array<std::uint32_t, 3>;
    const auto key = [](const float* p) {
        Key b{};
        for (std::size_t c = 0; c < 3; ++c) {
            const float x = p[c] == 0.0f ? 0.0f : p[c];
            std::memcpy(&b[c], &x, 4);
        }
        return b;
    };
    const auto hash = [](const Key& b) {
        return static_cast<std::size_t>((std::uint64_t{b[0]} * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t{b[1]} * 0xC2B2AE3D27D4EB4Full) ^ b[2]);
    };
    std::unordered_map<Key, std::pair<std::size_t, std::uint32_t>, decltype(hash)> later(0, hash);
    for (std::size_t k = 1; k < parts.size(); ++k)
        for (std::uint32_t v = 0; v < parts[k].index.size(); ++v) later.emplace(key(&parts[k].frame.position[3 * v]), std::pair{k, v});
    Joined j;
    std::size_t total = 0;
    for (const Part& part : parts) total += part.index.size();
    const bool shaded = !parts[0].frame.foam.empty(), coloured = !parts[0].frame.color.empty();
    j.texcoords.reserve(2 * total), j.frame.position.reserve(3 * total), j.frame.normal.reserve(3 * total);
    j.frame.reflect.reserve(shaded ? total : 0), j.frame.refract.reserve(shaded ? total : 0), j.frame.foam.reserve(shaded ? total : 0);
    j.frame.color.reserve(coloured ? 3 * total : 0);
    std::uint32_t count = 0;
    const auto take = [&](const Part& part, std::size_t v) {
        const auto copy = [v](std::vector<float>& to, const std::vector<float>& from, std::size_t width) {
            if (!from.empty())
                to.insert(to.end(), from.begin() + static_cast<std::ptrdiff_t>(width * v), from.begin() + static_cast<std::ptrdiff_t>(width * (v + 1)));
        };
        const Frame& f = part.frame;
        copy(j.texcoords, part.uv, 2), copy(j.frame.position, f.position, 3), copy(j.frame.normal, f.normal, 3);
        copy(j.frame.reflect, f.reflect, 1), copy(j.frame.refract, f.refract, 1), copy(j.frame.foam, f.foam, 1);
        copy(j.frame.color, f.color, 3);
        return count++;
    };
    // The first primitive's vertices in order, each later vertex at one's position
    // welded onto it; then the later primitives' other vertices.
    for (std::size_t v = 0; v < parts[0].index.size(); ++v) {
        parts[0].index[v] = take(parts[0], v);
        if (const auto seam = later.find(key(&parts[0].frame.position[3 * v])); seam != later.end()) {
            std::uint32_t& welded = parts[seam->second.first].index[seam->second.second];
            if (welded == kUnjoined) welded = parts[0].index[v];
        }
    }
    for (std::size_t k = 1; k < parts.size(); ++k)
        for (std::size_t v = 0; v < parts[k].index.size(); ++v)
            if (parts[k].index[v] == kUnjoined) parts[k].index[v] = take(parts[k], v);
    for (const Part& part : parts)
        for (const std::uint32_t i : part.indices) j.triangles.push_back(part.index[i]);
    return j;
}

// A morph frame: base + delta (no delta: the base). A delta of another length than the
// base is refused (found by tests/fuzz/fuzz_gltf: it was read past its end).
void add(const Reader& r, std::size_t target, const char* what, std::vector<float>& into, const std::vector<float>& base,
         const std::vector<float>& delta) {
    if (!delta.empty() && delta.size() != base.size())
        r.fail("morph target " + std::to_string(target) + ": its " + what + " has " + std::to_string(delta.size()) +
               " values, the base mesh " + std::to_string(base.size()));
    for (std::size_t i = 0; i < base.size(); ++i) into.push_back(base[i] + (delta.empty() ? 0.0f : delta[i]));
}

void append(StoredAnimation& a, const Frame& f) {
    a.positions.insert(a.positions.end(), f.position.begin(), f.position.end());
    a.normals.insert(a.normals.end(), f.normal.begin(), f.normal.end());
    a.reflect.insert(a.reflect.end(), f.reflect.begin(), f.reflect.end());
    a.refract.insert(a.refract.end(), f.refract.begin(), f.refract.end());
    a.foam.insert(a.foam.end(), f.foam.begin(), f.foam.end());
    a.colors.insert(a.colors.end(), f.color.begin(), f.color.end());
}

// The morph form: frame k = base + Σ_t w_kt · target t, w from the STEP weights track.
// libwave writes target k for frame k (weight 1) and, in quantised files, NORMAL-only
// targets after the frames' holding a normal's excess beyond ±1 (weight 1 in their
// frame's row); other weights are refused.
// The frames of a file to read: [first, first + count) of its own (0-based).
struct FrameWindow {
    std::size_t first = 0, count = std::numeric_limits<std::size_t>::max();
    bool has(std::size_t k) const noexcept { return k >= first && k - first < count; }
};

void read_morph_frames(const Reader& r, const tinygltf::Model& m, const tinygltf::Primitive& first, StoredAnimation& a,
                       const std::function<void()>& frame_read, const FrameWindow& window) {
    const tinygltf::Animation& anim = m.animations[0];
    const int s = anim.channels[0].sampler;
    if (s < 0 || static_cast<std::size_t>(s) >= anim.samplers.size()) r.fail("the weights channel has no sampler");
    const tinygltf::AnimationSampler& sampler = anim.samplers[static_cast<std::size_t>(s)];
    const std::size_t targets = first.targets.size(), frames = r.floats(sampler.input, 1).size();
    const std::vector<float> w = r.floats(sampler.output, 1);
    if (frames > targets || w.size() != frames * targets)
        r.fail("the weights track has " + std::to_string(w.size()) + " values for " + std::to_string(frames) + " keys and " +
               std::to_string(targets) + " morph targets");
    std::vector<std::vector<float>> excess(targets - frames);
    for (std::size_t t = frames; t < targets; ++t) {
        if (first.targets[t].size() != 1 || !first.targets[t].count("NORMAL"))
            r.fail("morph target " + std::to_string(t) + " (beyond the " + std::to_string(frames) + " frames) is not NORMAL-only");
        if (r.normals) append_z_up(excess[t - frames], r.floats(first.targets[t].at("NORMAL"), 3), {0, 0, 0}, {1, 1, 1}, false);
    }
    const Frame base = read_frame(r, first.attributes, 0, false, a.layout);
    for (std::size_t k = 0; k < frames; ++k) {
        std::size_t excess_weighed = 0;
        for (std::size_t t = 0; t < targets; ++t) {
            const float wk = w[k * targets + t];
            if (wk != (t == k ? 1.0f : 0.0f) && (t < frames || wk != 1.0f || ++excess_weighed > 1))
                r.fail("frame " + std::to_string(k) + " weighs morph target " + std::to_string(t) + " by " + std::to_string(wk) +
                       " (libwave's frames weigh their own target and at most one normals' excess by 1, others by 0)");
        }
        if (!window.has(k)) {  // a frame before the window moves the pieces' first frame on
            if (k < window.first) ++a.first_frame;
            continue;
        }
        const Frame d = read_frame(r, first.targets[k], 0, true, a.layout);
        Frame f;
        add(r, k, "POSITION", f.position, base.position, d.position);
        add(r, k, "NORMAL", f.normal, base.normal, d.normal);
        for (std::size_t t = frames; t < targets && r.normals; ++t) {
            if (w[k * targets + t] == 0.0f) continue;
            const std::vector<float> with = f.normal;
            f.normal.clear();
            add(r, t, "NORMAL", f.normal, with, excess[t - frames]);
        }
        if (quantised(r, first.attributes.count("NORMAL") ? first.attributes.at("NORMAL") : -1)) unit_normals(f.normal);
        add(r, k, "reflect weight", f.reflect, base.reflect, d.reflect);
        add(r, k, "refract weight", f.refract, base.refract, d.refract);
        add(r, k, "foam", f.foam, base.foam, d.foam);
        add(r, k, "COLOR_0", f.color, base.color, d.color);
        append(a, f);
        ++a.frame_count;
        frame_read();
    }
}

// A glTF file's JSON and, for a .glb, where its BIN chunk's data lies: read without
// that data, the header and chunk lengths checked against the file.
struct Container {
    std::string json;
    std::size_t bin_at = 0, bin_length = 0;  // a .glb's BIN chunk data: file offset, length
};

Container read_container(const std::string& path, std::ifstream& in, std::uintmax_t size, bool binary) {
    const auto fail = [&](const std::string& what) { throw InputError(path + ": not a readable glTF 2.0 file: " + what); };
    Container c;
    if (!binary) {
        c.json.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        if (in.bad()) throw InputError(path + ": cannot read the file");
        return c;
    }
    const auto u32 = [](const char* at) {
        std::uint32_t v = 0;
        std::memcpy(&v, at, 4);
        return std::size_t{v};
    };
    char head[20];
    if (size < 20 || !in.read(head, 20) || std::memcmp(head, "glTF", 4) != 0 || u32(head + 8) != size)
        fail("the GLB header does not match the file");
    const std::size_t json_length = u32(head + 12);
    if (json_length > size - 20 || std::memcmp(head + 16, "JSON", 4) != 0) fail("the JSON chunk runs past the file");
    c.json.resize(json_length);
    if (!in.read(c.json.data(), static_cast<std::streamsize>(json_length))) throw InputError(path + ": cannot read the file");
    const std::size_t bin_at = 20 + json_length;
    char chunk[8];
    if (bin_at + 8 <= size) {
        if (!in.read(chunk, 8)) throw InputError(path + ": cannot read the file");
        c.bin_length = u32(chunk);
        if (c.bin_length > size - bin_at - 8) fail("the BIN chunk runs past the file");
        c.bin_at = bin_at + 8;
    }
    return c;
}

// `length` bytes of a file from `at` (a Draco view, a static view of a lazy read).
std::string file_bytes(std::ifstream& in, const std::string& path, std::size_t at, std::size_t length) {
    std::string out(length, '\0');
    read_at(in, path, at, out.data(), length);
    return out;
}

// The bytes an embedded buffer's data: URI holds, as tinygltf decodes it (base64 of
// application/octet-stream or application/gltf-buffer); nothing for any other data: URI.
std::optional<std::size_t> data_uri_bytes(const std::string& uri) {
    std::string_view payload;
    for (const std::string_view header : {"data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,"})
        if (uri.rfind(header, 0) == 0) payload = std::string_view(uri).substr(header.size());
    if (payload.empty() || payload.size() % 4 != 0) return std::nullopt;
    std::size_t pad = 0;
    while (pad < 2 && payload[payload.size() - 1 - pad] == '=') ++pad;
    for (std::size_t i = 0; i < payload.size() - pad; ++i) {
        const char c = payload[i];
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '/') return std::nullopt;
    }
    return payload.size() / 4 * 3 - pad;
}

// A .gltf's external buffer, as tinygltf finds it (its URI percent-decoded beside the
// .gltf): inside the .gltf's folder and a regular file, or InputError.
std::string buffer_file(const std::string& path, const std::string& uri, const std::string& what) {
    std::string decoded;
    const auto hex = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : (std::tolower(static_cast<unsigned char>(c)) - 'a' + 10) & 15; };
    for (std::size_t i = 0; i < uri.size(); ++i) {  // tinygltf's dlib::urldecode
        if (uri[i] == '+') decoded += ' ';
        else if (uri[i] == '%' && uri.size() > i + 2) decoded += static_cast<char>((hex(uri[i + 1]) << 4) | hex(uri[i + 2])), i += 2;
        else decoded += uri[i];
    }
    const std::string file = path_inside(std::filesystem::path(path).parent_path().string(), decoded, path + ": " + what + "'s uri");
    require_input_file(file);
    return file;
}

// tinygltf (Debian's) trusts the file's byte ranges when it decodes Draco
// primitives: a bufferView beyond its buffer overflows the heap (found by
// tests/fuzz/fuzz_gltf). The container and every range are checked here first, on the
// JSON then handed to tinygltf; a .glb's Draco bitstreams are read from `in`.
void check_layout(const std::string& path, const nlohmann::json& doc, const Container& c, bool binary, std::ifstream& in) {
    const auto fail = [&](const std::string& what) { throw InputError(path + ": not a readable glTF 2.0 file: " + what); };
    const std::size_t bin_length = c.bin_length;
    const auto count = [](const nlohmann::json& o, const char* key) -> double {
        const auto it = o.find(key);
        return it == o.end() ? 0.0 : it->is_number() ? it->get<double>() : -1.0;
    };
    std::vector<double> buffer_bytes;
    if (doc.contains("buffers") && doc["buffers"].is_array())
        for (const auto& b : doc["buffers"]) {
            if (!b.is_object()) fail("a buffer is not an object");
            const std::string what = "buffer " + std::to_string(buffer_bytes.size());
            const double length = count(b, "byteLength");
            double available = static_cast<double>(bin_length);  // the GLB's own buffer
            if (b.contains("uri")) {
                if (!b["uri"].is_string()) fail(what + ": its uri is not a string");
                const std::string uri = b["uri"].get<std::string>();
                if (uri.rfind("data:", 0) == 0) {
                    const auto bytes = data_uri_bytes(uri);
                    if (!bytes)
                        throw InputError(path + ": " + what + ": an embedded data: URI other than base64 of application/octet-stream or "
                                         "application/gltf-buffer is not supported");
                    if (static_cast<double>(*bytes) != length)
                        throw InputError(path + ": " + what + ": its data: URI holds " + std::to_string(*bytes) + " bytes, its byteLength says " +
                                         detail::format_number(length));
                    available = static_cast<double>(*bytes);
                } else {
                    const std::string file = buffer_file(path, uri, what);
                    available = static_cast<double>(detail::input_file_bytes(file));
                }
            }
            if (!(length >= 0.0 && length <= available)) fail(what + ": its byteLength is not in its data");
            buffer_bytes.push_back(length);
        }
    if (doc.contains("bufferViews") && doc["bufferViews"].is_array())
        for (const auto& v : doc["bufferViews"]) {
            if (!v.is_object()) fail("a bufferView is not an object");
            const double buffer = count(v, "buffer"), offset = count(v, "byteOffset"), length = count(v, "byteLength");
            if (!(buffer >= 0.0 && buffer < static_cast<double>(buffer_bytes.size()) && offset >= 0.0 && length >= 0.0 &&
                  offset + length <= buffer_bytes[static_cast<std::size_t>(buffer)]))
                fail("a bufferView lies outside its buffer");
            // tinygltf takes a negative stride for none (packed elements): refused, as the
            // glTF specification does (4 … 252, a multiple of 4).
            if (v.contains("byteStride")) {
                const nlohmann::json& stride = v["byteStride"];
                if (!stride.is_number_integer() || stride.get<double>() < 4.0 || stride.get<double>() > 252.0 || stride.get<std::int64_t>() % 4 != 0)
                    fail("bufferView " + std::to_string(&v - &doc["bufferViews"][0]) + ": byteStride " + stride.dump().substr(0, 24) +
                         " is not a multiple of 4 in [4, 252]");
            }
        }
    // Indices into the arrays tinygltf indexes without checking (its Draco decoding).
    const auto size_of = [&](const char* key) {
        return doc.contains(key) && doc[key].is_array() ? static_cast<double>(doc[key].size()) : 0.0;
    };
    const double accessors = size_of("accessors"), views = size_of("bufferViews");
    const auto index_in = [&](const nlohmann::json& v, double n, const char* what) {
        if (!v.is_number_integer() || v.get<double>() < 0.0 || v.get<double>() >= n) fail(std::string("a ") + what + " index is out of range");
    };
    if (doc.contains("accessors") && doc["accessors"].is_array())
        for (const auto& a : doc["accessors"])
            if (a.is_object() && a.contains("bufferView")) index_in(a["bufferView"], views, "bufferView");
    if (doc.contains("meshes") && doc["meshes"].is_array())
        for (const auto& mesh : doc["meshes"]) {
            if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
            for (const auto& prim : mesh["primitives"]) {
                if (!prim.is_object()) fail("a primitive is not an object");
                if (prim.contains("indices")) index_in(prim["indices"], accessors, "indices accessor");
                if (prim.contains("attributes") && prim["attributes"].is_object())
                    for (const auto& [_, a] : prim["attributes"].items()) index_in(a, accessors, "attribute accessor");
                if (prim.contains("targets") && prim["targets"].is_array())
                    for (const auto& t : prim["targets"])
                        if (t.is_object())
                            for (const auto& [_, a] : t.items()) index_in(a, accessors, "morph target accessor");
                const auto ext = prim.find("extensions");
                if (ext != prim.end() && ext->is_object() && ext->contains("KHR_draco_mesh_compression")) {
                    const auto& d = (*ext)["KHR_draco_mesh_compression"];
                    if (!d.is_object() || !d.contains("bufferView")) fail("a Draco primitive without a bufferView");
                    index_in(d["bufferView"], views, "Draco bufferView");
                    if (!prim.contains("indices")) fail("a Draco primitive without indices");
                    if (!d.contains("attributes") || !d["attributes"].is_object()) fail("a Draco primitive without attributes");
                    // tinygltf sizes its decoded buffers by the accessors' component types.
                    const auto component = [&](const nlohmann::json& accessor, std::initializer_list<int> valid) {
                        const auto& a = doc["accessors"][accessor.get<std::size_t>()];
                        const int type = a.is_object() && a.contains("componentType") && a["componentType"].is_number_integer()
                                             ? a["componentType"].get<int>() : 0;
                        if (std::find(valid.begin(), valid.end(), type) == valid.end()) fail("a Draco accessor has an invalid componentType");
                    };
                    component(prim["indices"], {5121, 5123, 5125});
                    if (prim.contains("attributes") && prim["attributes"].is_object())
                        for (const auto& [_, a] : prim["attributes"].items()) component(a, {5120, 5121, 5122, 5123, 5125, 5126});
                    // tinygltf dereferences the Draco attribute of every id without a check:
                    // decode the bitstream here and require each id (and a GLB's own buffer).
                    const auto& view = doc["bufferViews"][d["bufferView"].get<std::size_t>()];
                    if (!binary || count(view, "buffer") != 0.0 || doc["buffers"][0].contains("uri")) continue;
                    const std::string bitstream = file_bytes(in, path, c.bin_at + static_cast<std::size_t>(count(view, "byteOffset")),
                                                             static_cast<std::size_t>(count(view, "byteLength")));
                    draco::DecoderBuffer buffer;
                    buffer.Init(bitstream.data(), bitstream.size());
                    draco::Decoder decoder;
                    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
                    if (!decoded.ok()) fail(std::string("a Draco primitive does not decode: ") + decoded.status().error_msg());
                    for (const auto& [name, id] : d["attributes"].items())
                        if (!id.is_number_integer() || !decoded.value()->GetAttributeByUniqueId(id.get<std::uint32_t>()))
                            fail("the Draco attribute of " + name + " is not in the bitstream");
                }
            }
        }
}

// What a morph or nodes file carries beside the water (SceneDressing), kept so that
// `wave convert` writes it again byte for byte.
void read_dressing(const Reader& r, const tinygltf::Model& m, StoredAnimation& a) {
    SceneDressing d;
    d.water_material = std::any_of(m.materials.begin(), m.materials.end(), [](const auto& mat) { return mat.name == "water"; });
    bool any = d.water_material;
    for (const tinygltf::Node& n : m.nodes) {
        if (n.name == "seafloor" && n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < m.meshes.size() &&
            !m.meshes[static_cast<std::size_t>(n.mesh)].primitives.empty()) {
            const tinygltf::Primitive& p = m.meshes[static_cast<std::size_t>(n.mesh)].primitives[0];
            if (!p.attributes.count("POSITION")) r.fail("the seafloor mesh has no POSITION");
            const std::vector<float> xyz = r.floats(p.attributes.at("POSITION"), 3);
            a.seafloor_positions.resize(xyz.size());
            for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) {  // glTF y up → z up
                a.seafloor_positions[i] = xyz[i];
                a.seafloor_positions[i + 1] = -xyz[i + 2];
                a.seafloor_positions[i + 2] = xyz[i + 1];
            }
            if (p.attributes.count("COLOR_0")) a.seafloor_colors = r.floats(p.attributes.at("COLOR_0"), 3);
            a.seafloor_triangles = r.indices(p.indices);
            any = true;
        } else if (n.camera >= 0 && static_cast<std::size_t>(n.camera) < m.cameras.size() && n.translation.size() == 3 &&
                   n.rotation.size() == 4) {
            const tinygltf::PerspectiveCamera& c = m.cameras[static_cast<std::size_t>(n.camera)].perspective;
            d.camera = any = true;
            d.camera_position = {n.translation[0], -n.translation[2], n.translation[1]};
            std::copy(n.rotation.begin(), n.rotation.end(), d.camera_rotation.begin());
            d.camera_yfov = c.yfov;
            d.camera_aspect = c.aspectRatio;
        } else if (n.extensions.count("KHR_lights_punctual") && n.rotation.size() == 4) {
            d.sun = any = true;
            std::copy(n.rotation.begin(), n.rotation.end(), d.sun_rotation.begin());
        }
    }
    if (any) a.dressing = d;
}

// The frames a piece holds: about 16 MB of decoded arrays (at least one frame; a
// streamed conversion holds a piece twice, decoded and in its writer).
std::size_t frames_per_piece(std::size_t vertex_count) {
    constexpr double piece_bytes = 16e6, per_vertex = 4.0 * (3 + 3 + 3 + 3);  // positions, normals, shading, colour
    return std::max<std::size_t>(1, static_cast<std::size_t>(piece_bytes / (per_vertex * static_cast<double>(std::max<std::size_t>(1, vertex_count)))));
}

// Every vertex of every frame of a piece is covered by each attribute (or it is absent):
// the writers index them by vertex.
void check_piece(const Reader& r, const StoredAnimation& a) {
    if (a.positions.size() != 3 * a.vertex_count * a.frame_count) r.fail("frames of different sizes");
    const std::size_t values = a.vertex_count * a.frame_count;
    if (a.normals.size() != (r.normals ? 3 * values : 0)) r.fail("NORMAL does not cover every vertex of every frame");
    for (const auto* scalar : {&a.reflect, &a.refract, &a.foam})
        if (!scalar->empty() && scalar->size() != values) r.fail("a shading attribute does not cover every vertex of every frame");
    if (!a.colors.empty() && a.colors.size() != 3 * values) r.fail("COLOR_0 does not cover every vertex of every frame");
}

// A .glb/.gltf of libwave's, a piece of frames at a time (frames_per_piece; a file of a
// morph or nodes form): the file's bytes go once tinygltf holds its buffer, and the
// decoded frames are handed on a piece at a time, so memory holds the file's buffer
// and one piece, not the decoded animation beside it.
// The buffer views only a file's frames use: those of morph target accessors and of the
// nodes form's later meshes (every mesh after the first but the seafloor), unless an
// accessor of the static parts (the first mesh, the seafloor, the animation), an image
// or a Draco bitstream uses them too.
std::set<int> frame_views(const nlohmann::json& doc, bool every_view = false) {
    std::set<int> frame_accessors, static_accessors, pinned;
    const auto accessor_of = [](const nlohmann::json& v, std::set<int>& into) {
        if (v.is_number_integer()) into.insert(v.get<int>());
    };
    const auto array = [&](const char* key) { return doc.contains(key) && doc[key].is_array() ? doc[key] : nlohmann::json::array(); };
    const nlohmann::json meshes = array("meshes");
    // The nodes form (several water meshes): the first frame's own attributes are a
    // frame's too, so a reader of another frame (read_animation_frames) leaves them in
    // the file; its indices and TEXCOORD_0, which every frame shares, stay resident.
    const auto water_mesh = [](const nlohmann::json& m) { return m.is_object() && !(m.contains("name") && m["name"] == "seafloor"); };
    const bool frames_of_their_own = std::count_if(meshes.begin(), meshes.end(), water_mesh) > 1;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const nlohmann::json& mesh = meshes[i];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        const bool frame_mesh = i > 0 && water_mesh(mesh);
        for (const auto& prim : mesh["primitives"]) {
            if (!prim.is_object()) continue;
            std::set<int>& own = frame_mesh ? frame_accessors : static_accessors;
            if (prim.contains("indices")) accessor_of(prim["indices"], own);
            if (prim.contains("attributes") && prim["attributes"].is_object())
                for (const auto& [name, a] : prim["attributes"].items())
                    accessor_of(a, i == 0 && frames_of_their_own && name != "TEXCOORD_0" ? frame_accessors : own);
            if (prim.contains("targets") && prim["targets"].is_array())
                for (const auto& t : prim["targets"])
                    if (t.is_object())
                        for (const auto& [_, a] : t.items()) accessor_of(a, frame_accessors);
            const auto ext = prim.find("extensions");
            if (ext != prim.end() && ext->is_object() && ext->contains("KHR_draco_mesh_compression") &&
                (*ext)["KHR_draco_mesh_compression"].is_object())
                accessor_of((*ext)["KHR_draco_mesh_compression"].value("bufferView", nlohmann::json()), pinned);
        }
    }
    for (const auto& anim : array("animations"))
        if (anim.is_object() && anim.contains("samplers") && anim["samplers"].is_array())
            for (const auto& sampler : anim["samplers"])
                if (sampler.is_object()) {
                    accessor_of(sampler.value("input", nlohmann::json()), static_accessors);
                    accessor_of(sampler.value("output", nlohmann::json()), static_accessors);
                }
    for (const auto& image : array("images"))
        if (image.is_object()) accessor_of(image.value("bufferView", nlohmann::json()), pinned);
    const nlohmann::json accessors = array("accessors");
    const auto views_of = [&](int a, std::set<int>& into) {
        if (a < 0 || static_cast<std::size_t>(a) >= accessors.size() || !accessors[static_cast<std::size_t>(a)].is_object()) return;
        const nlohmann::json& acc = accessors[static_cast<std::size_t>(a)];
        accessor_of(acc.value("bufferView", nlohmann::json()), into);
        if (acc.contains("sparse") && acc["sparse"].is_object())
            for (const char* part : {"indices", "values"})
                if (acc["sparse"].contains(part) && acc["sparse"][part].is_object())
                    accessor_of(acc["sparse"][part].value("bufferView", nlohmann::json()), into);
    };
    std::set<int> lazy;
    for (const int a : frame_accessors) views_of(a, lazy);
    for (const int a : static_accessors) views_of(a, every_view ? lazy : pinned);
    for (const int v : pinned) lazy.erase(v);
    return lazy;
}

// The views of every primitive's indices and TEXCOORD_0 (the rest positions): what the
// frame files of one run share.
std::set<int> shared_views(const nlohmann::json& doc) {
    std::set<int> out;
    if (!doc.contains("meshes") || !doc["meshes"].is_array() || !doc.contains("accessors") || !doc["accessors"].is_array()) return out;
    const nlohmann::json& accessors = doc["accessors"];
    const auto view_of = [&](const nlohmann::json& a) {
        if (!a.is_number_integer() || a.get<double>() < 0.0 || a.get<double>() >= static_cast<double>(accessors.size())) return;
        const nlohmann::json& acc = accessors[a.get<std::size_t>()];
        if (acc.is_object() && acc.contains("bufferView") && acc["bufferView"].is_number_integer()) out.insert(acc["bufferView"].get<int>());
    };
    for (const auto& mesh : doc["meshes"])
        if (mesh.is_object() && mesh.contains("primitives") && mesh["primitives"].is_array())
            for (const auto& prim : mesh["primitives"]) {
                if (!prim.is_object()) continue;
                if (prim.contains("indices")) view_of(prim["indices"]);
                if (prim.contains("attributes") && prim["attributes"].is_object() && prim["attributes"].contains("TEXCOORD_0"))
                    view_of(prim["attributes"]["TEXCOORD_0"]);
            }
    return out;
}

// EXT_meshopt_compression: each compressed view is pointed at its compressed bytes
// (the extension's buffer, offset and length) and its decoding recorded, the fallback
// buffers (no data) are dropped, so that the layout checks and the lazy reading see
// plain views of one buffer; the bytes are decoded as they are read. Every field is
// checked first: a view's decoded size must be count × byteStride and within what the
// codecs can expand its compressed bytes to (no allocation a stream cannot fill).
std::map<int, MeshoptView> unpack_meshopt(const std::string& path, nlohmann::json& doc) {
    std::map<int, MeshoptView> out;
    const auto listed = [&](const char* key) {
        if (!doc.contains(key) || !doc[key].is_array()) return false;
        for (const auto& e : doc[key])
            if (e == "EXT_meshopt_compression") return true;
        return false;
    };
    if (!listed("extensionsUsed")) return out;
    const auto fail = [&](const std::string& what) { throw InputError(path + ": EXT_meshopt_compression: " + what); };
    if (!doc.contains("buffers") || !doc["buffers"].is_array()) fail("no buffers");
    nlohmann::json& buffers = doc["buffers"];
    std::vector<char> fallback(buffers.size(), 0);
    for (std::size_t b = 0; b < buffers.size(); ++b) {
        const nlohmann::json& buffer = buffers[b];
        if (buffer.is_object() && buffer.contains("extensions") && buffer["extensions"].is_object() &&
            buffer["extensions"].contains("EXT_meshopt_compression")) {
            const nlohmann::json& e = buffer["extensions"]["EXT_meshopt_compression"];
            fallback[b] = e.is_object() && e.value("fallback", false) == true;
        }
    }
    std::size_t data_buffers = 0;  // the fallback buffers must come after every buffer with data
    while (data_buffers < fallback.size() && !fallback[data_buffers]) ++data_buffers;
    for (std::size_t b = data_buffers; b < fallback.size(); ++b)
        if (!fallback[b]) fail("buffer " + std::to_string(b) + " has data but follows a fallback buffer");
    if (!doc.contains("bufferViews") || !doc["bufferViews"].is_array()) return out;
    nlohmann::json& views = doc["bufferViews"];
    const auto whole = [&](const nlohmann::json& o, const char* key, std::size_t dflt, double most, const std::string& what) {
        if (!o.contains(key)) return dflt;
        const nlohmann::json& x = o[key];
        if (!x.is_number_integer() || x.get<double>() < 0.0 || x.get<double>() > most)
            fail(what + ": " + key + " is not a whole number in [0, " + detail::format_number(most) + "]");
        return x.get<std::size_t>();
    };
    for (std::size_t v = 0; v < views.size(); ++v) {
        nlohmann::json& view = views[v];
        const std::string what = "bufferView " + std::to_string(v);
        if (!view.is_object()) fail(what + " is not an object");
        const bool compressed = view.contains("extensions") && view["extensions"].is_object() &&
                                view["extensions"].contains("EXT_meshopt_compression");
        if (!compressed) {
            if (whole(view, "buffer", 0, 1e9, what) >= data_buffers) fail(what + " lies in a fallback buffer, which has no data");
            continue;
        }
        const nlohmann::json e = view["extensions"]["EXT_meshopt_compression"];
        if (!e.is_object()) fail(what + ": the extension is not an object");
        MeshoptView m;
        const std::size_t buffer = whole(e, "buffer", std::size_t(-1), 1e9, what);
        if (buffer >= data_buffers) fail(what + ": its compressed bytes are not in a buffer with data");
        const std::size_t offset = whole(e, "byteOffset", 0, 4294967295.0, what);
        const std::size_t length = whole(e, "byteLength", std::size_t(-1), 4294967295.0, what);
        m.stride = whole(e, "byteStride", std::size_t(-1), 256, what);
        m.count = whole(e, "count", std::size_t(-1), 4294967295.0, what);
        if (!e.contains("mode") || !e["mode"].is_string()) fail(what + ": no mode");
        const std::string mode = e["mode"].get<std::string>(), filter = e.value("filter", std::string("NONE"));
        if (mode == "ATTRIBUTES") m.mode = detail::MeshoptMode::attributes;
        else if (mode == "TRIANGLES") m.mode = detail::MeshoptMode::triangles;
        else if (mode == "INDICES") m.mode = detail::MeshoptMode::indices;
        else fail(what + ": unknown mode \"" + mode + "\"");
        if (filter == "NONE") m.filter = detail::MeshoptFilter::none;
        else if (filter == "OCTAHEDRAL") m.filter = detail::MeshoptFilter::octahedral;
        else if (filter == "QUATERNION") m.filter = detail::MeshoptFilter::quaternion;
        else if (filter == "EXPONENTIAL") m.filter = detail::MeshoptFilter::exponential;
        else fail(what + ": unknown filter \"" + filter + "\"");
        const std::size_t decoded = m.count * m.stride;
        if (whole(view, "byteLength", std::size_t(-1), 4294967295.0, what) != decoded)
            fail(what + ": byteLength " + std::to_string(view.value("byteLength", std::size_t{0})) + " is not count " + std::to_string(m.count) +
                 " × byteStride " + std::to_string(m.stride));
        // The vertex codec packs at most 64 bytes per byte (a stream of zeros), the index
        // codecs less: a larger declared size is not what the stream holds.
        if (decoded > 64 * length + 4096)
            fail(what + ": declares " + std::to_string(decoded) + " bytes for a stream of " + std::to_string(length));
        view["buffer"] = buffer;
        view["byteOffset"] = offset;
        view["byteLength"] = length;
        view["extensions"].erase("EXT_meshopt_compression");
        if (view["extensions"].empty()) view.erase("extensions");
        out[static_cast<int>(v)] = m;
    }
    buffers.erase(buffers.begin() + static_cast<std::ptrdiff_t>(data_buffers), buffers.end());
    for (const char* key : {"extensionsUsed", "extensionsRequired"})
        if (doc.contains(key) && doc[key].is_array()) {
            nlohmann::json kept = nlohmann::json::array();
            for (const auto& e : doc[key])
                if (e != "EXT_meshopt_compression") kept.push_back(e);
            doc[key] = kept;
        }
    return out;
}

// The most frames a loop of libwave's has (the schema's /animation/max_frames).
constexpr double kMaxStoredFrames = 1e7;

// asset.extras.libwave's numbers, checked in the file's JSON before tinygltf converts
// them: it casts an integer to int, so a loop of 2^40 frames became 0 in the output's
// extras, and a negative one wrapped round (docs/hardening.md).
void check_extras(const std::string& path, const nlohmann::json& doc) {
    const nlohmann::json* info = &doc;
    for (const char* key : {"asset", "extras", "libwave"}) {
        if (!info->is_object() || !info->contains(key)) return;  // read_glb_pieces says what is missing
        info = &(*info)[key];
    }
    const auto fail = [&](const std::string& what) { throw InputError(path + ": asset.extras.libwave." + what); };
    if (!info->is_object()) fail(" is not an object");
    const auto number = [&](const char* key, double most, bool whole) {
        const nlohmann::json v = info->value(key, nlohmann::json());
        if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= most) || (whole && !v.is_number_unsigned()))
            fail(std::string(key) + " is not " + (whole ? "a whole number" : "a number") + " in [0, " + detail::format_number(most) + "]");
        return v.get<double>();
    };
    if (!(number("fps", 1000.0, false) > 0.0)) fail("fps is 0");
    number("loop_frames", kMaxStoredFrames, true);
    number("first_frame", kMaxStoredFrames, true);
    if (!info->value("name", nlohmann::json()).is_string()) fail("name is not a string");
    if (info->contains("scene") && !(*info)["scene"].is_string()) fail("scene is not a string");
}

// Loads one of libwave's glTF files into `m`. When buffer 0 is a .glb's BIN chunk or a
// .gltf's external .bin (every layout libwave writes), tinygltf parses the JSON with a
// buffer of the static views alone, moved together, and the frames' views stay in the
// file for `lazy`; otherwise it loads the whole file, as it would.
// With `memo` (a FrameReader's files form), every view stays in the file until it is
// asked for, and the shared ones (shared_views) decode through the memo.
void load_model(const std::string& path, tinygltf::Model& m, LazyViews& lazy, ViewMemo* memo = nullptr) {
    const bool binary = std::filesystem::path(path).extension() == ".glb";
    detail::require_input_file(path);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (ec || !in) throw InputError(path + ": cannot read the file");
    const Container c = read_container(path, in, size, binary);
    nlohmann::json doc = detail::parse_json_input(c.json, path);  // nesting bounded before tinygltf parses it
    check_extras(path, doc);
    const std::map<int, MeshoptView> meshopt = unpack_meshopt(path, doc);
    check_layout(path, doc, c, binary, in);
    const std::string base_dir = std::filesystem::path(path).parent_path().string();  // a .gltf's .bin lies beside it
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool one_buffer = doc.contains("buffers") && doc["buffers"].is_array() && doc["buffers"].size() == 1 && doc["buffers"][0].is_object();
    const nlohmann::json uri = one_buffer ? doc["buffers"][0].value("uri", nlohmann::json()) : nlohmann::json();
    const bool in_bin_chunk = binary && one_buffer && uri.is_null() && c.bin_length > 0;
    const bool in_bin_file = !binary && one_buffer && uri.is_string() && uri.get<std::string>().rfind("data:", 0) != 0;
    const bool views_listed = !doc.contains("bufferViews") || doc["bufferViews"].is_array();
    if ((!in_bin_chunk && !in_bin_file) || !views_listed) {
        if (!meshopt.empty()) throw InputError(path + ": EXT_meshopt_compression with its data elsewhere than the GLB's chunk or one .bin");
        in.clear();
        in.seekg(0);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) throw InputError(path + ": cannot read the file");
        if (bytes.size() > std::numeric_limits<unsigned int>::max()) throw InputError(path + ": larger than glTF's 4 GB");
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        const auto length = static_cast<unsigned int>(bytes.size());
        const bool ok = binary ? loader.LoadBinaryFromMemory(&m, &err, &warn, data, length, base_dir)
                               : loader.LoadASCIIFromString(&m, &err, &warn, bytes.data(), length, base_dir);
        if (!ok) throw InputError(path + ": not a readable glTF 2.0 file: " + err);
        return;
    }
    lazy.file = in_bin_chunk ? path : buffer_file(path, uri.get<std::string>(), "buffer 0");
    lazy.base = in_bin_chunk ? c.bin_at : 0;
    lazy.in.open(lazy.file, std::ios::binary);
    if (!lazy.in) throw InputError(path + ": cannot read its buffer " + lazy.file);
    const std::set<int> deferred = frame_views(doc, memo != nullptr);
    if (memo) {
        lazy.memo = memo;
        lazy.kept = shared_views(doc);
    }
    std::string bin;  // the static views, each 4-byte aligned (accessors keep their alignment)
    nlohmann::json& views = doc["bufferViews"];
    for (std::size_t v = 0; v < views.size(); ++v) {
        nlohmann::json& view = views[v];
        const std::size_t offset = view.value("byteOffset", std::size_t{0}), length = view.value("byteLength", std::size_t{0});
        const auto compressed = meshopt.find(static_cast<int>(v));
        if (compressed != meshopt.end()) view["byteLength"] = compressed->second.count * compressed->second.stride;
        if (deferred.count(static_cast<int>(v))) {
            lazy.where[static_cast<int>(v)] = {offset, length};
            if (compressed != meshopt.end()) lazy.meshopt[static_cast<int>(v)] = compressed->second;
            view["byteOffset"] = 0;  // tinygltf does not read it; the reader asks `lazy`
            continue;
        }
        bin.resize((bin.size() + 3) & ~std::size_t{3}, '\0');
        view["byteOffset"] = bin.size();
        if (compressed == meshopt.end()) {
            bin += file_bytes(lazy.in, path, lazy.base + offset, length);
        } else {
            const std::string packed = file_bytes(lazy.in, path, lazy.base + offset, length);
            const std::vector<unsigned char> plain = decode_meshopt(
                path, static_cast<int>(v), compressed->second,
                std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(packed.data()), packed.size()));
            bin.append(reinterpret_cast<const char*>(plain.data()), plain.size());
        }
    }
    if (bin.empty()) bin.assign(4, '\0');  // every view left in the file (a FrameReader's): tinygltf wants a BIN chunk
    doc["buffers"][0] = nlohmann::json{{"byteLength", bin.size()}};
    std::string json = doc.dump();
    json.resize((json.size() + 3) & ~std::size_t{3}, ' ');
    bin.resize((bin.size() + 3) & ~std::size_t{3}, '\0');
    const auto u32 = [](std::size_t v) {
        const auto x = static_cast<std::uint32_t>(v);
        return std::string(reinterpret_cast<const char*>(&x), 4);
    };
    const std::string glb = "glTF" + u32(2) + u32(28 + json.size() + bin.size()) + u32(json.size()) + "JSON" + json +
                            u32(bin.size()) + std::string("BIN\0", 4) + bin;
    if (!loader.LoadBinaryFromMemory(&m, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                     static_cast<unsigned int>(glb.size()), base_dir))
        throw InputError(path + ": not a readable glTF 2.0 file: " + err);
}

// A loaded .glb/.gltf of libwave's: the model, its views still in the file, and its
// static parts (triangles, rest positions, dressing, the file's numbers) in `a`, whose
// frame arrays are empty. A FrameReader keeps one open across frames.
struct GlbFile {
    std::string path;
    tinygltf::Model m;
    LazyViews lazy;
    StoredAnimation a;
    std::vector<std::size_t> water;  // the water's meshes: all but the seafloor
    std::string path_kind;           // the first channel's ("weights": the morph form)
    std::optional<Joined> joined;    // the first water mesh's primitives joined (a frame with its skirt)
    std::size_t total = 0;           // the file's frames
    bool normals = true;             // read the frames' normals

    Reader reader() const {
        Reader r{m, path, lazy.where.empty() ? nullptr : &lazy};
        r.normals = normals;
        return r;
    }
};

// Loads `path` into `g` (its path set by the caller; `memo`: load_model's) and reads its
// static parts; `dressing` false leaves out the seafloor, camera and sun.
void open_glb(GlbFile& g, ViewMemo* memo = nullptr, bool dressing = true) {
    load_model(g.path, g.m, g.lazy, memo);
    const tinygltf::Model& m = g.m;
    const Reader r = g.reader();
    if (!m.asset.extras.Has("libwave")) r.fail("not written by libwave (no asset.extras.libwave): only libwave's outputs can be converted");
    const tinygltf::Value& info = m.asset.extras.Get("libwave");
    StoredAnimation& a = g.a;
    a.fps = info.Get("fps").GetNumberAsDouble();  // checked by check_extras
    a.first_frame = static_cast<std::size_t>(info.Get("first_frame").GetNumberAsInt());
    a.loop_frames = static_cast<std::size_t>(info.Get("loop_frames").GetNumberAsInt());
    a.name = info.Get("name").Get<std::string>();
    if (info.Has("scene")) a.scene = info.Get("scene").Get<std::string>();
    if (m.meshes.empty() || m.meshes[0].primitives.empty()) r.fail("no mesh");
    g.path_kind = m.animations.empty() || m.animations[0].channels.empty() ? "" : m.animations[0].channels[0].target_path;
    const tinygltf::Primitive& first = m.meshes[0].primitives[0];
    a.draco_frames = g.path_kind != "weights" && first.extensions.count("KHR_draco_mesh_compression") != 0;
    for (std::size_t i = 0; i < m.meshes.size(); ++i)
        if (m.meshes[i].name != "seafloor") g.water.push_back(i);
    // A Draco frame with its skirt as a second primitive (docs/far-field.md): one mesh again.
    if (g.path_kind != "weights" && !g.water.empty() && m.meshes[g.water[0]].primitives.size() > 1)
        g.joined = join_primitives(r, m.meshes[g.water[0]], static_cast<int>(g.water[0]), a.layout);
    if (g.joined) {
        a.triangles = g.joined->triangles;
        a.texcoords = g.joined->texcoords;
    } else {
        a.triangles = r.indices(first.indices);
        if (!first.attributes.count("TEXCOORD_0")) r.fail("the mesh has no TEXCOORD_0 (libwave writes the rest position there)");
        a.texcoords = r.floats(first.attributes.at("TEXCOORD_0"), 2);
    }
    a.vertex_count = a.texcoords.size() / 2;
    if (dressing) read_dressing(r, m, a);
    // The file's frames: its weights track's keys (read_morph_frames checks them), or its meshes.
    g.total = g.water.size();
    if (g.path_kind == "weights") {
        const int s = m.animations[0].channels[0].sampler;
        const int input = s >= 0 && static_cast<std::size_t>(s) < m.animations[0].samplers.size() ? m.animations[0].samplers[static_cast<std::size_t>(s)].input : -1;
        g.total = input >= 0 && static_cast<std::size_t>(input) < m.accessors.size() ? m.accessors[static_cast<std::size_t>(input)].count : 0;
    }
    r.release();  // the shared views read from the file (a files form's FrameReader)
}

// The frames of `window` of an opened file, a piece at a time. `keep` leaves `g` as it
// was (a FrameReader reads it again): the pieces then carry the frame arrays and the
// file's numbers, not its static arrays (triangles, rest positions, seafloor).
void read_glb_frames(GlbFile& g, const std::function<void(StoredAnimation&&, std::size_t)>& piece, const FrameWindow& window,
                     bool keep = false) {
    const tinygltf::Model& m = g.m;
    const Reader r = g.reader();
    StoredAnimation a;
    if (keep) {
        a.vertex_count = g.a.vertex_count, a.first_frame = g.a.first_frame, a.loop_frames = g.a.loop_frames, a.fps = g.a.fps;
        a.name = g.a.name, a.scene = g.a.scene, a.layout = g.a.layout, a.draco_frames = g.a.draco_frames;
    } else {
        a = std::move(g.a);
    }
    const std::vector<std::uint32_t>& triangles = keep ? g.a.triangles : a.triangles;
    const std::vector<std::size_t>& water = g.water;
    const std::size_t total = g.total;
    const tinygltf::Primitive& first = m.meshes[0].primitives[0];
    // A piece: the file's static parts and the frames read since the last one.
    const std::size_t per_piece = frames_per_piece(a.vertex_count);
    bool handed = false;
    const auto swap_frames = [](StoredAnimation& x, StoredAnimation& y) {
        for (auto member : {&StoredAnimation::positions, &StoredAnimation::normals, &StoredAnimation::reflect,
                            &StoredAnimation::refract, &StoredAnimation::foam, &StoredAnimation::colors})
            (x.*member).swap(y.*member);
    };
    const auto hand_on = [&] {
        check_piece(r, a);
        StoredAnimation frames;  // holds a's frame arrays while the static parts are copied
        swap_frames(a, frames);
        StoredAnimation out = a;
        swap_frames(out, frames);
        a.first_frame += a.frame_count;
        a.frame_count = 0;
        handed = true;
        piece(std::move(out), total);
    };
    const auto frame_read = [&] {
        r.release();  // the frame's views read from the file
        if (a.frame_count == 1 && per_piece > 1)  // the piece's arrays at their final size, not grown by doubling
            for (auto member : {&StoredAnimation::positions, &StoredAnimation::normals, &StoredAnimation::reflect,
                                &StoredAnimation::refract, &StoredAnimation::foam, &StoredAnimation::colors})
                (a.*member).reserve((a.*member).size() * per_piece);
        if (a.frame_count == per_piece) hand_on();
    };
    if (g.path_kind == "weights") {
        read_morph_frames(r, m, first, a, frame_read, window);
    } else {  // nodes (a mesh per frame) or one frame file
        for (std::size_t k = 0; k < water.size(); ++k) {
            const std::size_t mesh = water[k];
            if (!window.has(k)) {  // its views stay in the file, unread
                if (k < window.first) ++a.first_frame;
                continue;
            }
            if (m.meshes[mesh].primitives.empty()) r.fail("a frame's mesh has no primitive");
            // Draco's edgebreaker orders a frame's points by the triangles alone, so frames
            // of one run share an order; a file whose frames do not cannot be read as one.
            const auto other_triangles = [&] {
                r.fail("frame " + std::to_string(mesh) + " has other triangles than frame 0" +
                       (a.draco_frames ? " (Draco-compressed frames of different orders: convert from an uncompressed output, or run the scene again)" : ""));
            };
            if (m.meshes[mesh].primitives.size() > 1) {
                const Joined j = mesh != water[0] ? join_primitives(r, m.meshes[mesh], static_cast<int>(mesh), a.layout)
                                 : keep           ? *g.joined
                                                  : std::move(*g.joined);
                if (j.triangles != triangles) other_triangles();
                append(a, j.frame);
            } else {
                const tinygltf::Primitive& p = m.meshes[mesh].primitives[0];
                // The nodes form's frames share the first mesh's indices accessor: its
                // triangles, read at open, are not read and compared again.
                if ((g.joined || p.indices != first.indices) && r.indices(p.indices) != triangles) other_triangles();
                append(a, read_frame(r, p.attributes, static_cast<int>(mesh), false, a.layout));
            }
            ++a.frame_count;
            frame_read();
        }
    }
    if (a.frame_count > 0 || !handed) hand_on();
}

void read_glb_pieces(const std::string& path, const std::function<void(StoredAnimation&&, std::size_t)>& piece,
                     const FrameWindow& window = {}) {
    GlbFile g;
    g.path = path;
    open_glb(g);
    read_glb_frames(g, piece, window);
}

}  // namespace

MorphAnimationView StoredAnimation::view() const {
    MorphAnimationView v = animation_view(*this);
    v.name = name;
    return v;
}

namespace {

// Appends a later piece's frames to `a`.
void append_piece(StoredAnimation& a, StoredAnimation&& f) {
    if (a.frame_count == 0) {
        a = std::move(f);
        return;
    }
    a.frame_count += f.frame_count;
    const auto cat = [](std::vector<float>& to, const std::vector<float>& from) { to.insert(to.end(), from.begin(), from.end()); };
    cat(a.positions, f.positions), cat(a.normals, f.normals), cat(a.reflect, f.reflect), cat(a.refract, f.refract);
    cat(a.foam, f.foam), cat(a.colors, f.colors);
}

StoredAnimation read_glb(const std::string& path) {
    StoredAnimation a;
    read_glb_pieces(path, [&](StoredAnimation&& f, std::size_t) { append_piece(a, std::move(f)); });
    return a;
}

}  // namespace

namespace {

// The files form's index.json: its frame files (each inside the index's folder: no
// absolute path, no .., no link out) with their frame numbers, and its fps and loop
// when it records them.
struct FrameIndex {
    std::vector<std::pair<std::string, std::size_t>> listed;
    std::optional<double> fps;
    std::optional<std::size_t> loop_frames;
};

FrameIndex read_frame_index(const std::string& path) {
    detail::require_input_file(path);
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw InputError(path + ": cannot read the file");
    const nlohmann::json index = detail::parse_json_input(text, path + " (a frame index)");
    if (!index.is_object() || !index.contains("frames") || !index["frames"].is_array() || index["frames"].empty())
        throw InputError(path + ": not a frame index (no \"frames\")");
    const auto number = [&](const nlohmann::json& at, const std::string& where, const char* key, double most, bool whole) {
        const nlohmann::json& v = at[key];
        if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= most) || (whole && !v.is_number_unsigned()))
            throw InputError(path + ": " + where + key + " is not " + (whole ? "a whole number" : "a number") + " in [0, " +
                             detail::format_number(most) + "]");
        return v.get<double>();
    };
    // Every entry checked before a frame is read: its file named inside the index's
    // folder (no absolute path, no .., no link out), its frame a whole number.
    const std::string folder = std::filesystem::path(path).parent_path().string();
    FrameIndex out;
    for (const auto& entry : index["frames"]) {
        const std::string where = "frames[" + std::to_string(out.listed.size()) + "].";
        if (!entry.is_object() || !entry.contains("file") || !entry["file"].is_string() || !entry.contains("frame"))
            throw InputError(path + ": " + where.substr(0, where.size() - 1) + " is not an object with a \"file\" and a \"frame\"");
        const auto frame = static_cast<std::size_t>(number(entry, where, "frame", kMaxStoredFrames, true));
        out.listed.emplace_back(path_inside(folder, entry["file"].get<std::string>(), path + ": " + where + "file"), frame);
    }
    if (index.contains("fps")) out.fps = number(index, "", "fps", 1000.0, false);
    if (index.contains("loop_frames")) out.loop_frames = static_cast<std::size_t>(number(index, "", "loop_frames", kMaxStoredFrames, true));
    return out;
}

}  // namespace

void read_animation_pieces(const std::string& path, const std::function<void(StoredAnimation&&, std::size_t)>& piece) {
    if (std::filesystem::path(path).extension() != ".json") {
        read_glb_pieces(path, piece);
        return;
    }
    // The files form: index.json lists the frame files.
    const FrameIndex index = read_frame_index(path);
    const auto& listed = index.listed;
    std::vector<std::uint32_t> triangles;  // the first frame's, which every frame must share
    std::size_t expected = 0, vertex_count = 0;
    double fps = 0.0;
    std::size_t loop_frames = 0;
    bool draco = false;
    for (const auto& [file, frame] : listed) {
        StoredAnimation f = read_glb(file);
        if (expected == 0) {
            fps = index.fps.value_or(f.fps);
            loop_frames = index.loop_frames.value_or(f.loop_frames);
            if (!(fps > 0.0)) throw InputError(path + ": fps is 0");
            triangles = f.triangles, vertex_count = f.vertex_count, draco = f.draco_frames;
        } else {
            if (frame != expected) throw InputError(path + ": frame " + std::to_string(expected) + " is missing (next is " + std::to_string(frame) + ")");
            if (f.triangles != triangles || f.vertex_count != vertex_count)
                throw InputError(file + ": other triangles than the first frame" +
                                 std::string(draco || f.draco_frames ? " (Draco-compressed frames of different orders: convert from an uncompressed output, or run the scene again)" : ""));
        }
        f.first_frame = frame, f.fps = fps, f.loop_frames = loop_frames;
        expected = frame + 1;
        piece(std::move(f), listed.size());
    }
}

StoredAnimation read_animation(const std::string& path) {
    StoredAnimation a;
    read_animation_pieces(path, [&](StoredAnimation&& f, std::size_t) { append_piece(a, std::move(f)); });
    return a;
}

StoredAnimation read_animation_frames(const std::string& path, std::size_t first, std::size_t count) {
    if (std::filesystem::path(path).extension() == ".json")
        throw InputError(path + ": read_animation_frames reads a .glb or .gltf (the files form: read its frame files)");
    StoredAnimation a;
    read_glb_pieces(path, [&](StoredAnimation&& f, std::size_t) { append_piece(a, std::move(f)); }, FrameWindow{first, count});
    if (a.frame_count == 0) throw InputError(path + ": no frame " + std::to_string(first) + " in the file");
    return a;
}

struct FrameReader::State {
    std::string path;
    std::unique_ptr<GlbFile> glb;  // a .glb/.gltf, kept open
    std::vector<std::string> files;  // the files form's frame files
    ViewMemo memo;                   // the files form: the frame files' shared views, decoded
    StoredAnimation info;            // the numbers and the triangles (no frame arrays)
    std::size_t frame_count = 0;
    std::mutex mutex;
};

FrameReader::FrameReader(const std::string& path) : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.path = path;
    if (std::filesystem::path(path).extension() != ".json") {
        s.glb = std::make_unique<GlbFile>();
        s.glb->path = path;
        open_glb(*s.glb);
        const StoredAnimation& a = s.glb->a;
        s.info.vertex_count = a.vertex_count, s.info.first_frame = a.first_frame, s.info.loop_frames = a.loop_frames;
        s.info.fps = a.fps, s.info.scene = a.scene, s.info.name = a.name, s.info.triangles = a.triangles;
        s.frame_count = s.glb->total;
        return;
    }
    const FrameIndex index = read_frame_index(path);
    for (std::size_t i = 0; i < index.listed.size(); ++i) {
        const auto& [file, frame] = index.listed[i];
        if (i > 0 && frame != index.listed[0].second + i)
            throw InputError(path + ": frame " + std::to_string(index.listed[0].second + i) + " is missing (next is " + std::to_string(frame) + ")");
        s.files.push_back(file);
    }
    GlbFile first;
    first.path = s.files[0];
    open_glb(first, &s.memo, false);
    s.info.vertex_count = first.a.vertex_count, s.info.first_frame = index.listed[0].second, s.info.name = first.a.name;
    s.info.fps = index.fps.value_or(first.a.fps), s.info.loop_frames = index.loop_frames.value_or(first.a.loop_frames);
    s.info.scene = first.a.scene, s.info.triangles = std::move(first.a.triangles);
    if (!(s.info.fps > 0.0)) throw InputError(path + ": fps is 0");
    s.frame_count = s.files.size();
}

FrameReader::~FrameReader() = default;
FrameReader::FrameReader(FrameReader&&) noexcept = default;
FrameReader& FrameReader::operator=(FrameReader&&) noexcept = default;

std::size_t FrameReader::frame_count() const noexcept { return state_->frame_count; }
std::size_t FrameReader::vertex_count() const noexcept { return state_->info.vertex_count; }
std::size_t FrameReader::first_frame() const noexcept { return state_->info.first_frame; }
std::size_t FrameReader::loop_frames() const noexcept { return state_->info.loop_frames; }
double FrameReader::fps() const noexcept { return state_->info.fps; }
const std::string& FrameReader::scene() const noexcept { return state_->info.scene; }
const std::vector<std::uint32_t>& FrameReader::triangles() const noexcept { return state_->info.triangles; }

StoredAnimation FrameReader::frame(std::size_t k, bool normals) {
    State& s = *state_;
    const std::lock_guard<std::mutex> lock(s.mutex);
    if (k >= s.frame_count)
        throw InputError(s.path + ": no frame " + std::to_string(k) + " (it has " + std::to_string(s.frame_count) + ")");
    StoredAnimation out;
    const auto take = [&](StoredAnimation&& f, std::size_t) { out = std::move(f); };
    if (s.glb) {
        s.glb->normals = normals;
        read_glb_frames(*s.glb, take, FrameWindow{k, 1}, true);
        return out;
    }
    GlbFile g;
    g.path = s.files[k];
    g.normals = normals;
    open_glb(g, &s.memo, false);
    if (g.a.triangles != s.info.triangles || g.a.vertex_count != s.info.vertex_count || g.total != 1)
        throw InputError(g.path + ": other triangles than the first frame" +
                         std::string(g.a.draco_frames ? " (Draco-compressed frames of different orders: convert from an uncompressed output, or run the scene again)" : ""));
    read_glb_frames(g, take, FrameWindow{0, 1}, true);
    out.first_frame = s.info.first_frame + k, out.fps = s.info.fps, out.loop_frames = s.info.loop_frames;
    return out;
}

}  // namespace wave
