// The water mesh (surface.h): CGAL's constrained Delaunay triangulation of the domain
// rectangle and the shoreline, refined by Mesh_2 with a size field (docs/surface.md).
#include "libwave/surface.h"

#include "libwave/errors.h"
#include "libwave/isobath.h"
#include "centroid_size_criteria.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace wave {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// Vertices carry their output index, faces their region (kNone until the vote).
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<
    K, CGAL::Constrained_Delaunay_triangulation_face_base_2<
           K, CGAL::Constrained_triangulation_face_base_2<K, CGAL::Triangulation_face_base_with_info_2<std::uint32_t, K>>>>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact predicates: a shoreline polyline ending on the rectangle, or touching it,
// splits the border constraint at a constructed point.
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Point = CDT::Point;

double centroid_size(const EdgeSize& size, const ElevationGrid& grid, double x, double y) {
    if (depth_at(grid, x, y) <= 0.0) return std::numeric_limits<double>::infinity();  // land: shape only
    return size(x, y);
}

// The h = 0 polylines of the seafloor (none when it is all water or all land), rings
// shorter than min_ring left out.
DepthContours shoreline(const Seafloor& seafloor, double min_ring) {
    const auto [lo, hi] = std::minmax_element(seafloor.grid.z.begin(), seafloor.grid.z.end());
    if (!(*lo < 0.0 && *hi > 0.0)) return {};  // elevation z: land above 0
    IsobathOptions o;
    o.levels = {0.0};
    o.include_shoreline = false;
    const DepthContours all = extract_isobaths(seafloor, o);
    DepthContours kept;
    kept.offsets.push_back(0);
    for (std::size_t p = 0; p < all.size(); ++p) {
        double length = 0.0;
        const std::size_t first = all.offsets[p], last = all.offsets[p + 1];
        for (std::size_t i = first + 1; i < last; ++i)
            length += std::hypot(all.xy[2 * i] - all.xy[2 * i - 2], all.xy[2 * i + 1] - all.xy[2 * i - 1]);
        if (all.closed[p] && length < min_ring) continue;
        kept.xy.insert(kept.xy.end(), all.xy.begin() + static_cast<std::ptrdiff_t>(2 * first),
                       all.xy.begin() + static_cast<std::ptrdiff_t>(2 * last));
        kept.offsets.push_back(kept.xy.size() / 2);
        kept.depth.push_back(0.0);
        kept.closed.push_back(all.closed[p]);
    }
    return kept;
}

// The size field over the grid, in one pass: the expected vertex count (each wet
// cell holds area / (√3/4 · s²) triangles of edge s at its centre, and a triangulation
// has about half as many vertices as triangles) and the smallest size at a wet node.
struct SizeSurvey {
    double vertices = 0.0;
    double smallest = std::numeric_limits<double>::infinity();
};

SizeSurvey survey_sizes(const ElevationGrid& g, const EdgeSize& size) {
    SizeSurvey out;
    double triangles = 0.0;
    for (std::size_t j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < g.nx; ++i) {
            const double x = g.x0 + static_cast<double>(i) * g.dx, y = g.y0 + static_cast<double>(j) * g.dy;
            if (g.at(i, j) < 0.0) out.smallest = std::min(out.smallest, size(x, y));
            if (i + 1 == g.nx || j + 1 == g.ny) continue;
            const double cx = x + 0.5 * g.dx, cy = y + 0.5 * g.dy;
            if (depth_at(g, cx, cy) <= 0.0) continue;
            const double s = size(cx, cy);
            triangles += g.dx * g.dy / (std::sqrt(3.0) / 4.0 * s * s);
        }
    out.vertices = 0.5 * triangles;
    return out;
}

// Position along the rectangle's perimeter (counter-clockwise from (x0, y0)) of a
// point on it.
double perimeter_position(const ElevationGrid& g, double x, double y) {
    const double w = g.x_max() - g.x0, h = g.y_max() - g.y0;
    if (y == g.y0) return x - g.x0;
    if (x == g.x_max()) return w + (y - g.y0);
    if (y == g.y_max()) return w + h + (g.x_max() - x);
    return 2.0 * w + h + (g.y_max() - y);
}

