/// \file
/// libwave — surface: water surfaces built once per scene and evaluated per frame.
///
/// Height field (Ts'o & Barsky 1987 §3.2.4, §3.3): the traced wave lists deposit
/// η_i = a_i sin(φ_i − ω_i t) on an m×n grid; the grid values are the control vertices
/// of a uniform bicubic Beta2-spline surface whose tension β2 rises with height.
///
/// Ray strips (Gonzato & Le Saëc §3.3, fig. 11): triangles between consecutive fronts
/// of neighbouring rays, built in an OpenMesh TriMesh with per-vertex properties and
/// handed to the per-frame evaluators as flat arrays.
///
/// Units: SI. Positions are (x, y, z) with z up, in float, 3 per vertex. Time t in s.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/field.h"
#include "libwave/trace.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <limits>
#include <array>
#include <vector>

namespace wave {

/// How a ray leg deposits its wave on the grid nodes.
enum class Footprint {
    bresenham,  ///< the nodes on the leg's Bresenham line, weight 1 (Ts'o's method)
    smooth,     ///< nodes within footprint_radius, Gaussian weight (Ts'o §3.2.4 suggests it)
};

/// Ts'o–Barsky's height field (plan_height_field): the control grid, how rays deposit
/// their waves on it, the Beta2-spline sampling and its tension, and the loop.
struct HeightFieldOptions {
    std::size_t nx = 50;  ///< control vertices over the seafloor's rectangle (>= 2)
    std::size_t ny = 50;  ///< control vertices over the seafloor's rectangle (>= 2)
    Footprint footprint = Footprint::smooth;  ///< how a ray leg deposits its wave
    double footprint_radius = 1.5;  ///< smooth footprint: radius in grid cells (σ = radius / 2)
    int samples_per_span = 8;       ///< spline samples per span and axis (Ts'o: 8)
    /// Tension β2 = tension_per_metre · η at a control vertex with η > 0, 0 in troughs,
    /// at most max_tension: sharper crests, smooth troughs (Ts'o §3.3, figure 9).
    double tension_per_metre = 20.0;
    double max_tension = 30.0;  ///< upper bound of β2
    /// Loop length (s). 0: the least common multiple of the wave periods, which must be
    /// commensurate (ratios of integers up to 1000). > 0: the angular frequencies are
    /// quantised to multiples of 2π / repeat_time (Tessendorf eq. 18) so that any set
    /// of periods repeats exactly after repeat_time.
    double repeat_time = 0.0;
    std::size_t max_vertices = 20'000'000;  ///< guard rail on the sampled surface
};

/// TEXCOORD_0 of points in plan: u = (x − x0) / width, v = 1 − (y − y0) / height over
/// the grid's rectangle (u along +x, v down: glTF's image origin is top-left), 2 floats
/// per point into `texcoords`. Throws InputError when the sizes disagree.
void domain_texcoords(const ElevationGrid& grid, std::span<const double> x, std::span<const double> y,
                      std::span<float> texcoords);

/// Triangles of a row-major grid of nx × ny vertices (2 per cell, counter-clockwise
/// seen from +z): the topology of the height field and of the ocean patch.
std::vector<std::uint32_t> grid_triangles(std::size_t nx, std::size_t ny);

/// Hinsinger, Neyret & Cani's view-dependent sampling (Jeschke §5): a ray from the
/// camera through every `pixel_step`-th pixel of the image, met with the still-water
/// plane z = 0. The camera looks from `position` at `look_at` with z up and no roll.
struct GridCamera {
    std::array<double, 3> position{0.0, -50.0, 20.0};  ///< the camera (m, z up)
    std::array<double, 3> look_at{0.0, 0.0, 0.0};      ///< where it looks (m)
    double vertical_fov_degrees = 50.0;  ///< vertical field of view
    std::size_t image_width = 1024;  ///< pixels
    std::size_t image_height = 768;  ///< pixels
    std::size_t pixel_step = 4;  ///< a grid point every pixel_step-th pixel along both axes
    /// Pixel rows whose rays meet the water further than this (or above the horizon)
    /// are left out (m).
    double max_distance = std::numeric_limits<double>::infinity();
};

/// The sampled still-water points (row-major, `columns` per row, near rows last) and
/// their triangles (counter-clockwise seen from +z). Uniform in screen space: dense
/// near the camera, sparse towards the horizon.
struct CameraGrid {
    std::vector<double> x;  ///< still-water points (m)
    std::vector<double> y;  ///< still-water points (m)
    std::vector<std::uint32_t> triangles;  ///< 3 per triangle
    std::size_t columns = 0;  ///< points per row
    std::size_t rows = 0;     ///< rows
    std::size_t vertex_count() const noexcept { return x.size(); }  ///< points
};

/// Throws InputError naming the value when the camera is at or below the water,
/// looks nowhere, has a field of view outside (0, 170)°, an empty image or step, or
/// when fewer than two pixel rows see the water.
CameraGrid camera_grid(const GridCamera& camera);

// ---------------------------------------------------------------------------------
// Water mesh (CGAL): a graded triangulation of the water, bounded by the shoreline
// ---------------------------------------------------------------------------------

/// Options of mesh_water.
struct WaterMeshOptions {
    /// Smallest angle the refinement aims at (degrees, at most 20.7: CGAL's bound for
    /// which Ruppert–Shewchuk refinement terminates). Angles of the domain itself (a
    /// contour meeting the border obliquely) can stay below it.
    double min_angle_deg = 20.0;
    /// Shoreline rings (islets, ponds) shorter than this are left out (m): features
    /// below the mesh's resolution. 0 = twice the smallest target edge met on the grid.
    double min_ring_length = 0.0;
    std::size_t max_vertices = 20'000'000;  ///< refused (LimitError) before meshing when the estimate exceeds it
    /// Keep water that no path through water joins to the domain's border (hollows
    /// inland below still water). False (the default): they are left out — the sea does
    /// not fill them (land behind a dike is dry, a cut-off lagoon has its own level).
    /// Where no water reaches the border at all (an enclosed basin), every water region
    /// is kept.
    bool inland_water = false;
};

/// Vertices (m) and counter-clockwise triangles of the water mesh; `boundary` marks
/// the vertices on the domain rectangle or the shoreline.
struct WaterMesh {
    std::vector<double> x;  ///< vertices (m)
    std::vector<double> y;  ///< vertices (m)
    std::vector<std::uint32_t> triangles;  ///< 3 per triangle, counter-clockwise seen from above
    std::vector<std::uint8_t> boundary;  ///< per vertex: 1 on the domain rectangle or the shoreline
    std::size_t vertex_count() const noexcept { return x.size(); }  ///< vertices
};

/// The waterline on a water mesh (docs/inspect.md "The waterline"), planned once: where
/// the moved water meets the beach. Its shoreline vertices stand under the sand, so that
/// the mesh's edge (chords between points of the sliced contour, level with the sand) is
/// never drawn, and a trough keeps a film of water over the sand in the swash.
struct WaterlinePlan {
    std::vector<float> depth;           ///< still-water depth at each vertex's rest position (m, ≥ 0)
    std::vector<std::uint32_t> shore;   ///< the shoreline's vertices: on `boundary`, off the seafloor's rectangle
    float under_sand = 0.0f;            ///< how far the shoreline's vertices stand under the sand (m)
    float swash_film = 0.0f;            ///< the least share of the still-water depth a trough leaves
};

/// Plans the waterline of `mesh` over `seafloor` for a train of `amplitude` (m): the
/// shoreline a twentieth of it under the sand, troughs leaving 0.3 of the depth.
WaterlinePlan plan_waterline(const WaterMesh& mesh, const Seafloor& seafloor, double amplitude);

/// Applies the waterline to one frame's moved positions (3 per vertex, the mesh's
/// vertices first; more may follow): each vertex's total depth h + z eased (C¹) into at
/// least swash_film · h, then the shoreline's vertices lowered to −under_sand at most.
void keep_waterline(const WaterlinePlan& plan, std::span<float> positions);

/// The target edge length (m, > 0, finite) at a wet point (x, y).
using EdgeSize = std::function<double(double x, double y)>;

/// The water mesh's sizing for one wave train (the scenes' /surface/water_mesh): the
/// local linear wavelength over `per_wavelength`, the depth taken no shallower than where
/// the train breaks (H∞/γ = 2 A∞ / breaker_index, at least 1 mm), so that the surf zone
/// keeps the breaking depth's resolution up to the shore. The function reads
/// `seafloor`, which must outlive it. Throws InputError unless per_wavelength and
/// breaker_index are > 0 and the train is valid.
EdgeSize wavelength_edge_size(const Seafloor& seafloor, const WaveTrain& train, double per_wavelength,
                              double breaker_index = kBreakerIndex);

/// Constrained Delaunay triangulation of the seafloor's rectangle with the shoreline
/// (h = 0, sliced as extract_isobaths does) as constraints, refined (CGAL Mesh_2) until
/// every wet triangle's longest edge is at most `size` at its centroid and its smallest
/// angle at least min_angle_deg; the dry side is dropped (each region between
/// constraints is wet or dry by the area-weighted depth at its triangles' centroids).
/// The border is exactly the rectangle's straight sides; the shoreline vertices lie
/// on the sliced h = 0 polylines. Deterministic. Throws LimitError when the estimated
/// vertex count (the wet area over the target triangle areas) exceeds max_vertices,
/// InputError when no water is left.
WaterMesh mesh_water(const Seafloor& seafloor, const EdgeSize& size, const WaterMeshOptions& options = {});

// ---------------------------------------------------------------------------------
// The sea skirt (CGAL): the surface continued beyond the domain to the horizon
// ---------------------------------------------------------------------------------

/// A point of the skirt where its size is asked, with its nearest point on the
/// surface's rectangle.
struct SkirtSite {
    double x = 0.0;            ///< the point (m), outside the rectangle
    double y = 0.0;            ///< the point (m)
    double bx = 0.0;           ///< its nearest point on the rectangle (m)
    double by = 0.0;           ///< its nearest point on the rectangle (m)
    double d = 0.0;            ///< the distance between the two (m)
    /// the border's spacing at (bx, by) (m): linear along the border edge that holds it,
    /// between its ends' spacings, each the mean of the two border edges that meet there
    double border_edge = 0.0;
};

/// Target edge length (m, > 0, finite) of the skirt at a site.
using SkirtSize = std::function<double(const SkirtSite& site)>;

/// The scenes' skirt sizing (/surface/far_field): the border's spacing `e` (site.border_edge)
/// growing by 0.3 d to λ/6 over the swell band (swell_wavelengths · λ beyond the border,
/// λ the shortest train's local wavelength at the depth of the nearest border point),
/// then max(e, λ/6) + 0.08 d′ + 0.3 d′² / (d′ + 2 λ) at d′ past the band: the swell
/// fades over about two wavelengths, then edges grow by about a third of the distance.
/// The depth is taken no shallower than `min_depth` (the scenes: the highest train's
/// breaking depth H/γ, as the water mesh's sizing): towards a beach met by the border,
/// λ ∝ √h shrank to nothing at the waterline, and the skirt's sizes jumped between the
/// strip beside it and the quadrant round the shore's corner (edges 3.25 × their
/// neighbours on the breaking beach).
/// Reads `seafloor`, which must outlive it. Throws InputError unless shortest_period,
/// swell_wavelengths and min_depth are > 0.
SkirtSize swell_skirt_size(const Seafloor& seafloor, double shortest_period, double swell_wavelengths, double min_depth = 1e-3);

/// Options of plan_sea_skirt.
struct SeaSkirtOptions {
    double distance = 0.0;  ///< how far the skirt reaches beyond the rectangle (m, > 0): its outer rectangle
    SkirtSize size;         ///< the target edge lengths (required)
    /// Smallest angle the refinement aims at (degrees, in (0, 20.7]); triangles on the
    /// surface's border edges keep those edges (they are never split) and may stay below it.
    double min_angle_deg = 20.0;
    std::size_t max_vertices = 2'000'000;  ///< refused (LimitError) when the refinement would exceed it
    /// The seafloor, continued beyond its grid (depth_at), or none. When given, a border
    /// edge with land a quarter of its length beyond its midpoint is not continued: a
    /// straight shore that is a whole side of the surface's rectangle (a planar beach
    /// meshed up to its waterline) ends the skirt on cuts at its corners. Without it,
    /// the skirt carried the sea on over the land beyond such a shore, and the shore's
    /// vertices were not on the surface's boundary, so the untangling did not hold them.
    const ElevationGrid* seafloor = nullptr;
};

/// A skirt around a surface whose border runs along its bounding rectangle (the water
/// mesh, a height-field grid): triangles from the surface's border edges on the
/// rectangle out to a rectangle `distance` beyond it. Only water is continued: the skirt
/// covers the points whose nearest point on the rectangle lies on a border edge of the
/// surface (or is a corner inside a border chain); where a chain of border edges ends
/// (the shore meets the domain's side), the skirt ends on a straight cut going
/// outwards, perpendicular to that side.
struct SeaSkirt {
    std::size_t surface_vertices = 0;  ///< the surface's vertex count: new vertex i is index surface_vertices + i
    std::vector<double> x;  ///< new vertices (m), all outside the rectangle
    std::vector<double> y;  ///< new vertices (m)
    /// 3 per triangle, counter-clockwise seen from above; indices below
    /// surface_vertices are the surface's own border vertices (shared, never moved).
    std::vector<std::uint32_t> triangles;
    /// 2 per new vertex: the surface's border vertices at the ends of the border edge
    /// that holds its nearest point on the rectangle (the same vertex twice at a corner).
    std::vector<std::uint32_t> anchor;
    std::vector<float> anchor_weight;  ///< per new vertex: the first anchor's share (linear along the edge)
    std::vector<double> distance;      ///< per new vertex: to the rectangle (m)
    std::vector<double> normal_x;      ///< per new vertex: unit direction from its nearest border point
    std::vector<double> normal_y;      ///< per new vertex: unit direction from its nearest border point
    std::vector<double> size;          ///< per new vertex: the target edge length there (m)
    double x0 = 0.0;  ///< the rectangle: the surface vertices' bounding box (m)
    double y0 = 0.0;  ///< the rectangle (m)
    double x1 = 0.0;  ///< the rectangle (m)
    double y1 = 0.0;  ///< the rectangle (m)
    double reach = 0.0;  ///< how far the far rectangle lies beyond it (SeaSkirtOptions::distance, m)
    std::size_t vertex_count() const noexcept { return x.size(); }  ///< new vertices
};

/// The skirt of a surface (x, y its vertices at rest, `triangles` counter-clockwise):
/// a constrained Delaunay triangulation of the outside of its bounding rectangle up to
/// `distance`, with the surface's border edges on the rectangle, the cuts and the outer
/// rectangle as constraints, refined (CGAL Mesh_2, without splitting constrained
/// edges: the cuts and the outer rectangle are pre-split at the target sizes) until each
/// triangle's longest edge is at most `size` at its centroid. A surface with no border
/// edge on its rectangle gets an empty skirt. Deterministic. Throws InputError on bad
/// options or indices, LimitError above max_vertices.
SeaSkirt plan_sea_skirt(std::span<const double> x, std::span<const double> y, std::span<const std::uint32_t> triangles,
                        const SeaSkirtOptions& options);

// ---------------------------------------------------------------------------------
// Subdivision (OpenSubdiv): any triangle surface refined once per scene
// ---------------------------------------------------------------------------------

/// The subdivision scheme of a refinement.
enum class RefineScheme {
    loop,           ///< Loop: triangles stay triangles (4 per level)
    catmull_clark,  ///< Catmull–Clark: each triangle becomes 3 quads, then 4 per level; split into 2 triangles each
};

/// OpenSubdiv refinement of a surface (plan_refinement; the scenes' /refine).
struct RefineOptions {
    RefineScheme scheme = RefineScheme::loop;  ///< Loop or Catmull–Clark
    int level = 1;  ///< uniform refinement levels, 1 … 6 (adaptive: at most 2^level segments per edge)
    /// Adaptive (Loop only): each coarse edge is cut into 1 … 2^level segments — more
    /// where the surface bends (Ts'o's flatness criterion: the angle between its end
    /// normals over sampled frames of the loop, per `max_angle_degrees`) or near the
    /// camera (`near_distance`) — and every face is tessellated on the limit surface
    /// with its edges' rates (OpenSubdiv Bfr), so neighbours share their edge points.
    bool adaptive = false;
    double max_angle_degrees = 4.0;  ///< a segment may turn the normal by this much
    double near_distance = 0.0;      ///< m: full rate within it, falling as 1/distance; 0 = off
    /// Crest sharpness (uniform refinement): edges whose ends stand above still water
    /// get OpenSubdiv edge sharpness crest_sharpness_per_metre · (mean height), at most
    /// max_crest_sharpness — the subdivision counterpart of Ts'o's tension β2 = τ·η
    /// (§3.3). Sharpness is topology in OpenSubdiv: a frame with creases is refined
    /// again (same faces, its own stencils). 0 = off.
    double crest_sharpness_per_metre = 0.0;
    double max_crest_sharpness = 4.0;  ///< upper bound of an edge's sharpness
};

/// Crest creases of one frame (positions 3 per vertex, z up): every edge of the
/// triangles whose two ends are above z = 0, with sharpness per_metre · (z_a + z_b)/2
/// capped at `max`; edges as pairs of vertex indices (lower first, each edge once, in
/// the order first met).
struct Creases {
    std::vector<std::uint32_t> edges;  ///< 2 per crease
    std::vector<float> sharpness;  ///< per crease
};
/// The crest creases of one frame, as Creases describes.
Creases crest_creases(std::span<const float> positions, std::span<const std::uint32_t> triangles, double per_metre,
                      double max);

/// What adaptive refinement looks at: unit normals of the coarse surface at K sampled
/// times (K · vertices · 3 floats), the vertices' rest positions and the camera.
struct AdaptiveCriteria {
    std::span<const float> sample_normals;  ///< K · vertices · 3 unit normals
    std::span<const double> rest_x;  ///< rest positions (m)
    std::span<const double> rest_y;  ///< rest positions (m)
    std::array<double, 3> camera{0.0, 0.0, 0.0};  ///< for near_distance (m)
};

/// The refined topology of a triangle mesh and the stencils that give each refined
/// vertex as a weighted sum of the coarse ones (OpenSubdiv Far::StencilTable, boundary
/// edges and corners kept sharp). Built once; frames only apply the stencils.
struct Refinement {
    std::size_t coarse_vertices = 0;  ///< vertices of the surface refined
    std::size_t fine_vertices = 0;    ///< vertices of the refined mesh
    std::vector<std::uint32_t> triangles;                ///< of the refined mesh, same orientation
    std::vector<std::uint32_t> stencil_offsets;          ///< fine_vertices + 1 (compressed rows)
    std::vector<std::uint32_t> stencil_indices;          ///< coarse vertex of each weight
    std::vector<float> stencil_weights;  ///< weights, by stencil_offsets
    std::size_t triangle_count() const noexcept { return triangles.size() / 3; }  ///< refined triangles
};

/// Triangles a uniform refinement of `coarse_triangles` by `options` makes (Catmull–
/// Clark's quads counted as two), without building it: an upper bound for adaptive
/// refinement. About half as many vertices. Saturates instead of overflowing.
double refined_triangle_estimate(std::size_t coarse_triangles, const RefineOptions& options) noexcept;

/// Throws InputError for a level outside 1 … 6, an index out of range, or a topology
/// OpenSubdiv rejects (non-manifold), and LimitError when the refined mesh would
/// exceed `max_vertices` (naming the level that fits).
Refinement plan_refinement(std::size_t vertex_count, std::span<const std::uint32_t> triangles, const RefineOptions& options,
                           std::size_t max_vertices = 50'000'000, const AdaptiveCriteria* adaptive = nullptr,
                           const Creases* creases = nullptr);

/// fine[i·c + k] = Σ_j w_ij coarse[j·c + k] for c = `components` per vertex (3 for
/// positions, 1 for foam). Parallel over refined vertices; each is computed alone, so
/// the result does not depend on the thread count. Throws InputError on sizes.
void apply_refinement(const Refinement& refinement, std::span<const float> coarse, std::size_t components,
                      std::span<float> fine);
/// apply_refinement for double values.
void apply_refinement(const Refinement& refinement, std::span<const double> coarse, std::size_t components,
                      std::span<double> fine);

/// Least common multiple of periods that are rational multiples of each other (each
/// ratio to the first a fraction p/q with q <= 1000 within 1e-9), or 0 when none exists.
double loop_period(std::span<const double> periods);

/// Everything about the height-field surface that does not depend on time; built once,
/// evaluated per frame by evaluate_height_field.
struct HeightFieldPlan {
    // control grid
    std::size_t nx = 0;  ///< control vertices along x
    std::size_t ny = 0;  ///< control vertices along y
    double x0 = 0;  ///< control vertex (0, 0) (m)
    double y0 = 0;  ///< control vertex (0, 0) (m)
    double dx = 1;  ///< control spacing along x (m)
    double dy = 1;  ///< control spacing along y (m)
    // wave terms per control vertex: node v has terms term_offsets[v] .. term_offsets[v+1]−1,
    // η_v(t) = Σ term_amplitude · sin(term_phase − term_omega · t)
    std::vector<std::size_t> term_offsets;  ///< node v's terms: term_offsets[v] .. term_offsets[v+1]−1
    std::vector<double> term_amplitude;  ///< A of each term (m)
    std::vector<double> term_phase;      ///< its phase (rad)
    std::vector<double> term_omega;      ///< its ω (rad/s)
    // sampled surface: (samples·(nx−1) + 1) × (samples·(ny−1) + 1) vertices, row-major
    int samples_per_span = 8;  ///< spline samples per span and axis
    std::size_t vertex_nx = 0;  ///< sampled vertices along x
    std::size_t vertex_ny = 0;  ///< sampled vertices along y
    std::vector<std::uint32_t> triangles;  ///< 3 indices per triangle, counter-clockwise seen from +z
    double tension_per_metre = 0;  ///< β2 per metre of η
    double max_tension = 0;        ///< upper bound of β2
    double loop_period = 0.0;  ///< s: frame(t) == frame(t + loop_period)

