// OBJ text for one frame. std::to_chars gives the shortest text that reads back to the
// same float, so the file is exact and byte-identical for identical input.
#include "libwave/export.h"

#include "libwave/errors.h"

#include <bit>
#include <cassert>
#include <cstdint>
#include <charconv>

namespace wave {

std::string mesh_to_obj(std::span<const float> positions, std::span<const std::uint32_t> triangles,
                        std::string_view comment) {
    std::string out;
    out.reserve(positions.size() * 12 + triangles.size() * 8 + comment.size() + 8);
    out += "# ";
    out += comment;
    out += '\n';
    char buf[32];
    for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
        out += 'v';
        for (int c = 0; c < 3; ++c) {
            out += ' ';
            out.append(buf, std::to_chars(buf, buf + sizeof buf, positions[i + static_cast<std::size_t>(c)]).ptr);
        }
        out += '\n';
    }
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        out += 'f';
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = triangles[t + static_cast<std::size_t>(c)];
            assert(v < positions.size() / 3);
            out += ' ';
            out.append(buf, std::to_chars(buf, buf + sizeof buf, v + 1).ptr);
        }
        out += '\n';
    }
    return out;
}

std::string ply_frame_bytes(const MorphAnimationView& view, std::size_t f) {
    static_assert(std::endian::native == std::endian::little, "the PLY frames are binary little-endian");
    const std::size_t n = view.vertex_count;
    const bool shaded = !view.foam.empty();
    if (f >= view.frame_count || view.positions.size() < 3 * n * (f + 1) || view.normals.size() < 3 * n * (f + 1) ||
        view.texcoords.size() != 2 * n || (shaded && (view.reflect.size() < n * (f + 1) || view.refract.size() < n * (f + 1) ||
                                                      view.foam.size() < n * (f + 1))))
        throw InputError("PLY export: frame " + std::to_string(f) + " of " + std::to_string(view.frame_count) +
                         " frames of " + std::to_string(n) + " vertices is not in the arrays");
    for (std::uint32_t v : view.triangles)
        if (v >= n) throw InputError("PLY export: triangle index " + std::to_string(v) + " >= vertex count " + std::to_string(n));
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment libwave: frame " + std::to_string(view.first_frame + f) +
                      " of " + (view.scene.empty() ? std::string("an animation") : view.scene) + ", z up\nelement vertex " +
                      std::to_string(n) + "\n";
    for (const char* p : {"x", "y", "z", "nx", "ny", "nz", "s", "t"}) out += std::string("property float ") + p + "\n";
    if (shaded)
        for (const char* p : {"reflect", "refract", "foam"}) out += std::string("property float ") + p + "\n";
    out += "element face " + std::to_string(view.triangles.size() / 3) + "\nproperty list uchar uint vertex_indices\nend_header\n";
    const auto put = [&](const auto value) { out.append(reinterpret_cast<const char*>(&value), sizeof value); };
    for (std::size_t v = 0; v < n; ++v) {
        for (std::size_t c = 0; c < 3; ++c) put(view.positions[3 * (f * n + v) + c]);
        for (std::size_t c = 0; c < 3; ++c) put(view.normals[3 * (f * n + v) + c]);
        put(view.texcoords[2 * v]);
        put(view.texcoords[2 * v + 1]);
        if (shaded) put(view.reflect[f * n + v]), put(view.refract[f * n + v]), put(view.foam[f * n + v]);
    }
    for (std::size_t t = 0; t + 2 < view.triangles.size(); t += 3) {
        put(std::uint8_t{3});
        for (std::size_t c = 0; c < 3; ++c) put(view.triangles[t + c]);
    }
    return out;
}

std::string pc2_header(std::size_t point_count, std::size_t sample_count, float start_frame) {
    if (point_count > 0x7fffffff || sample_count > 0x7fffffff) throw LimitError("PC2 export: more than 2³¹ points or samples");
    static_assert(std::endian::native == std::endian::little, "PC2 is little-endian");
    std::string out("POINTCACHE2\0", 12);  // the signature with its terminating zero
    const auto put = [&](const auto value) { out.append(reinterpret_cast<const char*>(&value), sizeof value); };
    put(std::int32_t{1});
    put(static_cast<std::int32_t>(point_count));
    put(start_frame);
    put(1.0f);  // one sample per frame
    put(static_cast<std::int32_t>(sample_count));
    return out;
}

std::string pc2_bytes(std::span<const float> points, std::size_t point_count, std::size_t sample_count, float start_frame) {
    if (points.size() != 3 * point_count * sample_count)
        throw InputError("PC2 export: " + std::to_string(points.size()) + " values for " + std::to_string(sample_count) +
                         " samples of " + std::to_string(point_count) + " points");
    std::string out = pc2_header(point_count, sample_count, start_frame);
    out.append(reinterpret_cast<const char*>(points.data()), points.size_bytes());
    return out;
}

}  // namespace wave
