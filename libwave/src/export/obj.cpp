// OBJ text for one frame. std::to_chars gives the shortest text that reads back to the
// same float, so the file is exact and byte-identical for identical input.
#include "libwave/export.h"

#include <cassert>
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

}  // namespace wave
