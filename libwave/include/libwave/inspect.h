/// \file
/// libwave — inspect: what a renderer will meet in an animated water mesh.
///
/// Per frame: triangles facing down in plan (split into overturning lips, on breaking
/// crests, and folds, which are defects), slivers (smallest angle, longest edge over the
/// local spacing), degenerate triangles and the fastest vertex; once for the topology
/// (it is the same in every frame): unreferenced vertices, non-manifold edges and the
/// boundary loops with where they lie. docs/inspect.md gives the definitions; `wave
/// inspect` prints them for any output of `wave run`.
///
/// Units: SI, positions z up (as StoredAnimation and MorphAnimationView hold them).
#pragma once

#include "libwave/export.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace wave {

/// What inspect_animation counts as a defect (`wave inspect`'s options).
struct InspectOptions {
    /// A triangle whose smallest angle is below this is a sliver (degrees).
    double sliver_angle_deg = 15.0;
    /// A triangle facing down in plan is an overturning lip when one of its vertices
    /// carries at least this much foam (the breaking state in an exported file), a fold
    /// otherwise. Without foam every downward triangle is a fold.
    double lip_foam = 0.1;
    /// An edge is long when it exceeds this many times the local spacing: the smaller of
    /// the median lengths of the edges at its two ends.
    double long_edge_ratio = 3.0;
    /// A boundary vertex lies on the domain border when its plan position is within
    /// this distance (m) of the bounding rectangle of the first frame's plan positions.
    double border_tolerance = 1e-6;
    /// The motion's own overturned lips, or empty: when set, a triangle (vertices a, b,
    /// c) facing down or a sliver in frame `frame` of the loop is an overturning lip
    /// exactly when this holds, whatever its foam (`wave inspect --scene`: the breakers'
    /// jeschke_draws_overturned). Called from several threads.
    std::function<bool(std::size_t frame, std::uint32_t a, std::uint32_t b, std::uint32_t c)> drawn_lips{};
};

/// One frame's geometry.
struct FrameInspection {
    std::size_t frame = 0;           ///< number within the loop
    std::size_t facing_down = 0;     ///< triangles with negative signed area in plan (x, y)
    /// … of them on a breaking crest (a vertex's foam >= lip_foam), off the shore (no
    /// vertex on a boundary edge inside the border: the waterline is no crest)
    std::size_t lips = 0;
    std::size_t folds = 0;           ///< … the others: defects
    std::size_t degenerate = 0;      ///< triangles of zero area in 3D
    std::size_t slivers = 0;         ///< smallest angle < sliver_angle_deg (3D)
    std::size_t lip_slivers = 0;     ///< … of them on a breaking crest (as for lips)
    std::size_t shore_slivers = 0;   ///< … of them on the shore (a vertex on it): the clip boundary
    double smallest_angle_deg = 0.0; ///< over the non-degenerate triangles (3D)
    /// The same over the triangles neither on a breaking crest nor on the shore; 180
    /// when there are none.
    double smallest_angle_off_lips_deg = 0.0;
    double longest_edge = 0.0;       ///< m (3D)
    double median_edge = 0.0;        ///< m (3D)
    double worst_edge_ratio = 0.0;   ///< the largest edge length over its local spacing
    std::size_t long_edges = 0;      ///< edges longer than long_edge_ratio × local spacing
    /// The fastest vertex from this frame to the next (m/s; the last frame of a whole
    /// loop is compared with the first; 0 for the last frame of a slice).
    double max_speed = 0.0;
    std::size_t fastest_vertex = 0;  ///< its index
};

/// A closed chain of boundary edges (edges used by one triangle).
struct BoundaryLoop {
    std::size_t edges = 0;         ///< edges in the loop
    double length = 0.0;           ///< m, in plan, at the first frame
    std::size_t on_border = 0;     ///< vertices within border_tolerance of the domain rectangle
    double farthest_inside = 0.0;  ///< the largest distance (m) of a vertex inside from the rectangle
};

/// The whole animation: topology once, every frame's geometry, the worst values.
struct MeshInspection {
    std::size_t vertex_count = 0;           ///< per frame
    std::size_t triangle_count = 0;         ///< of the mesh
    std::size_t frame_count = 0;            ///< frames inspected
    std::size_t unreferenced_vertices = 0;  ///< vertices no triangle uses
    std::size_t non_manifold_edges = 0;  ///< edges used by more than two triangles
    std::size_t boundary_edges = 0;      ///< edges used by one triangle
    /// Edges whose loop could not be closed (a boundary through a non-manifold vertex
    /// counts its loops greedily; a chain left open is counted here).
    std::size_t open_boundary_chains = 0;
    std::vector<BoundaryLoop> loops;  ///< longest first
    /// Boundary vertices farther than border_tolerance inside the border at the first
    /// frame: the shore (the water mesh's shoreline, an island's coast)
    std::size_t shore_vertices = 0;
    /// The farthest (m, in plan) a shore vertex moves from its first-frame position
    /// over the frames: 0 when the water's edge holds on its line
    double shore_drift = 0.0;
    double border_min_x = 0.0;  ///< the domain rectangle: the first frame's plan bounds (m)
    double border_min_y = 0.0;  ///< the domain rectangle: the first frame's plan bounds (m)
    double border_max_x = 0.0;  ///< the domain rectangle: the first frame's plan bounds (m)
    double border_max_y = 0.0;  ///< the domain rectangle: the first frame's plan bounds (m)
    std::vector<FrameInspection> frames;  ///< one per frame
    FrameInspection worst;  ///< per field the worst over the frames (frame: the one with most folds)
};

/// Inspects every frame of `animation` (positions z up; foam per frame when present).
/// Throws InputError for inconsistent sizes or an index out of range.
MeshInspection inspect_animation(const MorphAnimationView& animation, const InspectOptions& options = {});

/// The inspection as JSON text (what `wave inspect --json` prints and Python's
/// libwave.inspect returns): the options, the topology, the boundary loops, the worst
/// values and, when `per_frame`, every frame. docs/inspect.md names the keys.
std::string inspection_json(const MeshInspection& inspection, const InspectOptions& options, bool per_frame = true);

}  // namespace wave
