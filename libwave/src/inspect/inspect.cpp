// Mesh inspection of an animation (libwave/inspect.h; definitions in docs/inspect.md).
#include "libwave/inspect.h"

#include "libwave/errors.h"

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <string>

namespace wave {
namespace {

struct Edge {
    std::uint32_t a = 0, b = 0;  // a < b
    std::uint32_t uses = 0;
};

// The topology, shared by every frame: unique edges with their use counts, each
// triangle's three edge numbers, and every vertex's edges (CSR).
struct Topology {
    std::vector<Edge> edges;
    std::vector<std::array<std::uint32_t, 3>> triangle_edges;
    std::vector<std::uint32_t> vertex_edge_start, vertex_edges;
};

Topology build_topology(std::span<const std::uint32_t> triangles, std::size_t vertex_count) {
    const std::size_t t_count = triangles.size() / 3;
    std::vector<std::array<std::uint32_t, 3>> half(3 * t_count);  // a, b, triangle·3 + corner
    for (std::size_t t = 0; t < t_count; ++t)
        for (std::size_t c = 0; c < 3; ++c) {
            const std::uint32_t u = triangles[3 * t + c], v = triangles[3 * t + (c + 1) % 3];
            half[3 * t + c] = {std::min(u, v), std::max(u, v), static_cast<std::uint32_t>(3 * t + c)};
        }
    std::sort(half.begin(), half.end());
    Topology topo;
    topo.triangle_edges.resize(t_count);
    for (std::size_t i = 0; i < half.size(); ++i) {
        if (i == 0 || half[i][0] != half[i - 1][0] || half[i][1] != half[i - 1][1])
            topo.edges.push_back({half[i][0], half[i][1], 0});
        ++topo.edges.back().uses;
        topo.triangle_edges[half[i][2] / 3][half[i][2] % 3] = static_cast<std::uint32_t>(topo.edges.size() - 1);
    }
    topo.vertex_edge_start.assign(vertex_count + 1, 0);
    for (const Edge& e : topo.edges) {
        ++topo.vertex_edge_start[e.a + 1];
        ++topo.vertex_edge_start[e.b + 1];
    }
    for (std::size_t v = 0; v < vertex_count; ++v) topo.vertex_edge_start[v + 1] += topo.vertex_edge_start[v];
    topo.vertex_edges.resize(topo.vertex_edge_start.back());
    std::vector<std::uint32_t> fill(topo.vertex_edge_start.begin(), topo.vertex_edge_start.end() - 1);
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        topo.vertex_edges[fill[topo.edges[e].a]++] = static_cast<std::uint32_t>(e);
        topo.vertex_edges[fill[topo.edges[e].b]++] = static_cast<std::uint32_t>(e);
    }
    return topo;
}

struct Vec3 {
    double x, y, z;
};
Vec3 point(std::span<const float> p, std::size_t v) { return {p[3 * v], p[3 * v + 1], p[3 * v + 2]}; }
Vec3 sub(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

double median(std::vector<double>& values) {
    if (values.empty()) return 0.0;
    const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    return *mid;
}

// Angles, areas and facing of every triangle of one frame.
void inspect_triangles(std::span<const std::uint32_t> triangles, std::span<const float> p, std::span<const float> foam,
                       std::span<const char> shore, const InspectOptions& options, std::size_t frame, FrameInspection& out) {
    const double sliver = options.sliver_angle_deg * std::numbers::pi / 180.0;
    double smallest = std::numbers::pi, smallest_off_lips = std::numbers::pi;
    for (std::size_t t = 0; t < triangles.size() / 3; ++t) {
        const std::uint32_t i[3] = {triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]};
        const Vec3 a = point(p, i[0]), b = point(p, i[1]), c = point(p, i[2]);
        const Vec3 n = cross(sub(b, a), sub(c, a));
        const double longest = std::max({norm(sub(b, a)), norm(sub(c, b)), norm(sub(a, c))});
        if (norm(n) <= 1e-12 * longest * longest) {
            ++out.degenerate;
            continue;
        }
        const bool on_shore = shore[i[0]] || shore[i[1]] || shore[i[2]];
        const double angle = std::min({std::atan2(norm(n), dot(sub(b, a), sub(c, a))),
                                       std::atan2(norm(n), dot(sub(a, b), sub(c, b))),
                                       std::atan2(norm(n), dot(sub(a, c), sub(b, c)))});
        // A lip: the motion's own overturned triangles where it says which they are (asked
        // only of the triangles it decides: facing down or slivers), else a foamy one.
        const bool breaking =
            !on_shore && (options.drawn_lips ? (n.z < 0.0 || angle < sliver) && options.drawn_lips(frame, i[0], i[1], i[2])
                                             : !foam.empty() && std::max({foam[i[0]], foam[i[1]], foam[i[2]]}) >= options.lip_foam);
        if (n.z < 0.0) {
            ++out.facing_down;
            ++(breaking ? out.lips : out.folds);
        }
        smallest = std::min(smallest, angle);
        if (!breaking && !on_shore) smallest_off_lips = std::min(smallest_off_lips, angle);
        if (angle < sliver) {
            ++out.slivers;
            if (breaking) ++out.lip_slivers;
            if (on_shore) ++out.shore_slivers;
        }
    }
    out.smallest_angle_deg = smallest * 180.0 / std::numbers::pi;
    out.smallest_angle_off_lips_deg = smallest_off_lips * 180.0 / std::numbers::pi;
}

// Edge lengths against the local spacing (the smaller of the medians at its two ends).
void inspect_edges(const Topology& topo, std::span<const float> p, std::size_t vertex_count,
                   const InspectOptions& options, FrameInspection& out) {
    std::vector<double> length(topo.edges.size());
    for (std::size_t e = 0; e < topo.edges.size(); ++e)
        length[e] = norm(sub(point(p, topo.edges[e].a), point(p, topo.edges[e].b)));
    std::vector<double> local(vertex_count, 0.0), scratch;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        scratch.clear();
        for (std::uint32_t k = topo.vertex_edge_start[v]; k < topo.vertex_edge_start[v + 1]; ++k)
            scratch.push_back(length[topo.vertex_edges[k]]);
        local[v] = median(scratch);
    }
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        out.longest_edge = std::max(out.longest_edge, length[e]);
        const double spacing = std::min(local[topo.edges[e].a], local[topo.edges[e].b]);
        if (spacing <= 0.0) continue;
        const double ratio = length[e] / spacing;
        out.worst_edge_ratio = std::max(out.worst_edge_ratio, ratio);
        if (ratio > options.long_edge_ratio) ++out.long_edges;
    }
    out.median_edge = median(length);
}

