// `wave inspect`: what a renderer meets in an output of `wave run` (libwave/inspect.h).
#include "commands.h"

#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/inspect.h"
#include "libwave/motion.h"
#include "libwave/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace wave::cli {
namespace {

// A file as given; a folder: its files form index, else its animation.glb / .gltf.
std::string animation_path(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError("inspect: no such file or folder '" + path + "'");
    if (!fs::is_directory(path, ec)) return path;
    for (const char* name : {"index.json", "animation.glb", "animation.gltf"})
        if (fs::exists(fs::path(path) / name, ec)) return (fs::path(path) / name).string();
    throw InputError("inspect: no libwave output in '" + path + "' (expected index.json, animation.glb or animation.gltf)");
}

void print_text(const std::string& path, const MeshInspection& m, const InspectOptions& o) {
    const FrameInspection& w = m.worst;
    std::cout << path << ": " << m.vertex_count << " vertices, " << m.triangle_count << " triangles, " << m.frame_count
              << " frame(s)\n"
              << "topology: " << m.unreferenced_vertices << " unreferenced vertices, " << m.non_manifold_edges
              << " non-manifold edges, " << m.boundary_edges << " boundary edges in " << m.loops.size() << " loop(s)"
              << (m.open_boundary_chains ? " and " + std::to_string(m.open_boundary_chains) + " open chain(s)" : "") << '\n';
    for (std::size_t i = 0; i < m.loops.size() && i < 5; ++i) {
        const BoundaryLoop& l = m.loops[i];
        std::cout << "  loop " << i << ": " << l.edges << " edges, " << std::setprecision(6) << l.length << " m, "
                  << l.on_border << " vertices on the domain border, farthest " << l.farthest_inside << " m inside it\n";
    }
    if (m.shore_vertices)
        std::cout << "shore: " << m.shore_vertices << " boundary vertices inside the border, moving at most " << m.shore_drift
                  << " m in plan\n";
    std::cout << "worst frame: " << w.folds << " folds (frame " << w.frame << "), " << w.lips
              << " overturning lips; at most " << w.facing_down << " triangles facing down\n"
              << "triangles: " << w.degenerate << " degenerate, " << w.slivers << " slivers (< " << o.sliver_angle_deg
              << "°; " << w.lip_slivers << " on overturning lips, " << w.shore_slivers << " on the shore), smallest angle "
              << w.smallest_angle_deg << "° (" << w.smallest_angle_off_lips_deg << "° off the lips and the shore)\n"
              << "edges: longest " << w.longest_edge << " m (median " << w.median_edge << " m), " << w.long_edges
              << " longer than " << o.long_edge_ratio << " × the local spacing (worst " << w.worst_edge_ratio << " ×)\n"
              << "motion: fastest vertex " << w.max_speed << " m/s (vertex " << w.fastest_vertex << ")\n";
}

// What compression did to one frame's positions, against the float run's.
struct FrameError {
    std::size_t frame = 0;
    double height = 0.0;      // the largest |Δz| over the domain's vertices (m)
    double horizontal = 0.0;  // the largest horizontal error over the domain's vertices (m)
    double relative = 0.0;    // the largest horizontal error over the shortest edge at the vertex
    double skirt_height = 0.0;  // the largest |Δz| beyond the domain (far-field skirt)
    std::size_t distinct_heights = 0;  // distinct z among the domain's vertices of the compared output
    std::size_t reference_heights = 0; // the same in the float run
};

// For each vertex of `test`, its vertex in `ref`: the same index when both share the
// triangles (each possibly rotated: meshopt's triangle codec), else (Draco's own point
// order) the nearest vertex of the first frame, positions within the codec's error of
// each other and far closer than the mesh's spacing; InputError when none is near.
std::vector<std::uint32_t> match_vertices(const StoredAnimation& test, const StoredAnimation& ref, const std::string& path) {
    std::vector<std::uint32_t> to(test.vertex_count);
    // Each triangle from its smallest index (meshopt's triangle codec may rotate corners).
    const auto canonical = [](std::vector<std::uint32_t> t) {
        for (std::size_t i = 0; i + 2 < t.size(); i += 3)
            while (t[i] > t[i + 1] || t[i] > t[i + 2])
                std::rotate(t.begin() + static_cast<std::ptrdiff_t>(i), t.begin() + static_cast<std::ptrdiff_t>(i + 1), t.begin() + static_cast<std::ptrdiff_t>(i + 3));
        return t;
    };
    if (test.vertex_count == ref.vertex_count && canonical(test.triangles) == canonical(ref.triangles)) {
        for (std::size_t v = 0; v < to.size(); ++v) to[v] = static_cast<std::uint32_t>(v);
        return to;
    }
    if (test.vertex_count != ref.vertex_count || ref.frame_count == 0)
        throw InputError("inspect --against: " + path + " has " + std::to_string(test.vertex_count) + " vertices, the reference " +
                         std::to_string(ref.vertex_count) + ": not the same scene's mesh");
    // A grid of the domain's average spacing over the reference's first frame (the far
    // skirt's few vertices share its outer cells).
    const std::size_t n = ref.vertex_count;
    const float* p = ref.positions.data();
    double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    double hi[2] = {-lo[0], -lo[1]};
    for (std::size_t v = 0; v < n; ++v)
        if (ref.texcoords[2 * v] >= 0.0f && ref.texcoords[2 * v] <= 1.0f && ref.texcoords[2 * v + 1] >= 0.0f && ref.texcoords[2 * v + 1] <= 1.0f)
            for (int c = 0; c < 2; ++c) lo[c] = std::min(lo[c], double{p[3 * v + c]}), hi[c] = std::max(hi[c], double{p[3 * v + c]});
    const double cell = std::max(1e-9, std::sqrt(std::max(1e-18, (hi[0] - lo[0]) * (hi[1] - lo[1])) / static_cast<double>(n)));
    const auto index = [&](double x) { return static_cast<long long>(std::floor(x / cell)); };
    const auto key = [](long long i, long long j) { return (i << 32) ^ (j & 0xFFFFFFFFLL); };
    std::unordered_map<long long, std::vector<std::uint32_t>> grid;
    for (std::size_t v = 0; v < n; ++v) grid[key(index(p[3 * v]), index(p[3 * v + 1]))].push_back(static_cast<std::uint32_t>(v));
    const float* q = test.positions.data();
    for (std::size_t v = 0; v < test.vertex_count; ++v) {
        double best = std::numeric_limits<double>::infinity();
        const long long i0 = index(q[3 * v]), j0 = index(q[3 * v + 1]);
        for (long long i = i0 - 1; i <= i0 + 1; ++i)
            for (long long j = j0 - 1; j <= j0 + 1; ++j) {
                const auto it = grid.find(key(i, j));
                if (it == grid.end()) continue;
                for (const std::uint32_t r : it->second) {
                    const double d = std::pow(double{p[3 * r]} - q[3 * v], 2) + std::pow(double{p[3 * r + 1]} - q[3 * v + 1], 2) +
                                     std::pow(double{p[3 * r + 2]} - q[3 * v + 2], 2);
                    if (d < best) best = d, to[v] = r;
                }
            }
        if (!std::isfinite(best))
            throw InputError("inspect --against: vertex " + std::to_string(v) + " of " + path + " has no vertex of the reference near it");
    }
    return to;
}

std::vector<FrameError> compare_positions(const StoredAnimation& test, const StoredAnimation& ref, const std::string& path) {
    if (test.first_frame != ref.first_frame || test.frame_count != ref.frame_count)
        throw InputError("inspect --against: " + path + " holds frames " + std::to_string(test.first_frame) + " … " +
                         std::to_string(test.first_frame + test.frame_count) + ", the reference " + std::to_string(ref.first_frame) +
                         " … " + std::to_string(ref.first_frame + ref.frame_count));
    const std::vector<std::uint32_t> to = match_vertices(test, ref, path);
    const std::size_t n = ref.vertex_count;
    std::vector<char> domain(n);
    for (std::size_t v = 0; v < n; ++v) {
        const float u = ref.texcoords[2 * v], w = ref.texcoords[2 * v + 1];
        domain[v] = u >= 0.0f && u <= 1.0f && w >= 0.0f && w <= 1.0f;
    }
    std::vector<FrameError> out;
    std::vector<double> shortest(n);
    for (std::size_t f = 0; f < ref.frame_count; ++f) {
        const float* p = &ref.positions[3 * n * f];
        const float* q = &test.positions[3 * n * f];
        std::fill(shortest.begin(), shortest.end(), std::numeric_limits<double>::infinity());
        for (std::size_t t = 0; t + 2 < ref.triangles.size(); t += 3)
            for (std::size_t k = 0; k < 3; ++k) {
                const std::uint32_t i = ref.triangles[t + k], j = ref.triangles[t + (k + 1) % 3];
                const double d = std::sqrt(std::pow(p[3 * i] - p[3 * j], 2) + std::pow(p[3 * i + 1] - p[3 * j + 1], 2) +
                                           std::pow(p[3 * i + 2] - p[3 * j + 2], 2));
                shortest[i] = std::min(shortest[i], d), shortest[j] = std::min(shortest[j], d);
            }
        FrameError e;
        e.frame = ref.first_frame + f;
        std::unordered_set<float> heights, ref_heights;
        for (std::size_t v = 0; v < test.vertex_count; ++v) {
            const std::size_t r = to[v];
            const double dz = std::abs(double{q[3 * v + 2]} - p[3 * r + 2]);
            if (!domain[r]) {
                e.skirt_height = std::max(e.skirt_height, dz);
                continue;
            }
            const double dh = std::hypot(double{q[3 * v]} - p[3 * r], double{q[3 * v + 1]} - p[3 * r + 1]);
            e.height = std::max(e.height, dz);
            e.horizontal = std::max(e.horizontal, dh);
            if (shortest[r] > 0.0 && std::isfinite(shortest[r])) e.relative = std::max(e.relative, dh / shortest[r]);
            heights.insert(q[3 * v + 2]);
            ref_heights.insert(p[3 * r + 2]);
        }
        e.distinct_heights = heights.size();
        e.reference_heights = ref_heights.size();
        out.push_back(e);
    }
    return out;
}

int run_against(const InspectArgs& a) {
    const std::string path = animation_path(a.path), reference = animation_path(a.against);
    const StoredAnimation test = read_animation(path);
    const StoredAnimation ref = read_animation(reference);
    const std::vector<FrameError> errors = compare_positions(test, ref, path);
    FrameError worst;
    worst.distinct_heights = std::numeric_limits<std::size_t>::max();
    for (const FrameError& e : errors) {
        worst.height = std::max(worst.height, e.height);
        worst.horizontal = std::max(worst.horizontal, e.horizontal);
        worst.relative = std::max(worst.relative, e.relative);
        worst.skirt_height = std::max(worst.skirt_height, e.skirt_height);
        worst.distinct_heights = std::min(worst.distinct_heights, e.distinct_heights);
    }
    if (a.json) {
        nlohmann::ordered_json frames = nlohmann::ordered_json::array();
        for (const FrameError& e : errors)
            frames.push_back({{"frame", e.frame}, {"height_error_m", e.height}, {"horizontal_error_m", e.horizontal},
                              {"horizontal_error_per_edge", e.relative}, {"skirt_height_error_m", e.skirt_height},
                              {"distinct_heights", e.distinct_heights}, {"reference_distinct_heights", e.reference_heights}});
        nlohmann::ordered_json doc{{"input", path}, {"against", reference}, {"vertices", test.vertex_count}, {"frames", errors.size()},
                                   {"height_error_m", worst.height}, {"horizontal_error_m", worst.horizontal},
                                   {"horizontal_error_per_edge", worst.relative}, {"skirt_height_error_m", worst.skirt_height},
                                   {"fewest_distinct_heights", worst.distinct_heights}, {"per_frame", frames}};
        std::cout << doc.dump(2) << '\n';
        return 0;
    }
    std::cout << path << " against " << reference << ": " << test.vertex_count << " vertices, " << errors.size() << " frame(s)\n"
              << "domain: heights within " << worst.height * 1e3 << " mm, horizontal within " << worst.horizontal * 1e3
              << " mm (" << worst.relative * 100.0 << " % of the shortest edge at a vertex); at least "
              << worst.distinct_heights << " distinct heights in a frame\n"
              << "far field: heights within " << worst.skirt_height * 1e3 << " mm\n";
    return 0;
}

}  // namespace

