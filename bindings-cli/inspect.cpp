// `wave inspect`: what a renderer meets in an output of `wave run` (libwave/inspect.h).
#include "commands.h"

#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/inspect.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iomanip>
#include <iostream>

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

}  // namespace

int run_inspect(const InspectArgs& a) {
    const std::string path = animation_path(a.path);
    const StoredAnimation stored = read_animation(path);
    const MeshInspection m = inspect_animation(stored.view(), a.options);
    if (a.json) {
        nlohmann::ordered_json doc = nlohmann::ordered_json::parse(inspection_json(m, a.options));
        doc["input"] = path;
        std::cout << doc.dump(2) << '\n';
    }
    else print_text(path, m, a.options);
    return 0;
}

}  // namespace wave::cli
