// Point location in a triangle mesh's plan (x, y): bucket grids over the triangles'
// bounding boxes, one for the mesh's ordinary triangles and one for its large ones (a
// far-field skirt's, kilometres across). Used to resample per-vertex fields of the ray
// strips at other points (the camera grid, the water mesh) and to ride whitewater on it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace wave::detail {

class TriangleLocator {
public:
    /// x, y: the vertices; triangles: 3 indices each. The spans must outlive the locator.
    TriangleLocator(std::span<const double> x, std::span<const double> y, std::span<const std::uint32_t> triangles);

    struct Hit {
        std::uint32_t a = 0, b = 0, c = 0;  ///< the triangle's vertices
        double wa = 0.0, wb = 0.0, wc = 0.0;  ///< barycentric weights (sum 1, each >= −1e-9)
    };
    /// The first triangle by index that holds (px, py) — where triangles overlap (folded
    /// strips at caustics) the lowest index wins — or false off every triangle.
    /// Degenerate triangles are skipped. Thread-safe.
    bool locate(double px, double py, Hit& hit) const;

private:
    // One bucket grid: per cell, the triangles meeting it in index order (compressed rows).
    struct Grid {
        double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0, cell = 1.0;
        std::size_t cx = 0, cy = 0;
        std::vector<std::uint32_t> start, items;
    };
    std::span<const double> x_, y_;
    std::span<const std::uint32_t> triangles_;
    std::array<Grid, 2> grids_;  ///< the ordinary triangles', the large ones'

    void build(Grid& g, std::span<const std::uint32_t> members) const;
    // The lowest-numbered triangle of `g` holding the point, below `below`; kNone if none.
    std::uint32_t first_in(const Grid& g, double px, double py, std::uint32_t below, Hit& hit) const;
};

}  // namespace wave::detail