int run_inspect(const InspectArgs& a) {
    if (!a.against.empty()) return run_against(a);
    const std::string path = animation_path(a.path);
    const StoredAnimation stored = read_animation(path);
    InspectOptions options = a.options;
    std::optional<ScenePlan> plan;
    if (!a.scene.empty()) {
        const Scene scene = read_scene(a.scene);
        if (!scene.breakers)
            throw InputError("inspect --scene: " + a.scene + " draws no lips of its own (only Jeschke's breakers do); without --scene the foam marks the lips");
        plan = plan_scene(scene);
        const std::size_t drawn = plan->breakers.vertex_count();
        if (drawn == 0 || drawn > stored.vertex_count || !(stored.fps > 0.0))
            throw InputError("inspect --scene: " + path + " holds " + std::to_string(stored.vertex_count) + " vertices, fewer than the " +
                             std::to_string(drawn) + " breaker vertices of " + a.scene + ": not its output");
        const double fps = stored.fps;
        const JeschkeMotionPlan& breakers = plan->breakers;
        options.drawn_lips = [&breakers, fps](std::size_t frame, std::uint32_t i, std::uint32_t j, std::uint32_t k) {
            return jeschke_draws_overturned(breakers, static_cast<double>(frame) / fps, i, j, k);
        };
    }
    const MeshInspection m = inspect_animation(stored.view(), options);
    if (a.json) {
        nlohmann::ordered_json doc = nlohmann::ordered_json::parse(inspection_json(m, a.options));
        doc["input"] = path;
        std::cout << doc.dump(2) << '\n';
    }
    else print_text(path, m, a.options);
    return 0;
}

}  // namespace wave::cli
