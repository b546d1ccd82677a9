/// \file
/// libwave — isobath: depth contours of the seafloor (CGAL) and exact ray–contour
/// intersection, the geometric core of Ts'o–Barsky wave tracing (§3.2.2).
///
/// Units: metres. Depths are positive down (h = −z_b); the shoreline is h = 0.
/// No CGAL type appears here: contours leave the stage as plain arrays.
#pragma once

#include "libwave/bathymetry.h"

#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace wave {

/// Which depths to contour.
/// Most depth levels extract_isobaths slices (each is a pass over the seafloor).
inline constexpr double kMaxIsobathLevels = 10'000;

/// Options of extract_isobaths (the scenes' /isobaths).
struct IsobathOptions {
    /// Explicit depth levels (m, positive down). When empty, the levels are the
    /// positive multiples of `spacing` strictly inside the seafloor's depth range
    /// (0.25 m: the scenes' /isobaths/spacing default).
    std::vector<double> levels;
    double spacing = 0.25;  ///< m between levels when `levels` is empty
    /// Add the shoreline h = 0 as a level (if the seafloor reaches land).
    bool include_shoreline = true;
    /// Ts'o smooths digitised contours with a uniform cubic Beta-spline (bias β1,
    /// tension β2); 0 samples per segment = no smoothing.
    int smoothing_samples = 0;
    double smoothing_beta1 = 1.0;  ///< bias β1 > 0 (1 = unbiased)
    double smoothing_beta2 = 0.0;  ///< tension β2 >= 0 (0 = uniform cubic B-spline)
};

/// Slices the seafloor at each level with horizontal planes
/// (CGAL::Polygon_mesh_slicer) — the source mesh when the seafloor came from one,
/// otherwise the grid split into two triangles per cell — into depth-tagged
/// polylines, chained, open or closed (a closed ring does not repeat its first point).
/// Throws InputError for a level outside the seafloor's depth range (the message
/// gives the range), a non-finite level, or neither levels nor a spacing > 0.
DepthContours extract_isobaths(const Seafloor& seafloor, const IsobathOptions& options = {});

/// Smooths each polyline with a uniform cubic Beta-spline (Barsky's β1, β2) using the
/// vertices as control points, sampled `samples` times per span; the end points of
/// open polylines are kept (doubled end vertices). Depths are unchanged.
DepthContours smooth_isobaths(const DepthContours& contours, int samples, double beta1 = 1.0,
                              double beta2 = 0.0);

/// The contour file format read by read_contour_file (docs/formats.md): a JSON
/// document {"sign": "depth", "contours": [{"depth", "points", "closed"}, …]}.
std::string contours_to_json(const DepthContours& contours);

/// Wavefront OBJ polylines ("v x y z" at z = −depth, "l i j k …") for viewing the
/// contours in a DCC tool; z up as everywhere in libwave (OBJ has no axis convention).
std::string contours_to_obj(const DepthContours& contours);

/// Where a ray first meets an isobath.
struct IsobathCrossing {
    double x = 0.0;  ///< crossing point (m), rounded from the exact point
    double y = 0.0;  ///< crossing point (m), rounded from the exact point
    double distance = 0.0;       ///< along the ray from its origin (m)
    std::size_t contour = 0;     ///< polyline index in the DepthContours
    std::size_t segment = 0;     ///< segment index within all segments (see IsobathIndex)
    double tangent_x = 0.0;  ///< unit direction of the crossed segment
    double tangent_y = 0.0;  ///< unit direction of the crossed segment
    double depth = 0.0;          ///< the isobath's depth (m)
    bool at_vertex = false;      ///< the ray passes exactly through a polyline vertex
    bool collinear = false;      ///< the ray runs along the segment (tangency / overlap)
};

/// A ray query: origin, direction (need not be unit), the range of distances searched,
/// and what to ignore: a whole contour, or the segment the ray stands on after a
/// crossing (the rounded crossing point may lie a hair off it).
struct CrossingQuery {
    double x = 0.0;   ///< origin (m)
    double y = 0.0;   ///< origin (m)
    double dx = 1.0;  ///< direction
    double dy = 0.0;  ///< direction
    double max_distance = std::numeric_limits<double>::infinity();  ///< crossings farther are not reported (m)
    double min_distance = 0.0;  ///< crossings at distance <= this are ignored (m)
    std::size_t skip_contour = std::numeric_limits<std::size_t>::max();  ///< a contour to ignore (max: none)
    std::size_t skip_segment = std::numeric_limits<std::size_t>::max();  ///< a segment to ignore (max: none)
};

/// Spatial index (an AABB tree) over all contour segments, built once per scene and
/// queried by every ray. Intersections are computed with CGAL's exact-predicates,
/// exact-constructions kernel, so a ray through a vertex, along a segment, or grazing
/// a contour gets the true nearest crossing; only the reported point is rounded.
class IsobathIndex {
public:
    explicit IsobathIndex(const DepthContours& contours);  ///< indexes every segment of `contours` (copied)
    ~IsobathIndex();  ///< frees the tree
    IsobathIndex(IsobathIndex&&) noexcept;             ///< moves the tree
    IsobathIndex& operator=(IsobathIndex&&) noexcept;  ///< moves the tree
    IsobathIndex(const IsobathIndex&) = delete;  ///< not copyable
    IsobathIndex& operator=(const IsobathIndex&) = delete;  ///< not copyable

    /// Nearest crossing ahead of the ray (distance > 0 and <= max_distance), or none.
    /// Thread-safe: queries do not modify the index.
    std::optional<IsobathCrossing> first_crossing(const CrossingQuery& query) const;

    std::size_t segment_count() const noexcept;  ///< segments indexed
    /// The segments adjacent to `segment` along its polyline (the same segment where
    /// there is none), for skipping both sides of a vertex crossing.
    std::size_t previous_segment(std::size_t segment) const noexcept;
    std::size_t next_segment(std::size_t segment) const noexcept;  ///< the segment after, along the polyline

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace wave
