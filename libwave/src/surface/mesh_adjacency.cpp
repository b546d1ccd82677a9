// The triangles around each vertex of a mesh (VertexFaces): what the parallel vertex
// normals gather, the untangling walks and the strips' gap filling spreads along.
#include "libwave/errors.h"
#include "libwave/surface.h"

#include <cstdint>
#include <string>
#include <vector>

namespace wave {

VertexFaces vertex_faces(std::size_t vertex_count, std::span<const std::uint32_t> tri) {
    VertexFaces a;
    a.offsets.assign(vertex_count + 1, 0);
    for (std::uint32_t v : tri) {
        if (v >= vertex_count) throw InputError("vertex_faces: triangle index " + std::to_string(v) + " >= " + std::to_string(vertex_count));
        ++a.offsets[v + 1];
    }
    for (std::size_t v = 0; v < vertex_count; ++v) a.offsets[v + 1] += a.offsets[v];
    a.faces.resize(tri.size());
    std::vector<std::uint32_t> fill(a.offsets.begin(), a.offsets.end() - 1);
    for (std::size_t i = 0; i < tri.size(); ++i) a.faces[fill[tri[i]]++] = static_cast<std::uint32_t>(i / 3);  // ascending
    return a;
}

}  // namespace wave
