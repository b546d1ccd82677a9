// Area-weighted vertex normals (Jeschke et al. 2003 §5: accumulate adjacent faces).
#include "libwave/errors.h"
#include "libwave/shade.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace wave {
namespace {

// Twice the area times the unit normal of triangle t, in float (as summed).
inline void face_cross(std::span<const float> p, std::span<const std::uint32_t> tri, std::size_t t, float& cx, float& cy,
                       float& cz) noexcept {
    const std::size_t a = 3 * std::size_t{tri[3 * t]}, b = 3 * std::size_t{tri[3 * t + 1]}, c = 3 * std::size_t{tri[3 * t + 2]};
    // In double: the cross product of nearly parallel float edges loses too much.
    const double ux = double{p[b]} - p[a], uy = double{p[b + 1]} - p[a + 1], uz = double{p[b + 2]} - p[a + 2];
    const double vx = double{p[c]} - p[a], vy = double{p[c + 1]} - p[a + 1], vz = double{p[c + 2]} - p[a + 2];
    cx = static_cast<float>(uy * vz - uz * vy);
    cy = static_cast<float>(uz * vx - ux * vz);
    cz = static_cast<float>(ux * vy - uy * vx);
}

inline void normalise(float* n) noexcept {
    const double len = std::sqrt(double{n[0]} * n[0] + double{n[1]} * n[1] + double{n[2]} * n[2]);
    if (len > 0.0) {
        n[0] = static_cast<float>(n[0] / len);
        n[1] = static_cast<float>(n[1] / len);
        n[2] = static_cast<float>(n[2] / len);
    } else {
        n[0] = 0.0f;
        n[1] = 0.0f;
        n[2] = 1.0f;
    }
}

}  // namespace

void vertex_normals(std::span<const float> p, std::span<const std::uint32_t> tri, std::span<float> n) noexcept {
    std::fill(n.begin(), n.end(), 0.0f);
    for (std::size_t t = 0; 3 * t + 2 < tri.size(); ++t) {
        float cx, cy, cz;
        face_cross(p, tri, t, cx, cy, cz);
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t v = 3 * std::size_t{tri[3 * t + k]};
            n[v] += cx;
            n[v + 1] += cy;
            n[v + 2] += cz;
        }
    }
    for (std::size_t v = 0; v + 2 < n.size(); v += 3) normalise(&n[v]);
}

void vertex_normals(std::span<const float> p, std::span<const std::uint32_t> tri, const VertexFaces& adj, std::span<float> n) {
    const std::size_t count = n.size() / 3;
    if (adj.offsets.size() != count + 1 || p.size() != n.size())
        throw InputError("vertex_normals: the adjacency is for " + std::to_string(adj.offsets.size() - 1) + " vertices, got " +
                         std::to_string(count));
    const std::size_t nt = tri.size() / 3;
    // Every entry is written below: no zero fill of the ~24 MB a 1 M-point frame needs.
    const auto face = std::make_unique_for_overwrite<float[]>(3 * nt);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nt, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t t = r.begin(); t != r.end(); ++t) face_cross(p, tri, t, face[3 * t], face[3 * t + 1], face[3 * t + 2]);
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 2048), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            float s[3] = {0.0f, 0.0f, 0.0f};
            for (std::uint32_t i = adj.offsets[v]; i < adj.offsets[v + 1]; ++i) {
                const float* c = &face[3 * std::size_t{adj.faces[i]}];
                s[0] += c[0];
                s[1] += c[1];
                s[2] += c[2];
            }
            normalise(s);
            n[3 * v] = s[0];
            n[3 * v + 1] = s[1];
            n[3 * v + 2] = s[2];
        }
    });
}

}  // namespace wave
