// Exact ray–isobath intersection: an AABB tree over the contour segments finds the
// candidates (exact predicates); each candidate is intersected with the ray in the
// exact-constructions kernel so that vertices, tangencies and collinear overlaps give
// the true nearest crossing (Ts'o–Barsky §3.2.1: "the nearest intersection").
#include "libwave/isobath.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <vector>

namespace wave {
namespace {

using Fast = CGAL::Exact_predicates_inexact_constructions_kernel;
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using SegmentIterator = std::vector<Fast::Segment_3>::const_iterator;
// CGAL 5.5 has no 2D AABB tree: segments live in the z = 0 plane of a 3D tree.
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Fast, CGAL::AABB_segment_primitive<Fast, SegmentIterator>>>;

// Collects the primitives of every tree leaf whose box the query meets. The tree's own
// primitive test would intersect a Ray_3 with a Segment_3 in the same plane z = 0 —
// a degenerate configuration on which the filtered kernel always falls back to exact
// arithmetic; the 2D tests below are cheap and exact instead.
template <class Query>
struct BoxHits {
    std::vector<std::size_t>& out;
    SegmentIterator first;
    bool go_further() const { return true; }
    template <class Primitive>
    void intersection(const Query&, const Primitive& p) {
        out.push_back(static_cast<std::size_t>(p.id() - first));
    }
    template <class Node>
    bool do_intersect(const Query& q, const Node& node) const {
        return CGAL::do_intersect(q, node.bbox());
    }
};

}  // namespace

struct IsobathIndex::Impl {
    std::vector<Fast::Segment_3> segments;
    std::vector<std::size_t> contour_of;  // segment -> polyline
    std::vector<double> depth;            // per polyline
    Tree tree;
};

IsobathIndex::IsobathIndex(const DepthContours& c) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.depth = c.depth;
    for (std::size_t p = 0; p < c.size(); ++p) {
        const std::size_t begin = c.offsets[p], end = c.offsets[p + 1];
        const auto add = [&](std::size_t a, std::size_t b) {
            const Fast::Point_3 pa(c.xy[2 * a], c.xy[2 * a + 1], 0.0), pb(c.xy[2 * b], c.xy[2 * b + 1], 0.0);
            if (pa == pb) return;  // zero-length segments cross nothing
            m.segments.emplace_back(pa, pb);
            m.contour_of.push_back(p);
        };
        for (std::size_t k = begin; k + 1 < end; ++k) add(k, k + 1);
        if (c.closed[p] && end - begin > 2) add(end - 1, begin);
    }
    m.tree.insert(m.segments.cbegin(), m.segments.cend());
    m.tree.build();
}

IsobathIndex::~IsobathIndex() = default;
IsobathIndex::IsobathIndex(IsobathIndex&&) noexcept = default;
IsobathIndex& IsobathIndex::operator=(IsobathIndex&&) noexcept = default;

std::size_t IsobathIndex::segment_count() const noexcept { return impl_->segments.size(); }

std::size_t IsobathIndex::previous_segment(std::size_t s) const noexcept {
    const Impl& m = *impl_;
    if (s > 0 && m.contour_of[s - 1] == m.contour_of[s] && m.segments[s - 1].target() == m.segments[s].source()) return s - 1;
    // A ring's first segment follows its closing segment (the last one of the contour).
    std::size_t last = s;
    while (last + 1 < m.segments.size() && m.contour_of[last + 1] == m.contour_of[s]) ++last;
    if (m.segments[last].target() == m.segments[s].source()) return last;
    return s;
}

std::size_t IsobathIndex::next_segment(std::size_t s) const noexcept {
    const Impl& m = *impl_;
    if (s + 1 < m.segments.size() && m.contour_of[s + 1] == m.contour_of[s] && m.segments[s + 1].source() == m.segments[s].target()) return s + 1;
    std::size_t first = s;
    while (first > 0 && m.contour_of[first - 1] == m.contour_of[s]) --first;
    if (m.segments[first].source() == m.segments[s].target()) return first;
    return s;
}

