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

std::string pc2_header(std::size_t point_count, std::size_t sample_count, float start_frame) {
    if (point_count > 0x7fffffff || sample_count > 0x7fffffff) throw LimitError("PC2 export: more than 2³¹ points or samples");
    static_assert(std::endian::native == std::endian::little, "PC2 is little-endian");
    std::string out("POINTCACHE2", 12);  // the signature with its terminating zero
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
