// The sea skirt (surface.h): the outside of a surface's bounding rectangle, where its
// border is water, triangulated out to a far rectangle (CGAL constrained Delaunay,
// Mesh_2 refinement that never splits a constrained edge: the skirt shares the
// surface's border edges as they are; the cuts and the far rectangle are pre-split).
// docs/far-field.md.
#include "libwave/surface.h"

#include "libwave/errors.h"
#include "centroid_size_criteria.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace wave::skirt_mesh {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// A vertex knows the surface vertex it is (kNone: a vertex of the skirt's own).
struct VertexInfo {
    std::uint32_t index = kNone;
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K, CGAL::Constrained_Delaunay_triangulation_face_base_2<K>>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Point = CDT::Point;

}  // namespace wave::skirt_mesh

namespace wave {
namespace {

using skirt_mesh::CDT;
using skirt_mesh::kNone;
using skirt_mesh::Point;

// The rectangle and positions along its perimeter, counter-clockwise from (x0, y0):
// sides 0 bottom, 1 right, 2 top, 3 left.
struct Rectangle {
    double x0, y0, x1, y1;
    double w() const { return x1 - x0; }
    double h() const { return y1 - y0; }
    double perimeter() const { return 2.0 * (w() + h()); }
    double position(int side, double x, double y) const {
        switch (side) {
            case 0: return x - x0;
            case 1: return w() + (y - y0);
            case 2: return w() + h() + (x1 - x);
            default: return 2.0 * w() + h() + (y1 - y);
        }
    }
    static std::array<double, 2> normal(int side) {
        constexpr std::array<std::array<double, 2>, 4> n{{{0.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}}};
        return n[static_cast<std::size_t>(side)];
    }
};

// A surface edge on the rectangle, oriented along the perimeter (a before b).
struct BorderEdge {
    double from, to;  // perimeter positions (to > from; the left side's last edge ends at the perimeter)
    std::uint32_t a, b;
    int side;
};

double edge_length(const BorderEdge& e, std::span<const double> x, std::span<const double> y) {
    return std::hypot(x[e.b] - x[e.a], y[e.b] - y[e.a]);
}

// The surface's boundary edges (one triangle) with both ends on one side and water beyond.
std::vector<BorderEdge> border_edges(std::span<const double> x, std::span<const double> y,
                                     std::span<const std::uint32_t> triangles, const Rectangle& r, double tol,
                                     const ElevationGrid* seafloor) {
    // Every edge's key (lower vertex, higher) sorted: an edge of one triangle appears
    // once, and the keys come in the order a map of them iterates in (a sort, not a
    // map of a million nodes: a tenth of the breaking beach's plan).
    std::vector<std::uint64_t> keys(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const std::uint64_t a = triangles[i], b = triangles[i - i % 3 + (i % 3 + 1) % 3];
        keys[i] = std::min(a, b) << 32 | std::max(a, b);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> single;  // the edges of one triangle, in key order
    for (std::size_t i = 0; i < keys.size();) {
        std::size_t end = i + 1;
        while (end < keys.size() && keys[end] == keys[i]) ++end;
        if (end - i == 1) single.emplace_back(static_cast<std::uint32_t>(keys[i] >> 32), static_cast<std::uint32_t>(keys[i] & 0xFFFFFFFFu));
        i = end;
    }
    const auto on_side = [&](std::uint32_t v, int side) {
        switch (side) {
            case 0: return std::abs(y[v] - r.y0) <= tol;
            case 1: return std::abs(x[v] - r.x1) <= tol;
            case 2: return std::abs(y[v] - r.y1) <= tol;
            default: return std::abs(x[v] - r.x0) <= tol;
        }
    };
    // Land beyond an edge: the side there is a shore (checked a quarter of the edge out).
    const auto dry_beyond = [&](std::uint32_t a, std::uint32_t b, int side) {
        if (seafloor == nullptr) return false;
        const auto n = Rectangle::normal(side);
        const double out = 0.25 * std::hypot(x[b] - x[a], y[b] - y[a]);
        return !(depth_at(*seafloor, 0.5 * (x[a] + x[b]) + out * n[0], 0.5 * (y[a] + y[b]) + out * n[1]) > 0.0);
    };
    std::vector<BorderEdge> out;
    for (const auto& edge : single) {
        for (int side = 0; side < 4; ++side) {
            if (!on_side(edge.first, side) || !on_side(edge.second, side)) continue;
            double pa = r.position(side, x[edge.first], y[edge.first]), pb = r.position(side, x[edge.second], y[edge.second]);
            std::uint32_t a = edge.first, b = edge.second;
            if (pa > pb) std::swap(pa, pb), std::swap(a, b);
            if (pb - pa > tol && !dry_beyond(a, b, side)) out.push_back({pa, pb, a, b, side});
            break;
        }
    }
    std::sort(out.begin(), out.end(), [](const BorderEdge& p, const BorderEdge& q) { return p.from < q.from; });
    return out;
}

// Runs of consecutive border edges [first, last] (indices into the sorted edges); a run
// through (x0, y0) is one chain (its first index after its last); `loop` when the
// edges go all the way round.
struct Chain {
    std::size_t first, last;
};

std::vector<Chain> chains_of(const std::vector<BorderEdge>& e, bool& loop) {
    std::vector<Chain> out;
    for (std::size_t i = 0; i < e.size(); ++i) {
        if (!out.empty() && e[out.back().last].b == e[i].a) out.back().last = i;
        else out.push_back({i, i});
    }
    loop = false;
    if (out.size() > 1 && e[out.back().last].b == e[out.front().first].a) {
        out.front().first = out.back().first;  // wraps round the first corner
        out.pop_back();
    } else if (out.size() == 1 && e.back().b == e.front().a) {
        loop = true;
    }
    return out;
}

// Per border edge, the border's spacing at its two ends: the mean of the two edges that
// meet there (the edge's own length at a chain's end).
std::vector<std::array<double, 2>> end_spacings(const std::vector<BorderEdge>& e, std::span<const double> x,
                                                std::span<const double> y) {
    const std::size_t n = e.size();
    std::vector<std::array<double, 2>> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const BorderEdge &prev = e[(i + n - 1) % n], &next = e[(i + 1) % n];
        const double len = edge_length(e[i], x, y);
        out[i] = {prev.b == e[i].a ? 0.5 * (len + edge_length(prev, x, y)) : len,
                  next.a == e[i].b ? 0.5 * (len + edge_length(next, x, y)) : len};
    }
    return out;
}

// The nearest point on the rectangle of a point outside it, and what the skirt needs
// there: the border edge (or corner vertex) that holds it, and the border's spacing,
// linear along that edge between its ends' spacings (the border edges' own lengths
// step by 2 where the water mesh's refinement halved one, and the skirt's sizes beside
// them stepped too: a 2.7 m border edge met triangles sized for its 1.4 m neighbour).
struct BorderLookup {
    const Rectangle& r;
    const std::vector<BorderEdge>& edges;
    std::span<const double> x, y;
    std::vector<std::array<double, 2>> end_spacing = end_spacings(edges, x, y);

