// Untangling a moved mesh: horizontal offsets scaled down where triangles would turn
// over in plan (libwave/motion.h).
#include "libwave/motion.h"

#include "core/format.h"
#include "core/smoothstep.h"

#include "libwave/errors.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace wave {
namespace {

constexpr std::size_t kMaxScaledPasses = 8;  // then a triangle still too small takes s = 0
constexpr double kShoreStretch = 1.15;  // the ramp's bound on a shore triangle's stretch (1 + λ_max)
constexpr double kStretch = 2.5;       // … and on any other's (UntangleOptions::ramp_slope)
constexpr double kLipAreaRatio = 0.02;  // a lip's triangle that may not turn over keeps this share of its area in plan
constexpr std::size_t kAngleRounds = 3;  // the ramp's rounds after the first for triangles its spread thinned

// Twice the signed area of (a, b, c) in plan.
double area2(double ax, double ay, double bx, double by, double cx, double cy) noexcept {
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

// The largest s ∈ [0, 1] with A(s) ≥ target, where A(s) = a0 + b·s + c·s² is twice the
// area with every offset scaled by s, A(0) = a0 > target and A(1) < target: the first
// root of A(s) − target above 0, a little inside it (float positions).
double restoring_factor(double a0, double b, double c, double target) noexcept {
    const double g0 = a0 - target;  // > 0
    double root = 1.0;
    if (std::abs(c) < 1e-12 * std::max(std::abs(a0), std::abs(b))) {
        if (b < 0.0) root = g0 / -b;
    } else {
        const double disc = b * b - 4.0 * c * g0;
        if (disc >= 0.0) {
            // Roots (−b ± √disc) / 2c by the stable formula; the smallest positive one.
            const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
            const double r1 = q / c, r2 = q != 0.0 ? g0 / q : 1.0;
            root = 1.0;
            for (double r : {r1, r2})
                if (r > 0.0 && r < root) root = r;
        }
    }
    return std::clamp(0.98 * root, 0.0, 1.0);
}

// Triangle t with its vertices' horizontal offsets (factor · d) scaled by s: twice its
// area in plan is A(s) = a0 + b·s + c·s², a0 its rest area; a1 = A(1).
struct Squeeze {
    double b = 0.0, c = 0.0, a1 = 0.0;
};
Squeeze squeeze(const UntanglePlan& plan, std::size_t t, const std::vector<double>& factor, const std::vector<double>& dx,
                const std::vector<double>& dy) noexcept {
    const std::uint32_t i = plan.triangles[3 * t], j = plan.triangles[3 * t + 1], k = plan.triangles[3 * t + 2];
    const double rx[3] = {plan.rest_x[i], plan.rest_x[j], plan.rest_x[k]};
    const double ry[3] = {plan.rest_y[i], plan.rest_y[j], plan.rest_y[k]};
    const double ex[3] = {factor[i] * dx[i], factor[j] * dx[j], factor[k] * dx[k]};
    const double ey[3] = {factor[i] * dy[i], factor[j] * dy[j], factor[k] * dy[k]};
    // u = rest edges, w = offset edges.
    const double ux1 = rx[1] - rx[0], uy1 = ry[1] - ry[0], ux2 = rx[2] - rx[0], uy2 = ry[2] - ry[0];
    const double wx1 = ex[1] - ex[0], wy1 = ey[1] - ey[0], wx2 = ex[2] - ex[0], wy2 = ey[2] - ey[0];
    Squeeze q;
    q.b = ux1 * wy2 + wx1 * uy2 - uy1 * wx2 - wy1 * ux2;
    q.c = wx1 * wy2 - wy1 * wx2;
    q.a1 = area2(rx[0] + ex[0], ry[0] + ey[0], rx[1] + ex[1], ry[1] + ey[1], rx[2] + ex[2], ry[2] + ey[2]);
    return q;
}

// The factor s ≤ 1 on triangle t's offsets (factor · d) that keeps at least `ratio` of
// its rest area, from a bound that is continuous in the offsets: with J the offsets'
// gradient over the triangle and λ the smallest eigenvalue of its symmetric part (the
// strongest compression), the moved triangle's linear map I + sJ stretches no unit
// vector by less than 1 + sλ, so its area ratio is at least (1 + sλ)² and it keeps its
// orientation while 1 + sλ > 0. Rotation never damps; stretching does beyond
// `stretch` (kStretch; kShoreStretch in the shore's band): the largest eigenvalue λ'
// damps from 1 + λ' = stretch on, s = (stretch − 1)/λ'. A compression damps from
// λ = −(1 − √ratio) on. (The quadratic's own first root is sharper but jumps where its
// dip below the target appears or vanishes.)
double strain_factor(const UntanglePlan& plan, std::size_t t, const std::vector<double>& factor,
                     const std::vector<double>& dx, const std::vector<double>& dy, double ratio, double stretch) noexcept {
    const std::uint32_t i = plan.triangles[3 * t], j = plan.triangles[3 * t + 1], k = plan.triangles[3 * t + 2];
    const double ux1 = plan.rest_x[j] - plan.rest_x[i], uy1 = plan.rest_y[j] - plan.rest_y[i];
    const double ux2 = plan.rest_x[k] - plan.rest_x[i], uy2 = plan.rest_y[k] - plan.rest_y[i];
    const double wx1 = factor[j] * dx[j] - factor[i] * dx[i], wy1 = factor[j] * dy[j] - factor[i] * dy[i];
    const double wx2 = factor[k] * dx[k] - factor[i] * dx[i], wy2 = factor[k] * dy[k] - factor[i] * dy[i];
    const double det = plan.rest_area[t];  // ux1 uy2 − ux2 uy1
    // J = W U⁻¹, U = [u1 u2], W = [w1 w2] (columns).
    const double j11 = (wx1 * uy2 - wx2 * uy1) / det, j12 = (wx2 * ux1 - wx1 * ux2) / det;
    const double j21 = (wy1 * uy2 - wy2 * uy1) / det, j22 = (wy2 * ux1 - wy1 * ux2) / det;
    const double s12 = 0.5 * (j12 + j21);
    const double mean = 0.5 * (j11 + j22), spread = std::hypot(0.5 * (j11 - j22), s12);
    const double lowest = mean - spread, highest = mean + spread;
    const double allowed = 1.0 - std::sqrt(ratio);
    const double squeeze = lowest < -allowed ? allowed / -lowest : 1.0;
    return highest > stretch - 1.0 ? std::min(squeeze, (stretch - 1.0) / highest) : squeeze;
}

// sin² of triangle t's smallest angle in 3D with its vertices' horizontal offsets
// (factor · d) scaled by s and their heights z: the smallest angle is opposite the
// shortest edge and below 60°, where sin rises, so sin² = |a × b|² / (|a|² |b|²) with
// a, b the two longer edges.
double thinness(const UntanglePlan& plan, std::size_t t, const std::vector<double>& factor, const std::vector<double>& dx,
                const std::vector<double>& dy, std::span<const float> positions, double s) noexcept {
    const std::uint32_t* v = &plan.triangles[3 * t];
    double p[3][3];
    for (int c = 0; c < 3; ++c) {
        p[c][0] = plan.rest_x[v[c]] + s * factor[v[c]] * dx[v[c]];
        p[c][1] = plan.rest_y[v[c]] + s * factor[v[c]] * dy[v[c]];
        p[c][2] = positions[3 * v[c] + 2];
    }
    double e[3][3], len2[3];
    for (int c = 0; c < 3; ++c) {
        for (int a = 0; a < 3; ++a) e[c][a] = p[(c + 2) % 3][a] - p[(c + 1) % 3][a];  // the edge opposite corner c
        len2[c] = e[c][0] * e[c][0] + e[c][1] * e[c][1] + e[c][2] * e[c][2];
    }
    const double cx = e[0][1] * e[1][2] - e[0][2] * e[1][1], cy = e[0][2] * e[1][0] - e[0][0] * e[1][2];
    const double cz = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    const double shortest = std::min({len2[0], len2[1], len2[2]});
    const double longer = len2[0] * len2[1] * len2[2] / std::max(shortest, 1e-300);
    return longer > 0.0 ? (cx * cx + cy * cy + cz * cz) / longer : 0.0;
}

// The factor on triangle t's offsets that keeps its smallest angle at `min_sin2`
// (UntangleOptions::min_angle_degrees): 1 when the moved triangle keeps it or when
// even at rest offsets (s = 0) its heights make it thinner; else the crossing by
// bisection, a little inside it.
double angle_factor(const UntanglePlan& plan, std::size_t t, const std::vector<double>& factor, const std::vector<double>& dx,
                    const std::vector<double>& dy, std::span<const float> positions, double min_sin2) noexcept {
    if (thinness(plan, t, factor, dx, dy, positions, 1.0) >= min_sin2) return 1.0;
    if (thinness(plan, t, factor, dx, dy, positions, 0.0) <= min_sin2) return 1.0;
    double low = 0.0, high = 1.0;  // thin enough at low, too thin at high
    for (int i = 0; i < 24; ++i) {
        const double mid = 0.5 * (low + high);
        (thinness(plan, t, factor, dx, dy, positions, mid) >= min_sin2 ? low : high) = mid;
    }
    return 0.98 * low;
}

// The ramp's spread (UntangleOptions::ramp_slope): the seeds w.ramp rise outwards by a
// min-plus (Dijkstra) sweep over the edges, by ramp_slope × edge / longer offset per
// edge; then each vertex's factor takes them, less what its foam frees (foam_weight,
// 0 … 1). Sequential, in (factor, vertex) order: the same bits on any thread count.
template <class FoamWeight>
void spread_ramp(const UntanglePlan& plan, const FoamWeight& foam_weight, UntangleWorkspace& w) {
    const std::size_t n = plan.vertex_count();
    std::vector<double>& g = w.ramp;
    auto& heap = w.queue;
    heap.clear();
    for (std::uint32_t v = 0; v < n; ++v)
        if (g[v] < 1.0) heap.emplace_back(g[v], v);
    if (heap.empty()) return;
    const auto later = std::greater<>();
    std::make_heap(heap.begin(), heap.end(), later);
    const auto offset = [&](std::uint32_t v) { return w.factor[v] * std::hypot(w.dx[v], w.dy[v]); };
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), later);
        const auto [gv, v] = heap.back();
        heap.pop_back();
        if (gv > g[v]) continue;  // a stale entry
        for (std::uint32_t f = plan.face_offsets[v]; f < plan.face_offsets[v + 1]; ++f)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t u = plan.triangles[3 * plan.faces[f] + c];
                if (u == v) continue;
                const double longer = std::max(offset(u), offset(v));
                if (!(longer > 0.0)) continue;
                const double edge = std::hypot(plan.rest_x[u] - plan.rest_x[v], plan.rest_y[u] - plan.rest_y[v]);
                const double gu = gv + plan.options.ramp_slope * edge / longer;
                if (gu < g[u]) {
                    g[u] = gu;
                    heap.emplace_back(gu, u);
                    std::push_heap(heap.begin(), heap.end(), later);
                }
            }
    }
    // A breaking crest's vertices shed the ramp as their foam grows from lip_foam to 1
    // (smoothly: the foam is continuous in time, so is the factor).
    for (std::size_t v = 0; v < n; ++v) {
        const double free = foam_weight(v);
        w.factor[v] *= g[v] + (1.0 - g[v]) * free;
        w.lowered[v] = g[v] < 1.0 ? 3 : w.lowered[v] & 2;
    }
}

