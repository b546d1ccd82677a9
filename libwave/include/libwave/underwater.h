/// \file
/// libwave — underwater light: the caustic pattern that a frame's surface focuses onto
/// the seafloor (Tessendorf 2001, §5.2), written into caller-owned maps.
///
/// Sunlight is a parallel beam. Each surface triangle facing the sun intercepts the
/// flux I₀ / l_z · (its vector area · l) (l: unit vector towards the sun, I₀: the sun's
/// irradiance on a horizontal plane above the water). At each vertex the beam is
/// refracted (Snell, air → water) by the vertex normal, weighted by the Fresnel
/// transmissivity T and attenuated by e^{−c·s} over its path s to the seafloor. The
/// triangle's flux, times the mean of its vertices' weights, is spread uniformly over
/// the triangle its three refracted rays draw on the seafloor (its footprint) and
/// summed, with the exact overlap of footprint and pixel, into a map in plan. The flux
/// of every bundle is conserved: where footprints shrink the floor is bright (the
/// caustic lines), where they spread it is dim, and a footprint that collapses to a
/// line still carries its whole flux (docs/underwater.md).
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/physics.h"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace wave {

/// Named waters by how fast they dim sunlight with path length: broadband
/// approximations (blue–green light, ~490 nm) of Jerlov's optical water types, from
/// the clearest open ocean to turbid harbour water (docs/underwater.md gives the values).
enum class WaterType {
    clear_ocean,     ///< "clear-ocean": c = 0.03/m, like Jerlov's I (the clearest open ocean)
    ocean,           ///< "ocean": c = 0.08/m, like Jerlov's III
    coastal,         ///< "coastal" (the scenes' default): c = 0.15/m, like Jerlov's coastal 1
    turbid_coastal,  ///< "turbid-coastal": c = 0.35/m, like Jerlov's coastal 5
    harbour,         ///< "harbour": c = 0.7/m, like Jerlov's coastal 9
};

/// c (1/m) of a named water (docs/underwater.md).
double water_attenuation(WaterType type) noexcept;

/// "clear-ocean", "ocean", "coastal", "turbid-coastal", "harbour"; and back
/// (InputError naming the accepted names).
const char* water_type_name(WaterType type) noexcept;
/// The water type spelt `name`; InputError naming `where` and the accepted names.
WaterType parse_water_type(const std::string& name, const std::string& where);

/// The sun, the water and the map of plan_caustics (the scenes' /underwater).
struct CausticOptions {
    /// Towards the sun (any length > 0; z > 0: the sun above the horizon).
    std::array<double, 3> sun{0.0, 0.0, 1.0};
    double surface_irradiance = 1.0;  ///< I₀: on a horizontal plane above the water (any unit)
    double water_index = kWaterRefractiveIndex;  ///< n of water (air is 1)
    double attenuation = 0.15;  ///< c (1/m) along the refracted path (WaterType::coastal)
    /// Map pixels along x and y: the map covers the seafloor grid's rectangle, row 0
    /// at its largest y (an image's top: the same frame as the animation's TEXCOORD_0).
    std::size_t width = 512;   ///< map pixels along x
    std::size_t height = 512;  ///< map pixels along y
    /// Beyond the surface's rectangle the water is taken as flat: the floor near the
    /// up-sun borders, whose light entered beyond them, gets flat water's irradiance
    /// instead of none.
    bool flat_water_beyond = true;
};