    struct Hit {
        double bx, by, d, nx, ny, spacing;  // spacing: the border's, at (bx, by)
        std::uint32_t a, b;
        float weight;  // of a
    };

    Hit at(double px, double py) const {
        Hit h{};
        h.bx = std::clamp(px, r.x0, r.x1);
        h.by = std::clamp(py, r.y0, r.y1);
        h.d = std::hypot(px - h.bx, py - h.by);
        h.nx = h.d > 0.0 ? (px - h.bx) / h.d : 0.0;
        h.ny = h.d > 0.0 ? (py - h.by) / h.d : 0.0;
        // Its perimeter position (a corner: both of its sides' positions are tried).
        const int side = h.by == r.y0 && h.bx > r.x0 ? 0 : h.bx == r.x1 ? 1 : h.by == r.y1 ? 2 : 3;
        double p = r.position(side, h.bx, h.by);
        if (side == 3 && p <= 0.0) p = r.perimeter();
        const BorderEdge* best = nullptr;
        double best_gap = std::numeric_limits<double>::infinity();
        const auto consider = [&](double q) {
            auto it = std::upper_bound(edges.begin(), edges.end(), q, [](double v, const BorderEdge& e) { return v < e.from; });
            for (auto c : {it, it == edges.begin() ? it : it - 1}) {
                if (c == edges.end()) continue;
                const double gap = q < c->from ? c->from - q : q > c->to ? q - c->to : 0.0;
                if (gap < best_gap) best_gap = gap, best = &*c, p = q;
            }
        };
        consider(p);
        if (p == r.perimeter()) consider(0.0);
        const double t = std::clamp((p - best->from) / (best->to - best->from), 0.0, 1.0);
        h.a = best->a;
        h.b = best->b;
        h.weight = static_cast<float>(1.0 - t);
        const std::array<double, 2>& s = end_spacing[static_cast<std::size_t>(best - edges.data())];
        h.spacing = (1.0 - t) * s[0] + t * s[1];
        if (h.weight >= 1.0f) h.b = h.a;
        if (h.weight <= 0.0f) h.a = h.b, h.weight = 1.0f;
        return h;
    }