// Whether triangle t has a vertex whose `lowered` flags hold `bit`.
bool touches(const UntanglePlan& plan, const std::vector<std::uint8_t>& lowered, std::size_t t, std::uint8_t bit) noexcept {
    const std::uint32_t* v = &plan.triangles[3 * t];
    return ((lowered[v[0]] | lowered[v[1]] | lowered[v[2]]) & bit) != 0;
}

// The ramp: each compressed or stretched triangle's strain_factor (at ramp_area_ratio;
// in the shore's band at shore_band_area_ratio and kShoreStretch) and each thinned
// one's angle_factor seed its vertices, and spread_ramp spreads them. The spread's own
// gradient shears: between neighbours whose factors differ by ramp_slope × edge /
// offset, a triangle of 35° at rest went to 12.5° on the coast. So up to
// kAngleRounds more rounds seed the triangles still thinner than
// min_angle_degrees, on the ramped factors, and spread again (only triangles round
// the vertices the last round lowered can have changed). Every step is continuous in
// the offsets (and the foam).
template <class FoamWeight>
void ramp_factors(const UntanglePlan& plan, const FoamWeight& foam_weight, std::span<const float> positions, double min_sin2,
                  UntangleWorkspace& w) {
    const UntangleOptions& o = plan.options;
    const std::size_t n = plan.vertex_count(), m = plan.rest_area.size();
    std::vector<double>& g = w.ramp;
    std::vector<double>& seed = w.s;  // per triangle (the passes set it afresh)
    seed.resize(m);
    for (std::size_t round = 0; round <= kAngleRounds; ++round) {
        g.assign(n, 1.0);
        // Each triangle's seed in parallel (each a function of the triangle alone), then
        // taken by its vertices in order: the same factors on any thread count.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t t = range.begin(); t != range.end(); ++t) {
                seed[t] = 1.0;
                if (!(plan.rest_area[t] > 0.0) || (round > 0 && !touches(plan, w.lowered, t, 1))) continue;
                const std::uint32_t* v = &plan.triangles[3 * t];
                double keep = min_sin2 > 0.0 ? angle_factor(plan, t, w.factor, w.dx, w.dy, positions, min_sin2) : 1.0;
                if (round == 0) {
                    // In the shore's band a stretch damps sooner and a squeeze keeps more of
                    // the area: the held shore cannot follow its neighbours.
                    const bool by_shore = !plan.shore_ring.empty() &&
                                          std::min({plan.shore_ring[v[0]], plan.shore_ring[v[1]], plan.shore_ring[v[2]]}) < o.shore_band_rings;
                    keep = std::min(keep, strain_factor(plan, t, w.factor, w.dx, w.dy,
                                                        by_shore ? o.shore_band_area_ratio : o.ramp_area_ratio,
                                                        by_shore ? kShoreStretch : kStretch));
                }
                seed[t] = keep;
            }
        });
        bool seeded = false;
        for (std::size_t t = 0; t < m; ++t) {
            const double keep = seed[t];
            if (keep >= 1.0) continue;
            seeded = true;
            const std::uint32_t* v = &plan.triangles[3 * t];
            for (int c = 0; c < 3; ++c) g[v[c]] = std::min(g[v[c]], keep);
        }
        if (!seeded) return;
        spread_ramp(plan, foam_weight, w);
    }
}

