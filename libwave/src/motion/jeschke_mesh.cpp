// Jeschke's breakers over the water mesh's graph: the traced breakers carried into the
// mesh's gaps (fill_jeschke_gaps) and where the mesh resolves a breaker's tube and wall
// (resolve_jeschke_lips). Both walk the mesh's edges outward from a set of vertices.
#include "core/smoothstep.h"
#include "libwave/errors.h"
#include "libwave/motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace wave {
namespace {

// resolve_jeschke_lips: the sections are taken in full this many heights H from the
// mesh's boundary.
constexpr double kResolveReachHeights = 4.0;

// Each vertex's neighbours over the triangles (indices below n), as compressed rows:
// vertex v's are next[start[v] .. start[v + 1]), two per triangle it is in.
std::pair<std::vector<std::uint32_t>, std::vector<std::uint32_t>> vertex_neighbours(std::span<const std::uint32_t> triangles,
                                                                                     std::size_t n) {
    std::vector<std::uint32_t> start(n + 1, 0), next;
    for (std::uint32_t v : triangles) start[v + 1] += 2;
    for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    next.resize(start[n]);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (std::size_t i = 0; i < 3; ++i) {
            const std::uint32_t a = triangles[t + i];
            next[fill[a]++] = triangles[t + (i + 1) % 3];
            next[fill[a]++] = triangles[t + (i + 2) % 3];
        }
    return {std::move(start), std::move(next)};
}

}  // namespace

std::size_t fill_jeschke_gaps(JeschkeMotionPlan& p, std::span<const std::uint32_t> triangles, double reach_wavelengths) {
    const std::size_t n = p.vertex_count();
    if (!(reach_wavelengths > 0.0) || !std::isfinite(reach_wavelengths))
        throw InputError("jeschke gaps: reach_wavelengths must be > 0");
    // The mesh's vertex neighbours.
    for (std::uint32_t v : triangles)
        if (v >= n) throw InputError("jeschke gaps: triangle index " + std::to_string(v) + " of " + std::to_string(n) + " vertices");
    const auto [start, next] = vertex_neighbours(triangles, n);
    // Dijkstra from every traced vertex at once; a gap vertex keeps its nearest source.
    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> source(n, none);
    std::vector<double> distance(n, std::numeric_limits<double>::infinity());
    using Item = std::tuple<double, std::uint32_t, std::uint32_t>;  // (distance, vertex, source)
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (std::uint32_t v = 0; v < n; ++v)
        if (p.width[v] > 0.0f) source[v] = v, distance[v] = 0.0, queue.emplace(0.0, v, v);
    while (!queue.empty()) {
        const auto [d, v, s] = queue.top();
        queue.pop();
        if (d > distance[v] || source[v] != s) continue;
        for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
            const std::uint32_t w = next[i];
            if (p.width[w] > 0.0f) continue;  // traced: keeps its own
            const double dw = std::hypot(p.x[w] - p.x[s], p.y[w] - p.y[s]);
            if (dw > reach_wavelengths * p.width[s]) continue;
            if (dw < distance[w] || (dw == distance[w] && s < source[w])) {
                distance[w] = dw, source[w] = s;
                queue.emplace(dw, w, s);
            }
        }
    }
    std::size_t filled = 0;
    for (std::size_t v = 0; v < n; ++v) {
        const std::uint32_t s = source[v];
        if (s == none || s == v) continue;
        const double k = 2.0 * std::numbers::pi / p.width[s];
        p.phase[v] = p.phase[s] + k * (p.dir_x[s] * (p.x[v] - p.x[s]) + p.dir_y[s] * (p.y[v] - p.y[s]));
        p.dir_x[v] = p.dir_x[s], p.dir_y[v] = p.dir_y[s];
        for (auto* f : {&p.width, &p.scale, &p.mean_level, &p.rise, &p.breaking_length, &p.curl, &p.foam_yield,
                        &p.break_phase, &p.end_phase})
            (*f)[v] = (*f)[s];
        if (!p.life_start.empty()) p.life_start[v] = p.life_start[s];
        ++filled;
    }
    return filled;
}

void resolve_jeschke_lips(JeschkeMotionPlan& p, std::span<const std::uint32_t> triangles, std::span<const std::uint8_t> boundary,
                          double fraction) {
    const std::size_t n = p.vertex_count();
    if (n == 0) return;
    if (boundary.size() != n) throw InputError("resolve lips: boundary flags for " + std::to_string(boundary.size()) + " of " + std::to_string(n) + " vertices");
    if (!(fraction > 0.0)) throw InputError("resolve lips: fraction must be > 0");
    std::vector<double> sum(n, 0.0);
    std::vector<std::uint32_t> count(n, 0);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (std::size_t i = 0; i < 3; ++i) {
            const std::uint32_t a = triangles[t + i], b = triangles[t + (i + 1) % 3];
            if (a >= n || b >= n) throw InputError("resolve lips: triangle index out of range");
            const double e = std::hypot(p.x[a] - p.x[b], p.y[a] - p.y[b]);
            sum[a] += e, sum[b] += e, ++count[a], ++count[b];
        }
    // Distance to the boundary in wavelengths, by hops over the mesh (Dijkstra on edges).
    std::vector<double> reach(n, std::numeric_limits<double>::infinity());
    const auto [start, next] = vertex_neighbours(triangles, n);
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (std::uint32_t v = 0; v < n; ++v)
        if (boundary[v]) reach[v] = 0.0, queue.emplace(0.0, v);
    while (!queue.empty()) {
        const auto [d, v] = queue.top();
        queue.pop();
        if (d > reach[v]) continue;
        for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
            const std::uint32_t w = next[i];
            const double dw = d + std::hypot(p.x[w] - p.x[v], p.y[w] - p.y[v]);
            if (dw < reach[w]) reach[w] = dw, queue.emplace(dw, w);
        }
    }
    p.resolve.assign(n, 0.0f);
    p.wall_resolve.assign(n, 0.0f);
    for (std::size_t v = 0; v < n; ++v) {
        if (count[v] == 0 || !(p.width[v] > 0.0f) || !(p.scale[v] > 0.0f)) continue;
        const double spacing = sum[v] / count[v], h = p.scale[v] / 5.0;
        // Clear of the boundary by a few heights (and never more than a wavelength): the
        // surf zone on a beach lies within a wavelength of the shore.
        const double inside = detail::smoothstep(0.0, std::min(static_cast<double>(p.width[v]), kResolveReachHeights * h), reach[v]);
        const double fine = 1.0 - detail::smoothstep(fraction * h, 2.0 * fraction * h, spacing);
        const double wall = 1.0 - detail::smoothstep(2.0 * fraction * h, 4.0 * fraction * h, spacing);
        p.resolve[v] = p.curl_sections.empty() ? 0.0f : static_cast<float>(fine * inside);
        p.wall_resolve[v] = static_cast<float>(wall * inside);
    }
}

}  // namespace wave