    std::size_t control_count() const noexcept { return nx * ny; }  ///< control vertices
    std::size_t vertex_count() const noexcept { return vertex_nx * vertex_ny; }  ///< sampled vertices
    std::size_t triangle_count() const noexcept { return triangles.size() / 3; }  ///< triangles
};

/// Deposits the traced rays on the control grid (complex mean per train and node, so
/// neighbouring orthogonals of one train do not add up; trains superpose) and builds
/// the sampled topology. Nodes on land (h <= 0) and nodes no ray reached stay at 0.
/// Throws InputError for bad options (naming the field), LimitError above max_vertices,
/// and InputError when the periods are incommensurate and repeat_time is 0.
HeightFieldPlan plan_height_field(const Seafloor& seafloor, const RaySet& rays,
                                  std::span<const WaveTrain> trains,
                                  const HeightFieldOptions& options = {});

/// Control-vertex heights η (m) at time t into `heights` (size control_count()).
void evaluate_control_heights(const HeightFieldPlan& plan, double t, std::span<float> heights);

/// The Beta2-spline surface at time t: control heights into `heights` (scratch, size
/// control_count()), vertex positions into `positions` (size 3·vertex_count()).
/// Tension varies continuously over each patch (Barsky's continuously shaped
/// Beta-splines: corner values blended by the quintic 10u³ − 15u⁴ + 6u⁵). The border
/// uses linearly extrapolated phantom vertices, so the surface spans the whole grid
/// and passes through the border control vertices. Allocates nothing.
void evaluate_height_field(const HeightFieldPlan& plan, double t, std::span<float> heights,
                           std::span<float> positions);

// ---------------------------------------------------------------------------------
// Gonzato's ray strips
// ---------------------------------------------------------------------------------

namespace detail {
struct RayStripTriMesh;  // the OpenMesh TriMesh (surface/ray_strips.cpp)
}

/// The ray-strip surface of one traced train: one vertex per ray per front at its rest
/// position (z = 0), with the ray's state there, and triangles between consecutive
/// fronts. Flat arrays (vertex i = the fronts' point i); the OpenMesh TriMesh with the
/// same vertices, faces and per-vertex properties is built from them where it is asked
/// for (write_ray_strips_ply), so that planning never pays for it.
struct RayStrips {
    std::vector<std::uint32_t> ray;   ///< ray id of each vertex
    std::vector<std::uint32_t> step;  ///< front number of each vertex
    std::vector<double> x;  ///< rest position (m)
    std::vector<double> y;  ///< rest position (m)
    std::vector<double> dir_x;  ///< unit ray direction: the profile's horizontal axis
    std::vector<double> dir_y;  ///< unit ray direction: the profile's horizontal axis
    std::vector<double> phase;              ///< Σ k Δs (rad) along the ray
    std::vector<double> k;          ///< as in FrontSet
    std::vector<double> amplitude;  ///< as in FrontSet
    std::vector<double> depth;      ///< as in FrontSet
    std::vector<double> slope;      ///< as in FrontSet
    std::vector<double> rise;       ///< as in FrontSet
    std::vector<RayFlag> flag;  ///< the ray's state at the vertex
    std::vector<std::uint8_t> caustic;      ///< 1 where rays crossed (FrontSet::caustic)
    std::vector<double> entry_break_phase;  ///< per ray id (FrontSet::entry_break_phase)
    std::vector<std::uint32_t> triangles;   ///< 3 per triangle, counter-clockwise seen from above
    double omega = 0.0;                     ///< ω of the train (rad/s)
    std::size_t degenerate_skipped = 0;     ///< zero-area cells left out (rays meeting on the shore)