// The border: the rest positions' bounding rectangle, each side moved out to the
// domain's (`domain`, when given) where it lies inside it; a side moved out has no
// vertex on it, so its boundary edges are shore.
void set_border(UntanglePlan& p, const std::array<double, 4>& domain) {
    const auto [x0, x1] = std::minmax_element(p.rest_x.begin(), p.rest_x.end());
    const auto [y0, y1] = std::minmax_element(p.rest_y.begin(), p.rest_y.end());
    p.x_min = *x0, p.y_min = *y0, p.x_max = *x1, p.y_max = *y1;
    const std::size_t finite = static_cast<std::size_t>(std::count_if(domain.begin(), domain.end(), [](double v) { return std::isfinite(v); }));
    if (finite == 0) return;
    const auto text = [&] {
        return "{" + detail::format_number(domain[0]) + ", " + detail::format_number(domain[1]) + ", " +
               detail::format_number(domain[2]) + ", " + detail::format_number(domain[3]) + "}";
    };
    if (finite != 4 || !(domain[0] <= p.x_min && domain[1] <= p.y_min && domain[2] >= p.x_max && domain[3] >= p.y_max))
        throw InputError("untangle: border_rectangle " + text() + " is not four finite numbers holding every rest position");
    const double tol = 1e-9 * std::max({1.0, domain[2] - domain[0], domain[3] - domain[1]});
    if (p.x_min > domain[0] + tol) p.x_min = domain[0];
    if (p.y_min > domain[1] + tol) p.y_min = domain[1];
    if (p.x_max < domain[2] - tol) p.x_max = domain[2];
    if (p.y_max < domain[3] - tol) p.y_max = domain[3];
}

