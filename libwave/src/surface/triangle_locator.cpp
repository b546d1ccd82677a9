// Point location by a bucket grid (triangle_locator.h).
#include "surface/triangle_locator.h"

#include <algorithm>
#include <cmath>

namespace wave::detail {

TriangleLocator::TriangleLocator(std::span<const double> x, std::span<const double> y, std::span<const std::uint32_t> triangles)
    : x_(x), y_(y), triangles_(triangles) {
    const std::size_t nt = triangles.size() / 3;
    if (nt == 0 || x.empty()) return;
    // The triangles' bounding box (not every vertex's: vertices no triangle uses, e.g. a
    // far skirt's, widened the buckets until thousands of triangles shared each).
    x0_ = x1_ = x[triangles[0]];
    y0_ = y1_ = y[triangles[0]];
    for (const std::uint32_t v : triangles) {
        x0_ = std::min(x0_, x[v]);
        x1_ = std::max(x1_, x[v]);
        y0_ = std::min(y0_, y[v]);
        y1_ = std::max(y1_, y[v]);
    }
    // Half a mean triangle's width per cell, at most 2048 cells a side: a graded mesh
    // (a surf zone at H/4 in a mesh of metres) crowds its fine triangles into cells
    // sized by the mean, and a cell of two mean widths held ~100 of them there (a
    // point's lookup took 18 % of a breaking beach's frames). The first triangle found
    // is the lowest-numbered one holding the point, whatever the cells.
    cell_ = std::max(0.5 * std::sqrt((x1_ - x0_) * (y1_ - y0_) / static_cast<double>(nt)),
                     std::max(x1_ - x0_, y1_ - y0_) / 2048.0) + 1e-12;
    cx_ = static_cast<std::size_t>((x1_ - x0_) / cell_) + 1;
    cy_ = static_cast<std::size_t>((y1_ - y0_) / cell_) + 1;
    start_.assign(cx_ * cy_ + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::uint32_t> fill(pass ? start_.begin() : start_.end(), start_.end());
        if (pass) items_.resize(start_.back());
        for (std::size_t t = 0; t < nt; ++t) {
            const std::uint32_t a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
            const std::size_t i0 = cell_of(std::min({x[a], x[b], x[c]}), x0_, cx_), i1 = cell_of(std::max({x[a], x[b], x[c]}), x0_, cx_),
                              j0 = cell_of(std::min({y[a], y[b], y[c]}), y0_, cy_), j1 = cell_of(std::max({y[a], y[b], y[c]}), y0_, cy_);
            for (std::size_t j = j0; j <= j1; ++j)
                for (std::size_t i = i0; i <= i1; ++i) {
                    if (pass == 0) ++start_[j * cx_ + i + 1];
                    else items_[fill[j * cx_ + i]++] = static_cast<std::uint32_t>(t);
                }
        }
        if (pass == 0)
            for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
    }
}

std::size_t TriangleLocator::cell_of(double v, double lo, std::size_t count) const {
    return static_cast<std::size_t>(std::clamp((v - lo) / cell_, 0.0, static_cast<double>(count - 1)));
}

bool TriangleLocator::locate(double px, double py, Hit& hit) const {
    if (start_.empty() || px < x0_ || px > x1_ || py < y0_ || py > y1_) return false;
    const std::size_t k = cell_of(py, y0_, cy_) * cx_ + cell_of(px, x0_, cx_);
    for (std::uint32_t i = start_[k]; i < start_[k + 1]; ++i) {
        const std::size_t t = items_[i];
        const std::uint32_t a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
        const double ux = x_[b] - x_[a], uy = y_[b] - y_[a], wx = x_[c] - x_[a], wy = y_[c] - y_[a];
        const double d = ux * wy - uy * wx;
        if (d == 0.0) continue;
        const double qx = px - x_[a], qy = py - y_[a];
        const double wb = (qx * wy - qy * wx) / d, wc = (ux * qy - uy * qx) / d, wa = 1.0 - wb - wc;
        constexpr double eps = -1e-9;
        if (wa < eps || wb < eps || wc < eps) continue;
        hit = {a, b, c, wa, wb, wc};
        return true;
    }
    return false;
}

}  // namespace wave::detail