// The point moved onto the nearest side of the rectangle when within `tolerance` of it.
bool snap_to_border(const ElevationGrid& g, double& x, double& y, double tolerance) {
    const double d[4] = {y - g.y0, g.x_max() - x, g.y_max() - y, x - g.x0};
    const int side = static_cast<int>(std::min_element(d, d + 4) - d);
    if (!(d[side] <= tolerance)) return false;
    if (side == 0) y = g.y0;
    else if (side == 1) x = g.x_max();
    else if (side == 2) y = g.y_max();
    else x = g.x0;
    x = std::clamp(x, g.x0, g.x_max());
    y = std::clamp(y, g.y0, g.y_max());
    return true;
}

// The rectangle and the shoreline as constraints that meet only at shared vertices:
// shoreline points closer than `min_gap` to the previous one are skipped (the slicer
// leaves near-duplicates where a contour passes by a grid node), open polylines'
// ends within `min_gap` of a side are put on it, and the border runs through them,
// so no constraint crosses another (a crossing would construct a point off both and
// refine without end around it).
void insert_constraints(CDT& cdt, const ElevationGrid& g, const DepthContours& shore, double min_gap) {
    std::vector<std::pair<double, Point>> border = {{0.0, Point(g.x0, g.y0)},
                                                    {perimeter_position(g, g.x_max(), g.y0), Point(g.x_max(), g.y0)},
                                                    {perimeter_position(g, g.x_max(), g.y_max()), Point(g.x_max(), g.y_max())},
                                                    {perimeter_position(g, g.x0, g.y_max()), Point(g.x0, g.y_max())}};
    std::vector<std::vector<Point>> lines;
    for (std::size_t p = 0; p < shore.size(); ++p) {
        std::vector<Point> line;
        for (std::size_t i = shore.offsets[p]; i < shore.offsets[p + 1]; ++i) {
            const double x = std::clamp(shore.xy[2 * i], g.x0, g.x_max()), y = std::clamp(shore.xy[2 * i + 1], g.y0, g.y_max());
            if (!line.empty() && std::hypot(x - line.back().x(), y - line.back().y()) < min_gap) continue;
            line.emplace_back(x, y);
        }
        if (shore.closed[p]) {
            while (line.size() > 3 && std::hypot(line.back().x() - line.front().x(), line.back().y() - line.front().y()) < min_gap)
                line.pop_back();
            if (line.size() < 3) continue;
            line.push_back(line.front());
        } else {
            if (line.size() < 2) continue;
            for (Point* end : {&line.front(), &line.back()}) {
                double x = end->x(), y = end->y();
                if (snap_to_border(g, x, y, min_gap)) {
                    *end = Point(x, y);
                    border.emplace_back(perimeter_position(g, x, y), *end);
                }
            }
        }
        lines.push_back(std::move(line));
    }
    std::sort(border.begin(), border.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Point> ring;
    for (const auto& [_, q] : border)
        if (ring.empty() || q != ring.back()) ring.push_back(q);
    ring.push_back(ring.front());
    cdt.insert_constraint(ring.begin(), ring.end());
    for (const std::vector<Point>& line : lines) cdt.insert_constraint(line.begin(), line.end());
}

// Regions between constraints, each wet or dry by the area-weighted vote of its
// triangles' centroid depths: every finite face's info becomes its region, and the
// result says per region whether it is water.
std::vector<bool> wet_regions(CDT& cdt, const ElevationGrid& g) {
    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) f->info() = kNone;
    std::vector<double> wet_area, dry_area;
    std::vector<CDT::Face_handle> stack;
    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (f->info() != kNone) continue;
        const auto r = static_cast<std::uint32_t>(wet_area.size());
        wet_area.push_back(0.0);
        dry_area.push_back(0.0);
        f->info() = r;
        stack.assign(1, f);
        while (!stack.empty()) {
            const CDT::Face_handle h = stack.back();
            stack.pop_back();
            const Point &a = h->vertex(0)->point(), &b = h->vertex(1)->point(), &c = h->vertex(2)->point();
            const double area = std::abs(CGAL::area(a, b, c));
            (depth_at(g, (a.x() + b.x() + c.x()) / 3.0, (a.y() + b.y() + c.y()) / 3.0) > 0.0 ? wet_area : dry_area)[r] += area;
            for (int e = 0; e < 3; ++e) {
                const CDT::Face_handle n = h->neighbor(e);
                if (cdt.is_infinite(n) || cdt.is_constrained({h, e}) || n->info() != kNone) continue;
                n->info() = r;
                stack.push_back(n);
            }
        }
    }
    std::vector<bool> wet(wet_area.size());
    for (std::size_t r = 0; r < wet.size(); ++r) wet[r] = wet_area[r] > dry_area[r];
    return wet;
}