// Flags (4) the vertices of the rest mesh's boundary edges that do not run along a
// side of its border rectangle: the shore.
void mark_shore(UntanglePlan& p) {
    const std::size_t m = p.triangles.size() / 3;
    const auto on_side = [&](std::uint32_t a, std::uint32_t b) {
        const auto same = [](double u, double w, double low, double high) { return u == w && (u == low || u == high); };
        return same(p.rest_x[a], p.rest_x[b], p.x_min, p.x_max) || same(p.rest_y[a], p.rest_y[b], p.y_min, p.y_max);
    };
    // An edge (v, w) on the boundary has one triangle: w is v's neighbour in only one
    // of the triangles round v.
    std::vector<std::uint32_t> around;
    for (std::uint32_t v = 0; v < p.vertex_count(); ++v) {
        around.clear();
        for (std::uint32_t f = p.face_offsets[v]; f < p.face_offsets[v + 1]; ++f)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t w = p.triangles[3 * p.faces[f] + c];
                if (w != v) around.push_back(w);
            }
        std::sort(around.begin(), around.end());
        for (std::size_t k = 0; k < around.size();) {
            std::size_t e = k + 1;
            while (e < around.size() && around[e] == around[k]) ++e;
            if (e - k == 1 && !on_side(v, around[k])) p.pinned[v] |= 4;
            k = e;
        }
    }
    // The band: rings of triangles out from the shore.
    p.shore_ring.assign(p.vertex_count(), std::numeric_limits<std::uint8_t>::max());
    for (std::uint32_t v = 0; v < p.vertex_count(); ++v)
        if (p.pinned[v] & 4) p.shore_ring[v] = 0;
    for (std::uint8_t ring = 1; ring <= p.options.shore_band_rings; ++ring)
        for (std::size_t t = 0; t < m; ++t) {
            const std::uint32_t* v = &p.triangles[3 * t];
            if (std::min({p.shore_ring[v[0]], p.shore_ring[v[1]], p.shore_ring[v[2]]}) != ring - 1) continue;
            for (int c = 0; c < 3; ++c) p.shore_ring[v[c]] = std::min(p.shore_ring[v[c]], ring);
        }
}

}  // namespace