void inspect_speed(std::span<const float> p, std::span<const float> next, double fps, FrameInspection& out) {
    for (std::size_t v = 0; v < p.size() / 3; ++v) {
        const double speed = norm(sub(point(next, v), point(p, v))) * fps;
        if (speed > out.max_speed) {
            out.max_speed = speed;
            out.fastest_vertex = v;
        }
    }
}

// Boundary loops, walked along their triangles' orientation, measured at frame 0; the
// shore vertices (on a boundary edge, inside the border) flagged in `shore`.
void inspect_boundary(const MorphAnimationView& a, const Topology& topo, const InspectOptions& options,
                      MeshInspection& out, std::vector<char>& shore) {
    std::multimap<std::uint32_t, std::uint32_t> next;  // from → to, boundary half-edges
    for (std::size_t t = 0; t < a.triangles.size() / 3; ++t)
        for (std::size_t c = 0; c < 3; ++c)
            if (topo.edges[topo.triangle_edges[t][c]].uses == 1)
                next.emplace(a.triangles[3 * t + c], a.triangles[3 * t + (c + 1) % 3]);
    out.boundary_edges = next.size();
    const std::span<const float> p = a.positions.first(3 * a.vertex_count);
    auto border_distance = [&](std::uint32_t v) {
        return std::min({p[3 * v] - out.border_min_x, out.border_max_x - p[3 * v], p[3 * v + 1] - out.border_min_y,
                         out.border_max_y - p[3 * v + 1]});
    };
    while (!next.empty()) {
        const std::uint32_t first = next.begin()->first;
        std::uint32_t at = first;
        BoundaryLoop loop;
        bool closed = false;
        for (auto it = next.find(at); it != next.end(); it = next.find(at)) {
            const std::uint32_t to = it->second;
            next.erase(it);
            ++loop.edges;
            loop.length += std::hypot(p[3 * to] - p[3 * at], p[3 * to + 1] - p[3 * at + 1]);
            const double d = border_distance(at);
            if (d <= options.border_tolerance) ++loop.on_border;
            else shore[at] = 1;
            loop.farthest_inside = std::max(loop.farthest_inside, d);
            at = to;
            if (at == first) {
                closed = true;
                break;
            }
        }
        if (closed) out.loops.push_back(loop);
        else ++out.open_boundary_chains;
    }
    std::sort(out.loops.begin(), out.loops.end(),
              [](const BoundaryLoop& x, const BoundaryLoop& y) { return x.length > y.length; });
}