// The water regions (wet_regions, faces' info their region) joined to the domain's border
// by water: a region with a vertex on the grid's rectangle, and every wet region that
// shares a (constrained) edge with one of them — a region ends where a shoreline or a
// constraint crossing the water does, so water is flooded region to region. Where no wet
// region reaches the border, every wet one.
std::vector<bool> open_water(const CDT& cdt, const ElevationGrid& g, const std::vector<bool>& wet) {
    const double tol = 1e-9 * std::max({1.0, std::abs(g.x0), std::abs(g.x_max()), std::abs(g.y0), std::abs(g.y_max())});
    const auto on_border = [&](const Point& q) {
        return std::abs(q.x() - g.x0) <= tol || std::abs(q.x() - g.x_max()) <= tol || std::abs(q.y() - g.y0) <= tol ||
               std::abs(q.y() - g.y_max()) <= tol;
    };
    std::vector<bool> open(wet.size(), false);
    std::vector<std::vector<std::uint32_t>> next(wet.size());  // wet regions across a constrained edge
    std::vector<std::uint32_t> stack;
    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        const std::uint32_t r = f->info();
        if (!wet[r]) continue;
        if (!open[r] && (on_border(f->vertex(0)->point()) || on_border(f->vertex(1)->point()) || on_border(f->vertex(2)->point()))) {
            open[r] = true;
            stack.push_back(r);
        }
        for (int e = 0; e < 3; ++e) {
            const CDT::Face_handle n = f->neighbor(e);
            if (!cdt.is_infinite(n) && n->info() != r && wet[n->info()]) next[r].push_back(n->info());
        }
    }
    if (stack.empty()) return wet;  // an enclosed basin: all its water
    while (!stack.empty()) {
        const std::uint32_t r = stack.back();
        stack.pop_back();
        for (const std::uint32_t n : next[r])
            if (!open[n]) open[n] = true, stack.push_back(n);
    }
    return open;
}

}  // namespace