double lip_foam_rise(double phase_to_crest) noexcept {
    // A fifth of a period: on the default bay a tenth let vertices freed for their lip
    // move at 15 m/s.
    constexpr double rise = 0.4 * std::numbers::pi;
    return detail::smoothstep(0.0, 1.0, 1.0 - phase_to_crest / rise);
}

UntanglePlan plan_untangle(std::span<const double> rest_x, std::span<const double> rest_y,
                           std::span<const std::uint32_t> triangles, const UntangleOptions& options) {
    const std::size_t n = rest_x.size();
    if (rest_y.size() != n)
        throw InputError("untangle: " + std::to_string(rest_x.size()) + " rest x but " + std::to_string(rest_y.size()) + " rest y");
    if (triangles.size() % 3 != 0) throw InputError("untangle: " + std::to_string(triangles.size()) + " indices is not whole triangles");
    for (std::uint32_t v : triangles)
        if (v >= n) throw InputError("untangle: triangle index " + std::to_string(v) + " out of " + std::to_string(n) + " vertices");
    if (!(options.min_area_ratio > 0.0 && options.min_area_ratio < 1.0))
        throw InputError("untangle: min_area_ratio " + std::to_string(options.min_area_ratio) + " is not in (0, 1)");
    if (!(options.ramp_area_ratio > options.min_area_ratio && options.ramp_area_ratio < 1.0))
        throw InputError("untangle: ramp_area_ratio " + std::to_string(options.ramp_area_ratio) + " is not in (min_area_ratio " +
                         std::to_string(options.min_area_ratio) + ", 1)");
    if (!(options.shore_band_area_ratio >= options.ramp_area_ratio && options.shore_band_area_ratio < 1.0))
        throw InputError("untangle: shore_band_area_ratio " + std::to_string(options.shore_band_area_ratio) +
                         " is not in [ramp_area_ratio " + std::to_string(options.ramp_area_ratio) + ", 1)");
    if (!(options.ramp_slope >= 0.0 && std::isfinite(options.ramp_slope)))
        throw InputError("untangle: ramp_slope " + std::to_string(options.ramp_slope) + " is not a finite number >= 0");
    if (!(options.min_angle_degrees >= 0.0 && options.min_angle_degrees < 60.0))
        throw InputError("untangle: min_angle_degrees " + std::to_string(options.min_angle_degrees) + " is not in [0, 60)");
    if (options.shore_band_rings > 254)
        throw InputError("untangle: shore_band_rings " + std::to_string(options.shore_band_rings) + " is more than 254");
    UntanglePlan p;
    p.rest_x.assign(rest_x.begin(), rest_x.end());
    p.rest_y.assign(rest_y.begin(), rest_y.end());
    p.triangles.assign(triangles.begin(), triangles.end());
    p.options = options;
    const std::size_t m = triangles.size() / 3;
    p.rest_area.resize(m);
    for (std::size_t t = 0; t < m; ++t) {
        const std::uint32_t a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
        p.rest_area[t] = area2(rest_x[a], rest_y[a], rest_x[b], rest_y[b], rest_x[c], rest_y[c]);
    }
    if (n > 0) set_border(p, options.border_rectangle);  // refuses a bad border_rectangle whatever the flags
    if ((options.pin_border || options.hold_shore) && n > 0) {
        p.pinned.assign(n, 0);
        if (options.pin_border)
            for (std::size_t v = 0; v < n; ++v)
                p.pinned[v] = static_cast<std::uint8_t>((rest_x[v] == p.x_min || rest_x[v] == p.x_max ? 1 : 0) |
                                                        (rest_y[v] == p.y_min || rest_y[v] == p.y_max ? 2 : 0));
    }
    VertexFaces vf = vertex_faces(n, triangles);
    p.face_offsets = std::move(vf.offsets);
    p.faces = std::move(vf.faces);
    if (options.hold_shore && n > 0) mark_shore(p);
    return p;
}