void check_sizes(const MorphAnimationView& a) {
    const std::size_t n = a.vertex_count;
    if (a.triangles.size() % 3 != 0 || a.frame_count == 0 || a.positions.size() != a.frame_count * n * 3)
        throw InputError("inspect: an animation of " + std::to_string(a.frame_count) + " frames of " +
                         std::to_string(n) + " vertices holds " + std::to_string(a.positions.size()) +
                         " position values");
    if (!a.foam.empty() && a.foam.size() != a.frame_count * n)
        throw InputError("inspect: foam holds " + std::to_string(a.foam.size()) + " values for " +
                         std::to_string(a.frame_count) + " frames of " + std::to_string(n) + " vertices");
    for (std::size_t k = 0; k < a.triangles.size(); ++k)
        if (a.triangles[k] >= n)
            throw InputError("inspect: triangle " + std::to_string(k / 3) + " uses vertex " +
                             std::to_string(a.triangles[k]) + " of " + std::to_string(n));
}

FrameInspection worst_of(const std::vector<FrameInspection>& frames) {
    FrameInspection w = frames.front();
    for (const FrameInspection& f : frames) {
        if (f.folds > w.folds) w.frame = f.frame;
        w.facing_down = std::max(w.facing_down, f.facing_down);
        w.lips = std::max(w.lips, f.lips);
        w.folds = std::max(w.folds, f.folds);
        w.degenerate = std::max(w.degenerate, f.degenerate);
        w.slivers = std::max(w.slivers, f.slivers);
        w.lip_slivers = std::max(w.lip_slivers, f.lip_slivers);
        w.shore_slivers = std::max(w.shore_slivers, f.shore_slivers);
        w.smallest_angle_deg = std::min(w.smallest_angle_deg, f.smallest_angle_deg);
        w.smallest_angle_off_lips_deg = std::min(w.smallest_angle_off_lips_deg, f.smallest_angle_off_lips_deg);
        w.longest_edge = std::max(w.longest_edge, f.longest_edge);
        w.median_edge = std::max(w.median_edge, f.median_edge);
        w.worst_edge_ratio = std::max(w.worst_edge_ratio, f.worst_edge_ratio);
        w.long_edges = std::max(w.long_edges, f.long_edges);
        if (f.max_speed > w.max_speed) {
            w.max_speed = f.max_speed;
            w.fastest_vertex = f.fastest_vertex;
        }
    }
    return w;
}

}  // namespace

