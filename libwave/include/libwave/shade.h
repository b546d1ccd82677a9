// libwave — shade: per-vertex quantities computed per frame for renderers.
//
// Today: vertex normals by accumulating area-weighted face normals (Jeschke et al.
// 2003, §5). Fresnel weights and foam are not written yet.
#pragma once

#include <cstdint>
#include <span>

namespace wave {

/// Unit vertex normals of a triangle mesh: each triangle adds its cross product (twice
/// its area times its unit normal) to its three vertices, then the sums are
/// normalised. A vertex of only degenerate triangles gets (0, 0, 1). Counter-clockwise
/// triangles give normals on the side they face. Writes into `normals` (3 floats per
/// vertex, same size as `positions`); allocates nothing.
void vertex_normals(std::span<const float> positions, std::span<const std::uint32_t> triangles,
                    std::span<float> normals) noexcept;

}  // namespace wave