WaterMesh mesh_water(const Seafloor& seafloor, const EdgeSize& size, const WaterMeshOptions& options) {
    const ElevationGrid& g = seafloor.grid;
    if (!(options.min_angle_deg > 0.0 && options.min_angle_deg <= 20.7))
        throw InputError("water mesh: min_angle_deg " + std::to_string(options.min_angle_deg) + " outside (0, 20.7]");
    const SizeSurvey survey = survey_sizes(g, size);
    if (!(survey.vertices <= static_cast<double>(options.max_vertices)))
        throw LimitError("water mesh: about " + std::to_string(static_cast<long long>(survey.vertices)) +
                         " vertices for the target edge lengths, more than the limit of " +
                         std::to_string(options.max_vertices));
    const double smallest = survey.smallest;
    const double min_ring = options.min_ring_length > 0.0 ? options.min_ring_length : 2.0 * smallest;

    CDT cdt;
    const double min_gap = std::isfinite(smallest) ? 0.1 * smallest : 1e-9 * std::hypot(g.x_max() - g.x0, g.y_max() - g.y0);
    insert_constraints(cdt, g, shoreline(seafloor, std::isfinite(min_ring) ? min_ring : 0.0), min_gap);
    const double sine = std::sin(options.min_angle_deg * std::numbers::pi / 180.0);
    const std::function<double(double, double)> size_at = [&](double x, double y) { return centroid_size(size, g, x, y); };
    CGAL::Delaunay_mesher_2<CDT, detail::CentroidSizeCriteria<CDT>> mesher(cdt, detail::CentroidSizeCriteria<CDT>(sine * sine, size_at));
    mesher.refine_mesh();

    std::vector<bool> wet = wet_regions(cdt, g);
    if (!options.inland_water) wet = open_water(cdt, g, wet);
    for (CDT::Finite_vertices_iterator v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) v->info() = kNone;
    WaterMesh mesh;
    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (!wet[f->info()]) continue;
        for (int k = 0; k < 3; ++k) {
            const CDT::Vertex_handle v = f->vertex(k);
            if (v->info() == kNone) {
                v->info() = static_cast<std::uint32_t>(mesh.x.size());
                mesh.x.push_back(v->point().x());
                mesh.y.push_back(v->point().y());
                mesh.boundary.push_back(0);
            }
            mesh.triangles.push_back(v->info());
        }
        for (int e = 0; e < 3; ++e)
            if (cdt.is_constrained({f, e})) {
                mesh.boundary[f->vertex(CDT::ccw(e))->info()] = 1;
                mesh.boundary[f->vertex(CDT::cw(e))->info()] = 1;
            }
    }
    if (mesh.triangles.empty()) throw InputError("water mesh: the seafloor holds no water (depth > 0) to mesh");
    return mesh;
}

// The waterline (surface.h; docs/inspect.md "The waterline"). Level with the sand, the
// shoreline's chords dipped in and out of the seafloor's triangles — a saw-tooth a shore
// edge long; Gonzato's and Jeschke's troughs reach 1.1–1.9 h between 3 and 20 cm of
// depth on the default bay, and there the water went under the sand in patches between
// the held shoreline and the sea — flakes of water lying on the sand.
namespace {
constexpr double kSwashFilm = 0.3;        // the least share of the still-water depth a trough leaves
constexpr double kShoreUnderSand = 0.05;  // the shoreline's depth under the sand, × the amplitude

// max(d, floor) eased over [0, 2 floor] (C¹): d itself above 2 floor.
float ease_above(float d, float floor) {
    if (d >= 2.0f * floor) return d;
    if (d <= 0.0f) return floor;
    return floor + d * d / (4.0f * floor);
}
}  // namespace

WaterlinePlan plan_waterline(const WaterMesh& mesh, const Seafloor& seafloor, double amplitude) {
    WaterlinePlan p;
    const ElevationGrid& g = seafloor.grid;
    const std::size_t n = mesh.vertex_count();
    p.depth.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
        const double x = mesh.x[v], y = mesh.y[v];
        p.depth[v] = static_cast<float>(std::max(0.0, depth_at(g, x, y)));
        const bool side = x <= g.x0 || x >= g.x_max() || y <= g.y0 || y >= g.y_max();
        if (!mesh.boundary.empty() && mesh.boundary[v] && !side) p.shore.push_back(static_cast<std::uint32_t>(v));
    }
    p.under_sand = static_cast<float>(kShoreUnderSand * amplitude);
    p.swash_film = static_cast<float>(kSwashFilm);
    return p;
}

void keep_waterline(const WaterlinePlan& plan, std::span<float> positions) {
    if (positions.size() < 3 * plan.depth.size())
        throw InputError("keep_waterline: " + std::to_string(positions.size() / 3) + " positions for " +
                         std::to_string(plan.depth.size()) + " vertices");
    for (std::size_t v = 0; v < plan.depth.size(); ++v) {
        const float h = plan.depth[v];
        if (!(h > 0.0f)) continue;
        float& z = positions[3 * v + 2];
        z = ease_above(h + z, plan.swash_film * h) - h;
    }
    for (const std::uint32_t v : plan.shore) positions[3 * v + 2] = std::min(positions[3 * v + 2], -plan.under_sand);
}

}  // namespace wave