UntangleReport untangle_motion(const UntanglePlan& plan, std::span<const float> foam, std::span<float> positions,
                               UntangleWorkspace* workspace, const OverturnTest& may_overturn) {
    const std::size_t n = plan.vertex_count(), m = plan.rest_area.size();
    if (positions.size() != 3 * n)
        throw InputError("untangle: " + std::to_string(positions.size()) + " position floats for " + std::to_string(n) + " vertices");
    if (!foam.empty() && foam.size() != n)
        throw InputError("untangle: " + std::to_string(foam.size()) + " foam values for " + std::to_string(n) + " vertices");
    const UntangleOptions& o = plan.options;
    // The horizontal offsets as moved (double), the factor on each, each triangle's s.
    UntangleWorkspace local;
    UntangleWorkspace& w = workspace ? *workspace : local;
    w.dx.resize(n);
    w.dy.resize(n);
    w.factor.assign(n, 1.0);
    w.s.assign(m, 1.0);
    std::vector<double>& dx = w.dx;
    std::vector<double>& dy = w.dy;
    std::vector<double>& factor = w.factor;
    std::vector<double>& s = w.s;
    for (std::size_t v = 0; v < n; ++v) {
        dx[v] = static_cast<double>(positions[3 * v]) - plan.rest_x[v];
        dy[v] = static_cast<double>(positions[3 * v + 1]) - plan.rest_y[v];
        if (plan.pinned.empty() || plan.pinned[v] == 0) continue;
        if (plan.pinned[v] & 5) dx[v] = 0.0;
        if (plan.pinned[v] & 6) dy[v] = 0.0;
    }
    const bool lips = o.lips_overturn && !foam.empty();  // foamy crests may turn over
    const auto lip = [&](std::uint32_t v) { return lips && foam[v] >= o.lip_foam; };
    const auto shore = [&](std::uint32_t v) { return !plan.pinned.empty() && (plan.pinned[v] & 4) != 0; };
    // Pinned: every vertex but a lip's stays inside the rest rectangle by its factor
    // (a lip is clamped at the end: its triangles are all lips).
    if (o.pin_border && !plan.pinned.empty())
        for (std::size_t v = 0; v < n; ++v) {
            if (lip(static_cast<std::uint32_t>(v))) continue;
            const auto room = [](double offset, double to_low, double to_high) {
                return offset > 0.0 ? to_high / offset : offset < 0.0 ? to_low / offset : 1.0;
            };
            factor[v] = std::clamp(std::min({1.0, room(dx[v], plan.x_min - plan.rest_x[v], plan.x_max - plan.rest_x[v]),
                                              room(dy[v], plan.y_min - plan.rest_y[v], plan.y_max - plan.rest_y[v])}),
                                   0.0, 1.0);
        }
    const auto foam_weight = [&](std::size_t v) {
        if (!lips || (!plan.shore_ring.empty() && plan.shore_ring[v] <= o.shore_band_rings)) return 0.0;  // none by the shore
        return detail::smoothstep(o.lip_foam, 1.0, static_cast<double>(foam[v]));
    };
    // One ramp: a second on the first's factors found compressions that the first's
    // uneven factors made, and on the default bay its vertices jumped again (10 m/s).
    // The ramp looks at every triangle's angle first; the passes then only at those whose
    // vertices it lowered (2), and after a pass at those whose vertices that pass lowered.
    const double min_sin = std::sin(o.min_angle_degrees * std::numbers::pi / 180.0), min_sin2 = min_sin * min_sin;
    w.lowered.assign(n, o.ramp_slope > 0.0 ? 0 : 2);
    if (o.ramp_slope > 0.0) ramp_factors(plan, foam_weight, positions, min_sin2, w);
    std::uint8_t look = 2;
    UntangleReport report;
    for (std::size_t pass = 0;; ++pass) {
        report.passes = pass + 1;
        std::atomic<bool> tangled{false};
        const bool last_resort = pass >= kMaxScaledPasses;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
            bool any = false;
            for (std::size_t t = range.begin(); t != range.end(); ++t) {
                s[t] = 1.0;
                const double a0 = plan.rest_area[t];
                if (!(a0 > 0.0)) continue;
                const std::uint32_t i = plan.triangles[3 * t], j = plan.triangles[3 * t + 1], k = plan.triangles[3 * t + 2];
                if ((lip(i) || lip(j) || lip(k)) && !shore(i) && !shore(j) && !shore(k)) {
                    // A lip's triangle may stand vertical; it turns over only where the
                    // motion draws it so (may_overturn), else it keeps its orientation.
                    if (!may_overturn) continue;
                    const Squeeze q = squeeze(plan, t, factor, dx, dy);
                    const double target = kLipAreaRatio * a0;
                    if (q.a1 >= target || may_overturn(i, j, k)) continue;
                    any = true;
                    s[t] = last_resort ? 0.0 : restoring_factor(a0, q.b, q.c, target);
                    continue;
                }
                const Squeeze q = squeeze(plan, t, factor, dx, dy);
                const double target = o.min_area_ratio * a0;
                const double keep = q.a1 >= target ? 1.0 : restoring_factor(a0, q.b, q.c, target);
                const double thin =
                    min_sin2 > 0.0 && touches(plan, w.lowered, t, look) ? angle_factor(plan, t, factor, dx, dy, positions, min_sin2) : 1.0;
                if (keep >= 1.0 && thin >= 1.0) continue;
                any = true;
                s[t] = last_resort ? 0.0 : std::min(keep, thin);
            }
            if (any) tangled.store(true, std::memory_order_relaxed);
        });
        if (!tangled.load()) break;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t v = range.begin(); v != range.end(); ++v) {
                double lowest = 1.0;
                for (std::uint32_t q = plan.face_offsets[v]; q < plan.face_offsets[v + 1]; ++q) lowest = std::min(lowest, s[plan.faces[q]]);
                factor[v] *= lowest;
                w.lowered[v] = lowest < 1.0 ? 1 : 0;
            }
        });
        look = 1;
        if (report.passes > kMaxScaledPasses + n) break;  // cannot happen: each last-resort pass zeroes a vertex
    }
    const bool clip = o.pin_border && !plan.pinned.empty();
    for (std::size_t v = 0; v < n; ++v) {
        const bool pinned = !plan.pinned.empty() && plan.pinned[v] != 0;
        double x = plan.rest_x[v] + factor[v] * dx[v], y = plan.rest_y[v] + factor[v] * dy[v];
        if (clip) {  // a lip over a side stops at it
            x = std::clamp(x, plan.x_min, plan.x_max);
            y = std::clamp(y, plan.y_min, plan.y_max);
        }
        if (factor[v] < 1.0 && (dx[v] != 0.0 || dy[v] != 0.0)) ++report.damped_vertices;
        if (factor[v] == 1.0 && !pinned && x == plan.rest_x[v] + dx[v] && y == plan.rest_y[v] + dy[v]) continue;
        positions[3 * v] = static_cast<float>(x);
        positions[3 * v + 1] = static_cast<float>(y);
    }
    return report;
}

}  // namespace wave
