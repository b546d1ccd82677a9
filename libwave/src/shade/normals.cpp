// Area-weighted vertex normals (Jeschke et al. 2003 §5: accumulate adjacent faces).
#include "libwave/shade.h"

#include <algorithm>
#include <cmath>

namespace wave {

void vertex_normals(std::span<const float> p, std::span<const std::uint32_t> tri, std::span<float> n) noexcept {
    std::fill(n.begin(), n.end(), 0.0f);
    for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
        const std::size_t a = 3 * std::size_t{tri[t]}, b = 3 * std::size_t{tri[t + 1]}, c = 3 * std::size_t{tri[t + 2]};
        // In double: the cross product of nearly parallel float edges loses too much.
        const double ux = double{p[b]} - p[a], uy = double{p[b + 1]} - p[a + 1], uz = double{p[b + 2]} - p[a + 2];
        const double vx = double{p[c]} - p[a], vy = double{p[c + 1]} - p[a + 1], vz = double{p[c + 2]} - p[a + 2];
        const auto cx = static_cast<float>(uy * vz - uz * vy), cy = static_cast<float>(uz * vx - ux * vz),
                   cz = static_cast<float>(ux * vy - uy * vx);
        for (std::size_t v : {a, b, c}) {
            n[v] += cx;
            n[v + 1] += cy;
            n[v + 2] += cz;
        }
    }
    for (std::size_t v = 0; v + 2 < n.size(); v += 3) {
        const double len = std::sqrt(double{n[v]} * n[v] + double{n[v + 1]} * n[v + 1] + double{n[v + 2]} * n[v + 2]);
        if (len > 0.0) {
            n[v] = static_cast<float>(n[v] / len);
            n[v + 1] = static_cast<float>(n[v + 1] / len);
            n[v + 2] = static_cast<float>(n[v + 2] / len);
        } else {
            n[v] = 0.0f;
            n[v + 1] = 0.0f;
            n[v + 2] = 1.0f;
        }
    }
}

}  // namespace wave
