/// \file
/// libwave — bathymetry: the seafloor every later stage reads.
///
/// Conventions (docs/conventions.md): SI metres, right-handed, z up. The seafloor is an
/// *elevation* z_b(x, y), negative under water; still water is z = 0; depth
/// h = −z_b; land is h <= 0. Grids are node-registered: node (i, j) sits at
/// (x0 + i·dx, y0 + j·dy), row-major with j = 0 the southernmost row (smallest y).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <span>
#include <vector>

namespace wave {

/// A regular elevation grid (plain data).
struct ElevationGrid {
    std::size_t nx = 0;  ///< nodes along x and y (>= 2 each when valid)
    std::size_t ny = 0;  ///< nodes along x and y (>= 2 each when valid)
    double x0 = 0.0;  ///< position of node (0, 0) (m)
    double y0 = 0.0;  ///< position of node (0, 0) (m)
    double dx = 1.0;  ///< node spacing (m, > 0)
    double dy = 1.0;  ///< node spacing (m, > 0)
    std::vector<double> z;       ///< elevation (m, z up), size nx·ny, index j·nx + i

    double x_max() const noexcept { return x0 + dx * static_cast<double>(nx - 1); }  ///< x of the last column (m)
    double y_max() const noexcept { return y0 + dy * static_cast<double>(ny - 1); }  ///< y of the last row (m)
    double& at(std::size_t i, std::size_t j) { return z[j * nx + i]; }  ///< node (i, j): column i, row j
    double at(std::size_t i, std::size_t j) const { return z[j * nx + i]; }  ///< node (i, j): column i, row j
};

/// A triangle mesh of the seafloor (plain arrays), kept when the source was a mesh so
/// that the isobath stage can slice the original surface rather than its resampling.
struct SeafloorMesh {
    std::vector<double> xyz;              ///< vertex positions, 3 per vertex (m, z up)
    std::vector<std::uint32_t> triangles; ///< 3 vertex indices per triangle
};

/// Depth-tagged polylines (Ts'o's input; also what the isobath stage produces).
/// Polyline p has points offsets[p] .. offsets[p+1]−1 of `xy`.
struct DepthContours {
    std::vector<double> xy;             ///< 2 per point (m)
    std::vector<std::size_t> offsets;   ///< size = polylines + 1, offsets[0] = 0
    std::vector<double> depth;          ///< depth h of each polyline (m, positive down)
    std::vector<std::uint8_t> closed;   ///< 1 if the polyline is a closed ring