    std::size_t vertex_count() const noexcept { return x.size(); }  ///< vertices
    std::size_t triangle_count() const noexcept { return triangles.size() / 3; }  ///< triangles
};

/// Tessellates the fronts (Gonzato fig. 11): between two consecutive fronts, rays
/// present in both are joined, and the stretch between two such rays is zipped by the
/// shorter diagonal, which gives 2 triangles per cell, 3 where a ray was inserted or
/// removed inside it. Crossing rays (caustics) keep their triangles (folded, not cut).
/// Cells of zero area (AGROUND rays meeting on the shore) are left out and counted.
RayStrips build_ray_strips(const FrontSet& fronts);

/// The strips' per-vertex fields at other points, e.g. the water mesh (mesh_water):
/// each interpolated linearly in the strip triangle holding the point (the first by
/// index where strips overlap at caustics) — phase, k and direction from its corners
/// that carry a wave (k > 0), the direction renormalised; ray, step and
/// flag from the triangle's vertex of largest weight, caustic if any of its three is.
/// Points off the strips keep still water: amplitude and k 0, the seafloor's depth.
/// The result's triangles are `triangles`. Parallel;
/// independent of the thread count.
RayStrips resample_ray_strips(const RayStrips& strips, const Seafloor& seafloor, std::span<const double> x,
                              std::span<const double> y, std::span<const std::uint32_t> triangles);

/// Fills what the rays cannot give on resampled strips (resample_ray_strips; the
/// triangles are the water mesh's) with the field's wave (docs/wave-field.md, "Where
/// the rays leave off"):
/// * gaps: vertices no strip covers but under water (k = 0, depth > 0), along the
///   domain's sides where the rays diverge, in shadows;
/// * tears: where the first strip by index switches from one layer of rays to another
///   (rays that wrapped round an island over rays that did not), neighbours' phases
///   differ by more than k̄|e| + π/4; every vertex within a local wavelength of such an
///   edge (along the mesh) is bridged.
/// They take amplitude |η̂|, k by the dispersion relation at their depth, slope and rise
/// from the seafloor, phase arg η̂ plus an offset, and a direction. The offset is the
/// rays' φ − arg η̂ (unwrapped along the mesh between rays' vertices) continued over
/// them by a screened Laplace equation (a sparse Cholesky solve), so that crests run on
/// across every seam; far from any ray (screening length about two wavelengths) it
/// tends to the offsets' circular mean. The direction is the rays' continued the same
/// way towards the field's ∇ arg η̂. Vertices outside the field's water stay as they
/// are. Returns how many it filled.
std::size_t fill_strip_gaps(const WaveField& field, const Seafloor& seafloor, RayStrips& strips);

/// The triangles touching each vertex, in increasing order (compressed rows: vertex v's
/// are faces[offsets[v] .. offsets[v + 1])), built once per topology.
struct VertexFaces {
    std::vector<std::uint32_t> offsets;  ///< vertex_count + 1
    std::vector<std::uint32_t> faces;    ///< triangle indices, grouped by vertex
};
/// The triangles touching each of `vertex_count` vertices.
VertexFaces vertex_faces(std::size_t vertex_count, std::span<const std::uint32_t> triangles);

/// Binary little-endian PLY of the strips at rest, written by OpenMesh with the
/// per-vertex properties as PLY vertex properties: ray, step (int); phase, k, omega,
/// amplitude, depth, slope, rise, dir_x, dir_y (double); flag (uchar: 0 alive, 1 flat,
/// 2 aground), caustic (uchar). The strips are built into an OpenMesh TriMesh for it.
/// Atomic write; throws RuntimeError if the file cannot be written, InternalError if
/// OpenMesh rejects a face (a non-manifold strip: a bug).
void write_ray_strips_ply(const RayStrips& strips, const std::string& path);

}  // namespace wave