MeshInspection inspect_animation(const MorphAnimationView& a, const InspectOptions& options) {
    check_sizes(a);
    const std::size_t n = a.vertex_count;
    MeshInspection out;
    out.vertex_count = n;
    out.triangle_count = a.triangles.size() / 3;
    out.frame_count = a.frame_count;
    const Topology topo = build_topology(a.triangles, n);
    for (const Edge& e : topo.edges)
        if (e.uses > 2) ++out.non_manifold_edges;
    std::vector<char> used(n, 0);
    for (std::uint32_t v : a.triangles) used[v] = 1;
    out.unreferenced_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
    if (n > 0) {
        out.border_min_x = out.border_max_x = a.positions[0];
        out.border_min_y = out.border_max_y = a.positions[1];
    }
    for (std::size_t v = 0; v < n; ++v) {
        out.border_min_x = std::min(out.border_min_x, static_cast<double>(a.positions[3 * v]));
        out.border_max_x = std::max(out.border_max_x, static_cast<double>(a.positions[3 * v]));
        out.border_min_y = std::min(out.border_min_y, static_cast<double>(a.positions[3 * v + 1]));
        out.border_max_y = std::max(out.border_max_y, static_cast<double>(a.positions[3 * v + 1]));
    }
    std::vector<char> shore(n, 0);
    inspect_boundary(a, topo, options, out, shore);
    out.shore_vertices = static_cast<std::size_t>(std::count(shore.begin(), shore.end(), 1));

    out.frames.resize(a.frame_count);
    const bool whole_loop = a.loop_frames == a.frame_count && a.first_frame == 0;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, a.frame_count), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f < r.end(); ++f) {
            FrameInspection& fi = out.frames[f];
            fi.frame = a.first_frame + f;
            const auto p = a.positions.subspan(f * 3 * n, 3 * n);
            const auto foam = a.foam.empty() ? std::span<const float>{} : a.foam.subspan(f * n, n);
            inspect_triangles(a.triangles, p, foam, shore, options, fi.frame, fi);
            inspect_edges(topo, p, n, options, fi);
            if (f + 1 < a.frame_count || (whole_loop && a.frame_count > 1)) {
                const std::size_t g = (f + 1) % a.frame_count;
                inspect_speed(p, a.positions.subspan(g * 3 * n, 3 * n), a.fps, fi);
            }
        }
    });
    out.worst = worst_of(out.frames);
    std::vector<std::size_t> on_shore;
    for (std::size_t v = 0; v < n; ++v)
        if (shore[v]) on_shore.push_back(v);
    for (std::size_t f = 1; f < a.frame_count; ++f)
        for (const std::size_t v : on_shore) {
            const std::size_t at = 3 * (f * n + v);
            out.shore_drift = std::max(out.shore_drift, std::hypot(double(a.positions[at]) - a.positions[3 * v],
                                                                   double(a.positions[at + 1]) - a.positions[3 * v + 1]));
        }
    return out;
}

namespace {

using Json = nlohmann::ordered_json;

Json frame_json(const FrameInspection& f) {
    return {{"frame", f.frame},
            {"facing_down", f.facing_down},
            {"lips", f.lips},
            {"folds", f.folds},
            {"degenerate", f.degenerate},
            {"slivers", f.slivers},
            {"lip_slivers", f.lip_slivers},
            {"shore_slivers", f.shore_slivers},
            {"smallest_angle_deg", f.smallest_angle_deg},
            {"smallest_angle_off_lips_deg", f.smallest_angle_off_lips_deg},
            {"longest_edge_m", f.longest_edge},
            {"median_edge_m", f.median_edge},
            {"worst_edge_ratio", f.worst_edge_ratio},
            {"long_edges", f.long_edges},
            {"max_speed_m_s", f.max_speed},
            {"fastest_vertex", f.fastest_vertex}};
}

}  // namespace

std::string inspection_json(const MeshInspection& m, const InspectOptions& o, bool per_frame) {
    Json loops = Json::array();
    for (const BoundaryLoop& l : m.loops)
        loops.push_back({{"edges", l.edges}, {"length_m", l.length}, {"vertices_on_border", l.on_border},
                         {"farthest_inside_m", l.farthest_inside}});
    Json doc = {{"vertices", m.vertex_count},
                {"triangles", m.triangle_count},
                {"frames", m.frame_count},
                {"options", {{"sliver_angle_deg", o.sliver_angle_deg}, {"lip_foam", o.lip_foam},
                             {"long_edge_ratio", o.long_edge_ratio}, {"border_tolerance_m", o.border_tolerance}}},
                {"unreferenced_vertices", m.unreferenced_vertices},
                {"non_manifold_edges", m.non_manifold_edges},
                {"boundary", {{"edges", m.boundary_edges}, {"loops", loops}, {"open_chains", m.open_boundary_chains},
                              {"shore_vertices", m.shore_vertices}, {"shore_drift_m", m.shore_drift},
                              {"border", {m.border_min_x, m.border_min_y, m.border_max_x, m.border_max_y}}}},
                {"worst", frame_json(m.worst)}};
    if (per_frame) {
        Json frames = Json::array();
        for (const FrameInspection& f : m.frames) frames.push_back(frame_json(f));
        doc["per_frame"] = std::move(frames);
    }
    return doc.dump();
}

}  // namespace wave