    std::size_t size() const noexcept { return depth.size(); }  ///< number of polylines
};

/// A seafloor: always an elevation grid (what depth queries read), plus the source
/// mesh or contours when the input was one, plus a record of where it came from.
struct Seafloor {
    ElevationGrid grid;  ///< what depth queries read (a mesh or contours resampled to it)
    SeafloorMesh mesh;         ///< empty unless read from a mesh file
    DepthContours contours;    ///< empty unless read from contours / Ts'o generator
    std::string source;        ///< file path or generator name with parameters
    std::string frame;         ///< coordinate frame, e.g. "local metres" or the projection used
    std::size_t nodata_count = 0;  ///< grid nodes that had no data (filled per NodataPolicy)
};

// ---------------------------------------------------------------------------------
// Queries: bicubic depth and gradient anywhere (Gonzato §3.3 "cubic interpolation")
// ---------------------------------------------------------------------------------

/// Depth and its horizontal gradient at a point.
struct DepthSample {
    double depth = 0.0;       ///< h (m), positive under water
    double dh_dx = 0.0;       ///< ∂h/∂x (dimensionless)
    double dh_dy = 0.0;       ///< ∂h/∂y
    bool inside = true;       ///< false when (x, y) lies outside the grid (see below)
};

/// Depth and gradient by Catmull–Rom bicubic convolution (Keys 1981, a = −½): it
/// passes through the grid values, is C¹, and reproduces planes and quadratics
/// exactly, so a planar beach has an exact gradient.
/// Outside the grid the position is clamped to the nearest point of the grid's
/// rectangle (the border is extended horizontally): depth is that border depth, the
/// gradient component across the clamped border is 0, and `inside` is false.
/// Precondition: grid has nx, ny >= 2 (every reader and generator guarantees it).
DepthSample sample_depth(const ElevationGrid& grid, double x, double y) noexcept;

/// Depth h (m) alone; same rules as sample_depth.
double depth_at(const ElevationGrid& grid, double x, double y) noexcept;

/// Summary statistics, as `wave seafloor info` prints them.
struct SeafloorStats {
    std::size_t nx = 0;  ///< grid nodes along x
    std::size_t ny = 0;  ///< grid nodes along y
    double x_min = 0;  ///< the grid's extent (m)
    double x_max = 0;  ///< the grid's extent (m)
    double y_min = 0;  ///< the grid's extent (m)
    double y_max = 0;  ///< the grid's extent (m)
    double dx = 0;  ///< node spacing along x (m)
    double dy = 0;  ///< node spacing along y (m)
    double depth_min = 0;  ///< h range over the grid nodes (m)
    double depth_max = 0;  ///< h range over the grid nodes (m)
    double land_fraction = 0;             ///< fraction of nodes with h <= 0
    std::size_t nodata_count = 0;  ///< nodes that had no data
    std::size_t mesh_triangles = 0;  ///< triangles of the source mesh (0 unless read from one)
    std::size_t contour_lines = 0;  ///< polylines of the source contours (0 unless read from them)
};
/// The summary of a seafloor (its grid, depth range, land and NODATA share, source).
SeafloorStats seafloor_stats(const Seafloor& seafloor);

// ---------------------------------------------------------------------------------
// Readers
// ---------------------------------------------------------------------------------

/// Sign convention of the values in a file.
enum class ValueSign {
    elevation,  ///< positive up (ESRI grids, ETOPO, most DEMs)
    depth,      ///< positive down (SWAN .bot, nautical charts)
};

/// How grid nodes without data (NODATA / dry markers) are filled.
enum class NodataPolicy {
    land,   ///< become dry land at `nodata_elevation` (SWAN's −99 means "dry")
    error,  ///< reading fails with an InputError naming the first such node
};

/// Largest |elevation| (m) a reader accepts after scaling: the deepest trench is 11 km,
/// the highest summit 9 km; a value past 100 km is a damaged file or a missing NODATA.
inline constexpr double kMaxElevation = 1e5;

/// Options for read_seafloor. Every value has a default that suits the common case.
struct ReadOptions {
    /// Sign of the stored values. Empty = the format's convention (elevation for GDAL
    /// rasters and meshes, depth for SWAN .bot and contour files).
    std::optional<ValueSign> sign;
    /// Values are converted as metres = value · vertical_scale + vertical_offset before
    /// the sign is applied (e.g. 0.01 for centimetres, or 400 for a 1:400 model).
    double vertical_scale = 1.0;
    double vertical_offset = 0.0;  ///< added after vertical_scale (m)
    /// Horizontal scale applied to x and y (e.g. 400 to bring a 1:400 model to full size).
    double horizontal_scale = 1.0;
    /// Value that marks a missing node, overriding the file's own (GDAL NODATA).
    std::optional<double> nodata_value;
    NodataPolicy nodata_policy = NodataPolicy::land;  ///< what becomes of NODATA nodes
    /// Elevation (m) given to NODATA nodes under NodataPolicy::land.
    double nodata_elevation = 1.0;

    // SWAN .bot (a bare list of numbers): the grid is not in the file.
    std::size_t swan_nx = 0;  ///< nodes per row and rows (required for .bot)
    std::size_t swan_ny = 0;  ///< nodes per row and rows (required for .bot)
    double swan_dx = 0.0;  ///< spacing (m, required; dy = dx if 0)
    double swan_dy = 0.0;  ///< spacing (m, required; dy = dx if 0)
    double swan_x0 = 0.0;  ///< position of the first value
    double swan_y0 = 0.0;  ///< position of the first value