/// Once per seafloor and options: a copy of the seafloor grid, the map's frame, and a
/// bound on the seafloor's slope for the ray–floor search. InputError for bad options
/// (sun at or below the horizon, non-positive index, negative attenuation, a map side
/// of 0 or above 16 384, a grid of fewer than 2 × 2 nodes).
struct CausticPlan {
    CausticOptions options;  ///< as planned
    ElevationGrid floor;     ///< a copy of the seafloor grid
    double x0 = 0.0;     ///< x of pixel (0, 0)'s outer corner (m)
    double y_top = 0.0;  ///< y of pixel (0, 0)'s outer corner: the map's top (m)
    double pixel_x = 1.0;  ///< pixel size (m)
    double pixel_y = 1.0;  ///< pixel size (m)
    double per_pixel_x = 1.0;  ///< pixels per metre along x
    double per_pixel_y = 1.0;  ///< pixels per metre along y
    double max_slope = 0.0;                ///< |∇z| bound of the floor (for the search)
    static constexpr std::size_t kSlopeTile = 8;  ///< grid cells a side of the search's slope tiles
    std::size_t slope_tiles_x = 0;  ///< slope tiles along x
    std::size_t slope_tiles_y = 0;  ///< slope tiles along y
    /// The search's local bounds: |∇z| over each tile of kSlopeTile × kSlopeTile grid
    /// cells and its eight neighbours (a step that moves at most a tile in plan stays
    /// within them), row-major, slope_tiles_x per row.
    std::vector<double> tile_slope;
    double max_depth = 0.0;                ///< the floor's greatest depth (m)
    bool flat = false;                     ///< every node at one elevation: rays meet the floor in closed form
    /// The floor is a level in the water (plan_sun_volume's): a surface vertex at or
    /// below it passes no light (there the level is in the air).
    bool level_in_water = false;
    std::array<double, 3> sun{};           ///< unit, towards the sun
};
/// The caustic plan of a seafloor grid, as CausticPlan describes.
CausticPlan plan_caustics(const ElevationGrid& seafloor, const CausticOptions& options);

/// Once per triangle list (a surface's topology, the same in every frame of an
/// animation): every edge once, with the triangles on its two sides, so that a frame
/// walks each edge once rather than once per triangle. An edge that a third triangle
/// shares, or that two triangles walk the same way (one turned over), is listed again
/// for each such triangle. InputError for a list that is not whole triangles or an
/// index out of range.
struct CausticMesh {
    static constexpr std::uint32_t kNone = 0xffffffffu;  ///< no triangle on that side
    std::size_t vertex_count = 0;          ///< the vertices the triangles index
    std::vector<std::uint32_t> triangles;  ///< as planned, 3 per triangle
    /// 4 per edge: its vertices a and b, the triangle that walks a → b, the one that
    /// walks b → a (kNone on the border).
    std::vector<std::uint32_t> edges;
};
/// The edges of `triangles` over `vertex_count` vertices, as CausticMesh describes.
CausticMesh plan_caustic_mesh(std::span<const std::uint32_t> triangles, std::size_t vertex_count);

/// Per-frame scratch (per-vertex hits and weights, per-triangle densities, each band's
/// items), kept by a caller that evaluates frame after frame so that frames after the
/// first allocate nothing.
struct CausticWorkspace {
    std::vector<double> hit;     ///< 2 per vertex: the refracted ray's floor point, map pixels
    std::vector<double> weight;  ///< per vertex: T · e^{−c·s}
    /// Per triangle: −flux / footprint area, spread by its edges (0 when its flux goes
    /// whole into one pixel, or it carries none).
    std::vector<double> density;
    std::vector<double> direct;  ///< per triangle: the flux put whole into one pixel (else 0)
    std::vector<std::uint32_t> direct_pixel;  ///< per triangle with `direct`: that pixel's index in the map
    std::vector<std::uint32_t> item_bands;    ///< 2 per item (edges, then triangles): the first and last row band it reaches
    std::vector<std::uint32_t> chunk_counts;  ///< per chunk of items and band: items filed
    std::vector<std::uint32_t> band_offsets;  ///< per row band: its items' start in band_items
    std::vector<std::uint32_t> band_items;    ///< item indices, by band, each band in item order
    std::vector<float> level_map;             ///< evaluate_sun_volume: one level's map
};

/// The irradiance per unit plan area on the seafloor (same unit as I₀), width · height
/// floats, row-major from the top row, for one frame of a surface: positions and unit
/// normals 3 floats per vertex (m, z up, the still water at z = 0) of the planned mesh's
/// vertices, its triangles counter-clockwise seen from above. Flat water over a flat floor
/// of depth h gives T(θᵢ) · I₀ · e^{−c·h / cos θₜ} everywhere its light reaches. Light
/// enters only through the given surface (a map pixel whose light would come from
/// beyond it stays dark, unless flat_water_beyond), triangles facing away from the sun
/// pass none, and the water's own shadow (a crest shading a trough) is not traced. The
/// same bits for any thread count. InputError on mismatched sizes.
void evaluate_caustics(const CausticPlan& plan, const CausticMesh& mesh, std::span<const float> positions,
                       std::span<const float> normals, std::span<float> irradiance, CausticWorkspace* workspace = nullptr);

