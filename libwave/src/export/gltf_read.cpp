// Reading libwave's own glTF outputs back (`wave convert`): every form, layout,
// quantisation, and Draco-compressed morph bases. Only files libwave wrote: the asset
// carries `extras.libwave` (fps, first frame, loop) that glTF has no field for.
#include "gltf_library.h"

#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/io.h"
#include "core/files.h"
#include "core/format.h"
#include "core/json_input.h"
#include "gltf_load.h"
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

using detail::LazyViews;
using detail::ViewMemo;
using detail::kMaxStoredFrames;
using detail::load_model;

namespace {

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

// A .glb/.gltf of libwave's, a piece of frames at a time (frames_per_piece; a file of a
// morph or nodes form): the file's bytes go once tinygltf holds its buffer, and the
// decoded frames are handed on a piece at a time, so memory holds the file's buffer
// and one piece, not the decoded animation beside it.
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
