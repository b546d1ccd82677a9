// Point location in a triangle mesh's plan (x, y): a bucket grid over the triangles'
// bounding boxes. Used to resample per-vertex fields of the ray strips at other points
// (the camera grid, the water mesh).
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
    std::span<const double> x_, y_;
    std::span<const std::uint32_t> triangles_;
    double x0_ = 0.0, y0_ = 0.0, x1_ = 0.0, y1_ = 0.0, cell_ = 1.0;
    std::size_t cx_ = 0, cy_ = 0;
    std::vector<std::uint32_t> start_, items_;  ///< per cell, the triangles meeting it (compressed rows)

    std::size_t cell_of(double v, double lo, std::size_t count) const;
};

}  // namespace wave::detail