/// The same for a triangle list given with the frame (its mesh planned on each call).
void evaluate_caustics(const CausticPlan& plan, std::span<const float> positions, std::span<const float> normals,
                       std::span<const std::uint32_t> triangles, std::span<float> irradiance,
                       CausticWorkspace* workspace = nullptr);

/// Sunlight in the water (sunbeams, Tessendorf 2001 §5.2): the irradiance E / I₀ of the
/// refracted sun beam at each voxel of a box over the seafloor's rectangle, from its
/// deepest lit level up to the still water. Each level is a caustic map on a level
/// plane at the voxels' centre height, traced through the frame's surface exactly as
/// on the seafloor (flux conserved through every bundle, Fresnel, e^{−c·s} over the
/// path to the level): where the surface focuses light the beams are bright, and they
/// lean along the refracted sun. A voxel whose centre lies under the seafloor is dark,
/// and surface vertices at or below a level light none of it (a trough above the level
/// is air there). The floor casts no shadow through the water. A renderer's single
/// scattering towards the eye, b · p(θ) · E per unit length, gives the sunbeams
/// (docs/underwater.md: the Blender add-on's volume material).
struct SunVolumeOptions {
    std::size_t nx = 128;  ///< voxels along x (over the seafloor grid's rectangle)
    std::size_t ny = 128;  ///< voxels along y
    std::size_t nz = 32;   ///< voxels along z
    /// The volume reaches down to the floor's deepest point, or to where the beam has
    /// fallen below this share of I₀ on its vertical path, whichever is shallower.
    double darkest = 1e-3;
};

/// The sun's beam under flat water: the unit direction it travels in (z < 0), for a
/// direction towards the sun of any length with z > 0 and the water's index.
std::array<double, 3> refracted_beam(const std::array<double, 3>& sun, double water_index) noexcept;

/// Once per seafloor, caustic plan and options: the voxels' frame and a flat-level
/// caustic plan per level (the caustic plan's sun, water and flat_water_beyond; maps
/// of nx × ny). InputError for a side of 0 or above 4 096 voxels or `darkest` not in
/// (0, 1).
struct SunVolumePlan {
    std::size_t nx = 0;  ///< voxels along x
    std::size_t ny = 0;  ///< voxels along y
    std::size_t nz = 0;  ///< voxels along z
    double x0 = 0.0;  ///< the outer corner of voxel (0, 0, 0) (m): the rectangle's least x
    double y0 = 0.0;  ///< … its least y
    double z0 = 0.0;  ///< … the volume's bottom
    double dx = 1.0;  ///< voxel size (m)
    double dy = 1.0;  ///< voxel size (m)
    double dz = 1.0;  ///< voxel size (m)
    std::vector<CausticPlan> levels;  ///< per level k: a flat floor at z0 + (k + ½) dz, its light cut by the level
    /// Per column (j · nx + i): the first level above the seafloor at the column's centre.
    std::vector<std::uint32_t> first_wet;
};
/// The sunbeam volume's plan over the floor of `caustics`.
SunVolumePlan plan_sun_volume(const CausticPlan& caustics, const SunVolumeOptions& options);

/// A frame's sunlight, nx · ny · nz floats (voxel (i, j, k) at (k · ny + j) · nx + i: x
/// fastest, y up from the rectangle's least y, z up from the bottom), from the frame's
/// surface as evaluate_caustics takes it. Flat water gives T · I₀ · e^{−c·d / cos θₜ} at
/// every wet voxel of centre depth d. The same bits for any thread count. InputError
/// on mismatched sizes.
void evaluate_sun_volume(const SunVolumePlan& plan, const CausticMesh& mesh, std::span<const float> positions,
                         std::span<const float> normals, std::span<float> light, CausticWorkspace* workspace = nullptr);

/// A map as a 16-bit greyscale PNG (linear: pixel value 65 535 · E / full_scale,
/// clamped), what the caustic sequence beside an animation holds.
std::string caustic_png(std::span<const float> irradiance, std::size_t width, std::size_t height, double full_scale);

}  // namespace wave