std::optional<IsobathCrossing> IsobathIndex::first_crossing(const CrossingQuery& q) const {
    const Impl& m = *impl_;
    if (m.segments.empty()) return std::nullopt;
    const double len = std::hypot(q.dx, q.dy);
    if (!(len > 0.0)) return std::nullopt;

    std::vector<std::size_t> candidates;
    const Fast::Point_3 o(q.x, q.y, 0.0);
    if (std::isfinite(q.max_distance)) {
        const double s = q.max_distance / len;
        const Fast::Segment_3 query(o, Fast::Point_3(q.x + s * q.dx, q.y + s * q.dy, 0.0));
        BoxHits<Fast::Segment_3> hits{candidates, m.segments.cbegin()};
        m.tree.traversal(query, hits);
    } else {
        const Fast::Ray_3 query(o, Fast::Vector_3(q.dx, q.dy, 0.0));
        BoxHits<Fast::Ray_3> hits{candidates, m.segments.cbegin()};
        m.tree.traversal(query, hits);
    }

    const Fast::Ray_2 ray2(Fast::Point_2(q.x, q.y), Fast::Vector_2(q.dx, q.dy));
    // Exact ray parameter t of a point on the ray: (p − o)·d / |d|².
    const Exact::Point_2 origin(q.x, q.y);
    const Exact::Vector_2 dir(q.dx, q.dy);
    const Exact::Ray_2 ray(origin, dir);
    const auto param = [&](const Exact::Point_2& p) { return ((p - origin) * dir) / dir.squared_length(); };

    std::optional<IsobathCrossing> best;
    Exact::FT best_t = 0;
    for (const std::size_t seg_index : candidates) {
        const std::size_t contour = m.contour_of[seg_index];
        if (contour == q.skip_contour || seg_index == q.skip_segment) continue;
        const Fast::Segment_3& s3 = m.segments[seg_index];
        // Exact predicate first (filtered, cheap): most candidates are only box hits.
        const Fast::Segment_2 seg2(Fast::Point_2(s3.source().x(), s3.source().y()),
                                   Fast::Point_2(s3.target().x(), s3.target().y()));
        if (!CGAL::do_intersect(ray2, seg2)) continue;
        const Exact::Point_2 a(s3.source().x(), s3.source().y()), b(s3.target().x(), s3.target().y());
        const auto hit = CGAL::intersection(ray, Exact::Segment_2(a, b));
        if (!hit) continue;
        Exact::Point_2 p;
        bool collinear = false;
        if (const auto* pt = boost::get<Exact::Point_2>(&*hit)) {
            p = *pt;
        } else if (const auto* overlap = boost::get<Exact::Segment_2>(&*hit)) {
            // Along the contour: the crossing is where the overlap begins.
            collinear = true;
            p = param(overlap->source()) <= param(overlap->target()) ? overlap->source() : overlap->target();
        } else {
            continue;
        }
        const Exact::FT t = param(p);
        if (t <= 0) continue;  // the origin itself is not "ahead"
        if (best && t >= best_t) continue;
        const double distance = CGAL::to_double(t) * len;
        if (distance > q.max_distance || distance <= q.min_distance) continue;
        IsobathCrossing c;
        c.x = CGAL::to_double(p.x());
        c.y = CGAL::to_double(p.y());
        c.distance = distance;
        c.contour = contour;
        c.segment = seg_index;
        const double tx = s3.target().x() - s3.source().x(), ty = s3.target().y() - s3.source().y();
        const double tl = std::hypot(tx, ty);
        c.tangent_x = tx / tl;
        c.tangent_y = ty / tl;
        c.depth = m.depth[contour];
        c.at_vertex = (p == a || p == b);
        c.collinear = collinear;
        best = c;
        best_t = t;
    }
    return best;
}

}  // namespace wave