    // Where the size is asked: the point and what the lookup found for it.
    static SkirtSite site(double px, double py, const Hit& h) { return {px, py, h.bx, h.by, h.d, h.spacing}; }
};

void check(std::span<const double> x, std::span<const double> y, std::span<const std::uint32_t> triangles,
           const SeaSkirtOptions& o) {
    if (x.size() != y.size()) throw InputError("sea skirt: x and y differ in length");
    if (triangles.size() % 3 != 0) throw InputError("sea skirt: triangles are not a multiple of 3 indices");
    for (std::uint32_t v : triangles)
        if (v >= x.size()) throw InputError("sea skirt: triangle index " + std::to_string(v) + " >= vertex count");
    if (!(o.distance > 0.0) || !std::isfinite(o.distance)) throw InputError("sea skirt: distance must be finite and > 0 m");
    if (!o.size) throw InputError("sea skirt: no size function");
    if (!(o.min_angle_deg > 0.0 && o.min_angle_deg <= 20.7)) throw InputError("sea skirt: min_angle_deg outside (0, 20.7]");
}

// Points from `from` to `to` (both included) along a straight line, spaced by the size
// at each step; the first step `first` when it is > 0.
std::vector<Point> split_line(Point from, Point to, const BorderLookup& lookup, const SkirtSize& size, double first = 0.0) {
    std::vector<Point> out{from};
    const double len = std::sqrt(CGAL::squared_distance(from, to));
    double s = 0.0;
    while (true) {
        const double mx = from.x() + (to.x() - from.x()) * s / len, my = from.y() + (to.y() - from.y()) * s / len;
        const BorderLookup::Hit h = lookup.at(mx, my);
        // Constraints are never split: a quarter of the size leaves room for the refinement.
        const double step = s == 0.0 && first > 0.0 ? first : 0.25 * size(BorderLookup::site(mx, my, h));
        const double left = len - s;
        if (left <= step) break;
        s += left < 2.0 * step ? 0.5 * left : step;
        out.emplace_back(from.x() + (to.x() - from.x()) * s / len, from.y() + (to.y() - from.y()) * s / len);
    }
    out.push_back(to);
    return out;
}

// Each cut's first step, by the chain end it leaves from: as long as the border edge
// beside it, so that the corner holds a right triangle of two equal legs (a quarter of
// the size made 14° there). Where two chains meet at one vertex (the strips'
// sawtoothed border), both cuts take the shorter step, so that they coincide.
std::map<std::uint32_t, double> cut_first_steps(const std::vector<BorderEdge>& edges, const std::vector<Chain>& chains,
                                                std::span<const double> x, std::span<const double> y) {
    std::map<std::uint32_t, double> out;
    const auto note = [&](std::uint32_t v, const BorderEdge& e) {
        const auto [it, fresh] = out.emplace(v, edge_length(e, x, y));
        if (!fresh) it->second = std::min(it->second, edge_length(e, x, y));
    };
    for (const Chain& c : chains) note(edges[c.first].a, edges[c.first]), note(edges[c.last].b, edges[c.last]);
    return out;
}

// Each border edge's equilateral apex outside it, where the border is graded gently.
// The refinement never splits the border's edges, so it cannot mend a thin triangle on
// one (its circumcentre would encroach on the edge): without these, the first ring had
// triangles of 17° on the coast, which the motion squeezed to 11°. Left to the
// refinement: a chain's end edges (their apex would crowd the cut that starts there),
// edges at a corner of the rectangle, and edges more than 2.5 × as long or as short as
// a neighbour (two apexes of edges of ratio 3 make 19°).
void insert_apexes(CDT& cdt, const std::vector<BorderEdge>& edges, const std::vector<Chain>& chains, bool loop,
                   std::span<const double> x, std::span<const double> y) {
    const auto length = [&](std::size_t i) { return edge_length(edges[i], x, y); };
    for (const Chain& c : chains)
        for (std::size_t i = c.first;; i = (i + 1) % edges.size()) {
            const std::size_t prev = (i + edges.size() - 1) % edges.size(), next = (i + 1) % edges.size();
            const bool ends = !loop && (i == c.first || i == c.last);
            const bool corner = edges[prev].side != edges[i].side || edges[next].side != edges[i].side;
            const double len = length(i);
            const auto even = [&](std::size_t j) { return length(j) <= 2.5 * len && len <= 2.5 * length(j); };
            if (!ends && !corner && even(prev) && even(next)) {
                const BorderEdge& e = edges[i];
                const auto n = Rectangle::normal(e.side);
                const double h = 0.5 * std::sqrt(3.0) * len;
                cdt.insert(Point(0.5 * (x[e.a] + x[e.b]) + h * n[0], 0.5 * (y[e.a] + y[e.b]) + h * n[1]));
            }
            if (i == c.last) break;
        }
}

// The skirt's vertex count before meshing: the wet outside area over the target triangle
// areas (√3/4 s² each, half as many vertices as triangles), integrated outwards from
// each border edge (a strip of its length) and each wet corner (a quarter disc) on
// geometric steps of the distance.
double estimate_vertices(const std::vector<BorderEdge>& edges, const std::vector<Chain>& chains, bool loop,
                         const BorderLookup& lookup, const SkirtSize& size, double reach, std::span<const double> x,
                         std::span<const double> y) {
    constexpr int kSteps = 96;
    const auto integrate = [&](double bx, double by, double nx, double ny, double edge, double width, bool corner) {
        double triangles = 0.0, d0 = 0.0;
        for (int i = 1; i <= kSteps; ++i) {
            const double d1 = reach * std::pow(1e-6, 1.0 - double(i) / kSteps);
            const double dm = 0.5 * (d0 + d1), s = size({bx + dm * nx, by + dm * ny, bx, by, dm, edge});
            const double area = corner ? 0.5 * std::numbers::pi * dm * (d1 - d0) : width * (d1 - d0);
            triangles += area / (std::sqrt(3.0) / 4.0 * s * s);
            d0 = d1;
        }
        return triangles;
    };
    double triangles = 0.0;
    for (const BorderEdge& e : edges) {
        const double len = edge_length(e, x, y);
        const auto n = Rectangle::normal(e.side);
        triangles += integrate(0.5 * (x[e.a] + x[e.b]), 0.5 * (y[e.a] + y[e.b]), n[0], n[1], len, len, false);
    }
    // Corners inside a chain (the chain turns there): the edge that arrives at a corner
    // and the next one lie on different sides.
    for (const Chain& c : chains)
        for (std::size_t i = c.first;; i = (i + 1) % edges.size()) {
            const std::size_t next = (i + 1) % edges.size();
            if ((i != c.last || loop) && edges[next].side != edges[i].side) {
                const std::uint32_t v = edges[i].b;
                const auto n = Rectangle::normal(edges[i].side), m = Rectangle::normal(edges[next].side);
                triangles += integrate(x[v], y[v], std::sqrt(0.5) * (n[0] + m[0]), std::sqrt(0.5) * (n[1] + m[1]),
                                       lookup.at(x[v], y[v]).spacing, 0.0, true);
            }
            if (i == c.last) break;
        }
    return 0.5 * triangles;
}

}  // namespace

SeaSkirt plan_sea_skirt(std::span<const double> x, std::span<const double> y, std::span<const std::uint32_t> triangles,
                        const SeaSkirtOptions& o) {
    check(x, y, triangles, o);
    SeaSkirt out;
    out.surface_vertices = x.size();
    out.reach = o.distance;
    if (x.empty() || triangles.empty()) return out;
    const auto [xlo, xhi] = std::minmax_element(x.begin(), x.end());
    const auto [ylo, yhi] = std::minmax_element(y.begin(), y.end());
    const Rectangle r{*xlo, *ylo, *xhi, *yhi};
    out.x0 = r.x0, out.y0 = r.y0, out.x1 = r.x1, out.y1 = r.y1;
    if (!(r.w() > 0.0 && r.h() > 0.0)) return out;
    const double tol = 1e-9 * std::max({1.0, r.w(), r.h()});
    const std::vector<BorderEdge> edges = border_edges(x, y, triangles, r, tol, o.seafloor);
    if (edges.empty()) return out;
    bool loop = false;
    const std::vector<Chain> chains = chains_of(edges, loop);
    const BorderLookup lookup{r, edges, x, y};
    const double R = o.distance;
    const double expected = estimate_vertices(edges, chains, loop, lookup, o.size, R, x, y);
    if (!(expected <= static_cast<double>(o.max_vertices)))
        throw LimitError("sea skirt: about " + std::to_string(static_cast<long long>(std::min(expected, 1e18))) +
                         " vertices for the target edge lengths, more than the limit of " + std::to_string(o.max_vertices));

    CDT cdt;
    // The rectangle as one closed constraint through every border vertex (each knows its
    // surface index) and corner.
    std::map<std::pair<double, double>, std::uint32_t> surface_index;
    std::vector<std::pair<double, Point>> ring;
    for (const BorderEdge& e : edges)
        for (std::uint32_t v : {e.a, e.b}) {
            if (!surface_index.emplace(std::pair{x[v], y[v]}, v).second) continue;
            ring.emplace_back(v == e.a ? e.from : e.to, Point(x[v], y[v]));
        }
    for (const auto& [p, q] : {std::pair{0.0, Point(r.x0, r.y0)}, {r.w(), Point(r.x1, r.y0)},
                               {r.w() + r.h(), Point(r.x1, r.y1)}, {2.0 * r.w() + r.h(), Point(r.x0, r.y1)}})
        if (!surface_index.contains({q.x(), q.y()})) ring.emplace_back(p, q);
    std::sort(ring.begin(), ring.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<CDT::Vertex_handle> inner;
    for (const auto& [_, q] : ring) {
        inner.push_back(cdt.insert(q));
        const auto it = surface_index.find({q.x(), q.y()});
        if (it != surface_index.end()) inner.back()->info().index = it->second;
    }
    for (std::size_t i = 0; i < inner.size(); ++i) cdt.insert_constraint(inner[i], inner[(i + 1) % inner.size()]);

    // Cuts where a chain ends, and the outer rectangle through their far ends.
    std::vector<std::pair<double, Point>> outer_points;
    const Rectangle far{r.x0 - R, r.y0 - R, r.x1 + R, r.y1 + R};
    for (const auto& [p, q] : {std::pair{0.0, Point(far.x0, far.y0)}, {far.w(), Point(far.x1, far.y0)},
                               {far.w() + far.h(), Point(far.x1, far.y1)}, {2.0 * far.w() + far.h(), Point(far.x0, far.y1)}})
        outer_points.emplace_back(p, q);
    if (!loop) {
        const std::map<std::uint32_t, double> first_step = cut_first_steps(edges, chains, x, y);
        for (const Chain& c : chains)
            for (const auto& [v, side] : {std::pair{edges[c.first].a, edges[c.first].side}, {edges[c.last].b, edges[c.last].side}}) {
                const auto n = Rectangle::normal(side);
                const Point from(x[v], y[v]), to(x[v] + R * n[0], y[v] + R * n[1]);
                const std::vector<Point> cut = split_line(from, to, lookup, o.size, first_step.at(v));
                cdt.insert_constraint(cut.begin(), cut.end());
                outer_points.emplace_back(far.position(side, to.x(), to.y()), to);
            }
    }
    std::sort(outer_points.begin(), outer_points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Point> outer;
    for (std::size_t i = 0; i < outer_points.size(); ++i) {
        const Point from = outer_points[i].second, to = outer_points[(i + 1) % outer_points.size()].second;
        if (from == to) continue;
        const std::vector<Point> piece = split_line(from, to, lookup, o.size);
        outer.insert(outer.end(), piece.begin(), piece.end() - 1);
    }
    outer.push_back(outer.front());
    cdt.insert_constraint(outer.begin(), outer.end());

    insert_apexes(cdt, edges, chains, loop, x, y);

    // Water beyond each chain: a seed just outside its first edge.
    std::vector<Point> seeds;
    for (const Chain& c : chains) {
        const BorderEdge& e = edges[c.first];
        const auto n = Rectangle::normal(e.side);
        const double len = edge_length(e, x, y);
        seeds.emplace_back(0.5 * (x[e.a] + x[e.b]) + 0.25 * len * n[0], 0.5 * (y[e.a] + y[e.b]) + 0.25 * len * n[1]);
    }
    const double sine = std::sin(o.min_angle_deg * std::numbers::pi / 180.0);
    const std::function<double(double, double)> size_at = [&](double px, double py) {
        const BorderLookup::Hit h = lookup.at(px, py);
        return o.size(BorderLookup::site(px, py, h));
    };
    using Criteria = detail::CentroidSizeCriteria<CDT>;
    CGAL::Delaunay_mesher_no_edge_refinement_2<CDT, Criteria> mesher(cdt, Criteria(sine * sine, size_at));
    mesher.set_seeds(seeds.begin(), seeds.end(), true);
    mesher.refine_mesh();
    if (cdt.number_of_vertices() > o.max_vertices)
        throw LimitError("sea skirt: " + std::to_string(cdt.number_of_vertices()) + " vertices, more than the limit of " +
                         std::to_string(o.max_vertices));

    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (!f->is_in_domain()) continue;
        for (int k = 0; k < 3; ++k) {
            const CDT::Vertex_handle v = f->vertex(k);
            if (v->info().index == kNone) {
                v->info().index = static_cast<std::uint32_t>(out.surface_vertices + out.x.size());
                const BorderLookup::Hit h = lookup.at(v->point().x(), v->point().y());
                out.x.push_back(v->point().x());
                out.y.push_back(v->point().y());
                out.anchor.insert(out.anchor.end(), {h.a, h.b});
                out.anchor_weight.push_back(h.weight);
                out.distance.push_back(h.d);
                out.normal_x.push_back(h.nx);
                out.normal_y.push_back(h.ny);
                out.size.push_back(o.size(BorderLookup::site(v->point().x(), v->point().y(), h)));
            }
            out.triangles.push_back(v->info().index);
        }
    }
    return out;
}

}  // namespace wave
