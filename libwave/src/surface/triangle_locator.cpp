// Point location by bucket grids (triangle_locator.h).
#include "surface/triangle_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wave::detail {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// A triangle's bounding box's longer side is "large" beyond this many times the median
// one's: a far-field skirt's triangles grow to kilometres around a mesh of metres, and in
// one grid their box set the cells (at most 2048 a side: 20 m cells over a 40 km skirt),
// so that hundreds of a 1 km ocean's 2 m triangles shared each cell (a point's lookup took
// 38 % of the open ocean's run). Apart, each grid's cells follow its own triangles.
constexpr double kLarge = 16.0;

std::size_t cell_of(double v, double lo, double cell, std::size_t count) {
    return static_cast<std::size_t>(std::clamp((v - lo) / cell, 0.0, static_cast<double>(count - 1)));
}

}  // namespace

TriangleLocator::TriangleLocator(std::span<const double> x, std::span<const double> y, std::span<const std::uint32_t> triangles)
    : x_(x), y_(y), triangles_(triangles) {
    const std::size_t nt = triangles.size() / 3;
    if (nt == 0 || x.empty()) return;
    std::vector<double> side(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
        side[t] = std::max(std::max({x[a], x[b], x[c]}) - std::min({x[a], x[b], x[c]}),
                           std::max({y[a], y[b], y[c]}) - std::min({y[a], y[b], y[c]}));
    }
    std::vector<double> sorted = side;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(nt / 2), sorted.end());
    const double limit = kLarge * sorted[nt / 2];
    std::array<std::vector<std::uint32_t>, 2> members;
    for (std::size_t t = 0; t < nt; ++t) members[side[t] > limit ? 1 : 0].push_back(static_cast<std::uint32_t>(t));
    for (std::size_t level = 0; level < 2; ++level) build(grids_[level], members[level]);
}

void TriangleLocator::build(Grid& g, std::span<const std::uint32_t> members) const {
    if (members.empty()) return;
    // The members' bounding box (not every vertex's: vertices no triangle uses widened
    // the buckets until thousands of triangles shared each).
    const std::uint32_t first = triangles_[3 * members[0]];
    g.x0 = g.x1 = x_[first];
    g.y0 = g.y1 = y_[first];
    for (const std::uint32_t t : members)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = triangles_[3 * t + static_cast<std::size_t>(k)];
            g.x0 = std::min(g.x0, x_[v]), g.x1 = std::max(g.x1, x_[v]);
            g.y0 = std::min(g.y0, y_[v]), g.y1 = std::max(g.y1, y_[v]);
        }
    // Half a mean triangle's width per cell, at most 2048 cells a side: a graded mesh
    // (a surf zone at H/4 in a mesh of metres) crowds its fine triangles into cells
    // sized by the mean, and a cell of two mean widths held ~100 of them there (a
    // point's lookup took 18 % of a breaking beach's frames).
    g.cell = std::max(0.5 * std::sqrt((g.x1 - g.x0) * (g.y1 - g.y0) / static_cast<double>(members.size())),
                      std::max(g.x1 - g.x0, g.y1 - g.y0) / 2048.0) + 1e-12;
    g.cx = static_cast<std::size_t>((g.x1 - g.x0) / g.cell) + 1;
    g.cy = static_cast<std::size_t>((g.y1 - g.y0) / g.cell) + 1;
    g.start.assign(g.cx * g.cy + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::uint32_t> fill(pass ? g.start.begin() : g.start.end(), g.start.end());
        if (pass) g.items.resize(g.start.back());
        for (const std::uint32_t t : members) {  // in index order: each cell's row too
            const std::uint32_t a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
            const std::size_t i0 = cell_of(std::min({x_[a], x_[b], x_[c]}), g.x0, g.cell, g.cx),
                              i1 = cell_of(std::max({x_[a], x_[b], x_[c]}), g.x0, g.cell, g.cx),
                              j0 = cell_of(std::min({y_[a], y_[b], y_[c]}), g.y0, g.cell, g.cy),
                              j1 = cell_of(std::max({y_[a], y_[b], y_[c]}), g.y0, g.cell, g.cy);
            for (std::size_t j = j0; j <= j1; ++j)
                for (std::size_t i = i0; i <= i1; ++i) {
                    if (pass == 0) ++g.start[j * g.cx + i + 1];
                    else g.items[fill[j * g.cx + i]++] = t;
                }
        }
        if (pass == 0)
            for (std::size_t k = 1; k < g.start.size(); ++k) g.start[k] += g.start[k - 1];
    }
}

std::uint32_t TriangleLocator::first_in(const Grid& g, double px, double py, std::uint32_t below, Hit& hit) const {
    if (g.start.empty() || px < g.x0 || px > g.x1 || py < g.y0 || py > g.y1) return kNone;
    const std::size_t k = cell_of(py, g.y0, g.cell, g.cy) * g.cx + cell_of(px, g.x0, g.cell, g.cx);
    for (std::uint32_t i = g.start[k]; i < g.start[k + 1]; ++i) {
        const std::uint32_t t = g.items[i];
        if (t >= below) break;  // rows run in index order
        const std::uint32_t a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
        const double ux = x_[b] - x_[a], uy = y_[b] - y_[a], wx = x_[c] - x_[a], wy = y_[c] - y_[a];
        const double d = ux * wy - uy * wx;
        if (d == 0.0) continue;
        const double qx = px - x_[a], qy = py - y_[a];
        const double wb = (qx * wy - qy * wx) / d, wc = (ux * qy - uy * qx) / d, wa = 1.0 - wb - wc;
        constexpr double eps = -1e-9;
        if (wa < eps || wb < eps || wc < eps) continue;
        hit = {a, b, c, wa, wb, wc};
        return t;
    }
    return kNone;
}

bool TriangleLocator::locate(double px, double py, Hit& hit) const {
    const std::uint32_t t = first_in(grids_[0], px, py, kNone, hit);
    // A large triangle of a lower index wins where the two overlap (as one grid gave).
    return first_in(grids_[1], px, py, t, hit) != kNone || t != kNone;
}

}  // namespace wave::detail