    /// Node spacing (m) when a mesh or contour file is resampled to a grid; 0 = chosen
    /// from the data (mesh: mean vertex spacing; contours: extent / 256).
    double resample_spacing = 0.0;
    /// Refuse grids with more nodes than this (guard rail before allocation).
    std::size_t max_nodes = 100'000'000;
};

/// Reads a seafloor, choosing the reader by the file's extension:
///  * `.bot`                     — SWAN bottom file (needs swan_nx/ny/dx)
///  * `.off .obj .ply .stl`      — triangle mesh (CGAL I/O), kept and resampled to a grid
///  * `.json`                    — depth-tagged contour polylines (see docs/formats.md)
///  * anything else              — a raster through GDAL (ESRI ASCII, GeoTIFF, NetCDF, …);
///    geographic (lon/lat) rasters are reprojected by GDAL to a local azimuthal
///    equidistant frame centred on the grid (named in Seafloor::frame).
/// Throws InputError naming the file and what is wrong (missing, truncated, NaN/Inf
/// value with its row/column, empty, no triangles, non-numeric depth, …).
Seafloor read_seafloor(const std::string& path, const ReadOptions& options = {});

/// A seafloor from values in memory (a NumPy array, a DCC's terrain), validated as the
/// file readers validate theirs: `values` holds nx × ny values, row j (y = y0 + j·dy,
/// south to north) after row, node (0, 0) at (x0, y0) — a node, not a cell's corner: a
/// raster whose values stand for cells starts half a cell in. The values are read as
/// `options` say (sign: elevation unless options.sign says depth; vertical scale and
/// offset; horizontal_scale on x0, y0, dx, dy); nodes equal to options.nodata_value or
/// flagged in `missing` (empty, or one per value) are NODATA, filled per
/// options.nodata_policy. `name` names the source in messages and in Seafloor::source.
/// Throws InputError for a spacing that is not > 0, a non-finite origin or value, a
/// size mismatch, fewer than 2 nodes along an axis; LimitError above max_nodes.
Seafloor seafloor_from_grid(const ElevationGrid& values, const std::vector<char>& missing = {},
                            const ReadOptions& options = {}, const std::string& name = "<grid in memory>");

/// A seafloor from a triangle mesh in memory (3 coordinates per vertex, 3 indices per
/// triangle, counter-clockwise or not), resampled to a grid as read_mesh_file does (its
/// spacing options.resample_spacing, else about one node per vertex; nodes no triangle
/// covers are NODATA), the mesh kept for the isobath stage. Throws InputError for a
/// NaN/Inf coordinate, an index out of range, no triangle, no horizontal extent.
Seafloor seafloor_from_mesh(std::span<const double> xyz, std::span<const std::uint32_t> triangles,
                            const ReadOptions& options = {}, const std::string& name = "<mesh in memory>");

// Individual readers (read_seafloor dispatches to these by extension).
/// A raster through GDAL (ESRI ASCII, GeoTIFF, NetCDF, ...), as read_seafloor reads it.
Seafloor read_raster_gdal(const std::string& path, const ReadOptions& options = {});
/// A SWAN bottom file (.bot): its grid comes from options.swan_nx, swan_ny, swan_dx, ...
Seafloor read_swan_bot(const std::string& path, const ReadOptions& options);
/// A triangle mesh file (.off, .obj, .ply, .stl), kept and resampled to a grid.
Seafloor read_mesh_file(const std::string& path, const ReadOptions& options = {});
/// Depth-tagged contour polylines (.json, docs/formats.md), gridded by grid_from_contours.
Seafloor read_contour_file(const std::string& path, const ReadOptions& options = {});

/// Builds the elevation grid of a contour set: each node lies in the band between its
/// nearest isobath and the nearest isobath of another depth on the opposite side, and
/// its depth is linear in the distances to the two (exact for straight parallel
/// contours); beyond the outermost isobath the depth stays at that isobath's. `spacing` (m) is
/// the node spacing; the grid covers the contours' bounding box. Throws InputError if
/// the set is empty.
ElevationGrid grid_from_contours(const DepthContours& contours, double spacing,
                                 std::size_t max_nodes = 100'000'000);

// ---------------------------------------------------------------------------------
// Procedural seafloors (parameters in metres; each returns a validated Seafloor)
// ---------------------------------------------------------------------------------

/// Planar beach: a straight shoreline; the bottom falls with constant slope offshore
/// and rises with it on land. The sea lies in the direction `offshore_angle` (rad from
/// +x; −π/2 = sea to the south, waves travelling +y). Elevation is clamped to
/// [−max_depth, land_height].
struct PlanarBeachParams {
    double size_x = 200.0;  ///< domain [0, size_x] × [0, size_y]
    double size_y = 200.0;  ///< domain [0, size_x] × [0, size_y]
    double spacing = 1.0;                   ///< node spacing
    double slope = 0.05;                    ///< tan β
    double offshore_angle = -1.5707963267948966;  ///< direction of the sea (rad from +x)
    double shore_distance = 60.0;  ///< shoreline distance from the domain centre, onshore
    double max_depth = 10.0;  ///< deepest water (m)
    double land_height = 2.0;  ///< highest land (m)
};
/// The planar beach of `p`.
Seafloor make_planar_beach(const PlanarBeachParams& p = {});

/// The bay of Gonzato & Le Saëc's figures 9/12: 100 m × 100 m, open sea along y = 0,
/// a parabolic bay whose shoreline runs from headlands at y = headland_y (x = 0 and
/// x = size) to the bay head at y = head_y (x = size/2); depth = slope · (y_shore − y)
/// capped at max_depth.
struct GonzatoBayParams {
    double size = 100.0;     ///< side of the square domain (m)
    double spacing = 0.5;    ///< node spacing (m)
    double headland_y = 55.0;  ///< shoreline y at the headlands (m)
    double head_y = 90.0;      ///< shoreline y at the bay head (m)
    double slope = 0.1;        ///< tan β of the bottom
    double max_depth = 5.0;    ///< deepest water (m)
    double land_height = 2.0;  ///< highest land (m)
};
/// The bay of `p`.
Seafloor make_gonzato_bay(const GonzatoBayParams& p = {});

/// The island of Gonzato & Le Saëc's figure 9: an elliptic island (semi-axes at the
/// shoreline) in a 100 m × 100 m sea of depth max_depth; the bottom rises with
/// `slope` measured along the major axis.
struct GonzatoIslandParams {
    double size = 100.0;   ///< side of the square domain (m)
    double spacing = 0.5;  ///< node spacing (m)
    double center_x = 50.0;  ///< the island's centre (m)
    double center_y = 55.0;  ///< the island's centre (m)
    double semi_axis_x = 15.0;  ///< semi-axis along x at the shoreline (m)
    double semi_axis_y = 10.0;  ///< semi-axis along y at the shoreline (m)
    double slope = 0.15;      ///< tan β along the major axis
    double max_depth = 6.0;   ///< the sea's depth (m)
    double top_height = 3.0;  ///< the island's top (m)
};
/// The island of `p`.
Seafloor make_gonzato_island(const GonzatoIslandParams& p = {});

/// Ts'o–Barsky's contour set (figure 5): ten wavy depth contours across a 50 × 50
/// domain with the caption's depths from top (deep, large y) to bottom. The figure's
/// exact shapes are not in the text; the lines here are our reconstruction (gentle
/// sinusoids), only the depths are the paper's. Keeps the contours and grids them.
struct TsoContoursParams {
    double size = 50.0;     ///< side of the square domain (m)
    double spacing = 0.25;  ///< node spacing of the grid (m)
    std::vector<double> depths{2.0, 1.25, 0.75, 0.5, 0.3, 0.2, 0.1, -0.1, -0.1, 0.0};  ///< the ten contours' depths, top to bottom (m)
    double waviness = 2.0;  ///< amplitude of the contour undulation (m)
};
/// The contour set of `p`, gridded.
Seafloor make_tso_contours(const TsoContoursParams& p = {});

/// Berkhoff, Booy & Radder (1982) elliptic shoal (docs/conventions.md, validation cases): origin
/// at the shoal centre, x along the incident waves, wavemaker at x = −10, walls at
/// y = ±10, domain x ∈ [−10, 12]. Rotated coordinates x' = x cos20° − y sin20°,
/// y' = x sin20° + y cos20°; h = 0.45 for x' < −5.82, else 0.45 − 0.02 (5.82 + x');
/// inside (x'/3)² + (y'/4)² <= 1 the shoal −0.3 + 0.5 √(1 − (x'/3.75)² − (y'/5)²) is
/// subtracted (crest depth ≈ 0.1336 m).
struct BerkhoffShoalParams {
    double spacing = 0.05;  ///< node spacing (m)
    double x_min = -10.0;  ///< the wavemaker (m)
    double x_max = 12.0;   ///< the domain's end (m)
    double y_min = -10.0;  ///< a wall (m)
    double y_max = 10.0;   ///< a wall (m)
};
/// The shoal of `p`.
Seafloor make_berkhoff_shoal(const BerkhoffShoalParams& p = {});

/// Conical island of Briggs et al. (1995), the classic run-up benchmark: a truncated
/// cone (toe radius 3.6 m, crest radius 1.1 m, height 0.625 m, slope 1:4) in water
/// 0.32 m deep, centred in a 25 m × 30 m basin.
struct ConicalIslandParams {
    double size_x = 25.0;   ///< basin length (m)
    double size_y = 30.0;   ///< basin width (m)
    double spacing = 0.05;  ///< node spacing (m)
    double center_x = 12.5;  ///< the cone's centre (m)
    double center_y = 15.0;  ///< the cone's centre (m)
    double toe_radius = 3.6;     ///< radius at the toe (m)
    double crest_radius = 1.1;   ///< radius at the crest (m)
    double height = 0.625;       ///< cone height (m)
    double water_depth = 0.32;   ///< basin depth (m)
};
/// The conical island of `p`.
Seafloor make_conical_island(const ConicalIslandParams& p = {});

/// A plane beach with an offshore bar (a surf-zone case, docs/wave-field.md): waves come
/// from x = 0, the plane slope runs from offshore_depth at x = 0 to the shoreline at
/// x = shore_x and on up the land (at most land_height); a bar of Gaussian section,
/// h −= bar_height · exp(−½((x − bar_x)/bar_width)²), lies along y, cut by a rip channel
/// at y = gap_y where it keeps 30 % of its height (Gaussian in y, gap_width; 0: none).
/// With the defaults a 8 s swell of 1.2 m breaks on the bar (crest ≈ 1.7 m deep),
/// re-forms in the trough behind it (≈ 2.7 m) and breaks again on the beach.
struct BarredBeachParams {
    double size_x = 200.0;        ///< domain [0, size_x] × [0, size_y] (m)
    double size_y = 120.0;        ///< domain [0, size_x] × [0, size_y] (m)
    double spacing = 1.0;         ///< node spacing (m)
    double offshore_depth = 6.0;  ///< depth at x = 0 (m)
    double shore_x = 180.0;       ///< the plane slope's shoreline (m)
    double land_height = 2.0;     ///< highest land (m)
    double bar_x = 70.0;          ///< the bar's crest line (m)
    double bar_height = 2.0;      ///< above the plane slope (m)
    double bar_width = 10.0;      ///< the bar's Gaussian half-width σ (m)
    double gap_y = 80.0;          ///< the rip channel's centre (m)
    double gap_width = 10.0;      ///< its Gaussian half-width σ (m); 0: no channel
};
/// The barred beach of `p`.
Seafloor make_barred_beach(const BarredBeachParams& p = {});

/// How the land and the sea bottom go on beyond a grid's rectangle (the exported
/// seafloor's apron; docs/far-field.md, the terrain beyond the data). Every length 0
/// means: chosen from the grid.
struct TerrainBeyondOptions {
    double relief = 0.0;          ///< height the land rises by beyond the border, and its hills' scale (m); 0: 5 % of the grid's longer side, at least half its highest land
    double rise_distance = 0.0;   ///< distance beyond the border over which the land rises to `relief` (m); 0: half the grid's longer side
    double hill_wavelength = 0.0; ///< the shortest hills' wavelength (m), doubling over 8 octaves; 0: a quarter of the grid's longer side
    std::uint64_t seed = 1;       ///< the hills' directions and phases
};

/// The border profile the terrain beyond a grid is made from (plain data; build it with
/// plan_terrain_beyond): the elevation at each border node counter-clockwise from
/// (x0, y0), the perimeter coordinate s of each, integrals along s of the land's
/// height, the sea's elevation and each one's length, and where the shoreline meets
/// the border.
struct TerrainBeyond {
    double x0 = 0.0;  ///< the grid's rectangle (m): its lowest x
    double y0 = 0.0;  ///< its lowest y (m)
    double x1 = 0.0;  ///< its highest x (m)
    double y1 = 0.0;  ///< its highest y (m)
    std::vector<double> s;         ///< perimeter coordinate of each border node (m), from 0; the loop's length is `perimeter`
    std::vector<double> z;         ///< elevation at each border node (m)
    std::vector<double> land;      ///< ∫ max(z, 0) ds from s = 0 to each node, one more at the loop's end
    std::vector<double> land_len;  ///< ∫ [z >= 0] ds likewise
    std::vector<double> sea;       ///< ∫ min(z, 0) ds likewise
    std::vector<double> sea_len;   ///< ∫ [z < 0] ds likewise
    std::vector<double> shore;     ///< perimeter coordinates where the border's elevation crosses 0 (m)
    double perimeter = 0.0;        ///< the rectangle's perimeter (m)
    TerrainBeyondOptions options;  ///< with every 0 replaced by its value
    double hill_kx[8][3]{};     ///< the hills' wave vectors' x (rad/m), 3 per octave
    double hill_ky[8][3]{};     ///< the hills' wave vectors' y (rad/m)
    double hill_phase[8][3]{};  ///< the hills' phases (rad)
    double range_phase[12]{};   ///< the far ranges' phases (rad), one per harmonic of the azimuth about the grid's centre
};

/// The border profile of `grid` and the resolved options. Precondition: nx, ny >= 2.
TerrainBeyond plan_terrain_beyond(const ElevationGrid& grid, const TerrainBeyondOptions& options = {});

/// The elevation (m) at (x, y) beyond the grid's rectangle, for a mesh whose edges
/// there are about `resolution` m long (hills shorter than 4 edges fade out: the
/// noise stays band-limited for the mesh that draws it). With (s, d) the nearest
/// border point's perimeter coordinate and the distance to it:
///  * on the border (d = 0) it is the border's elevation: the terrain is continuous
///    with the data;
///  * beyond land (z(s) >= 0: h <= 0), the land's mean over a window of ±d/2 along the border
///    (the data's detail fades to its trend), plus `relief` rising over
///    `rise_distance` (smoothstep) with dunes a third of the way and band-limited hills
///    (a sum of sines), coming down to a low coast (the border's height plus a
///    twentieth of the relief and low hills) within max(a quarter of the grid's longer
///    side, d/2), along the border, of where the shoreline meets the border — always
///    above still water (> 0 for d > 0); from twice the grid's longer side out, the land
///    rises on into far ranges whose height grows with d (0.6–4.6 % of d, so they stand
///    at a constant angle seen from the grid) and varies with the azimuth about the
///    grid's centre (ridged harmonics, those finer than four mesh edges left out), so
///    the land's skyline is broken, not a plateau's straight top; none within a tenth
///    of d of the far field's cuts (the lines out from where the shoreline meets the
///    border), full from half of d;
///  * beyond sea (z(s) < 0), the sea's mean elevation over that window (sea bottom stays sea
///    bottom, as deep as the border's water), except near land: there the land goes on
///    over the sea and falls to it over a width growing with d (d/4, at most a tenth of
///    the grid's longer side) and wobbling with the hills, so that the coast beyond a
///    border where the shoreline meets it is not the straight line the far field's skirt
///    ends on; sea feet further than 0.08 of that side from the shore stay sea (< 0).
/// Inside the rectangle (d = 0 there) it is the border value at the nearest border
/// point; callers use the grid inside. Deterministic, no allocation.
double terrain_elevation(const TerrainBeyond& terrain, double x, double y, double resolution) noexcept;

/// Names accepted by make_named_seafloor, in a stable order.
const std::vector<std::string>& procedural_seafloor_names();

/// A procedural seafloor with default parameters, by name (for the CLI and scene
/// files): "planar-beach", "gonzato-bay", "gonzato-island", "tso-contours",
/// "berkhoff-shoal", "conical-island", "barred-beach". Throws InputError listing the
/// valid names.
Seafloor make_named_seafloor(const std::string& name);

}  // namespace wave
