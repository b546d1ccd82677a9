// Triangle-mesh seafloors (OFF, OBJ, PLY, STL) through CGAL's polygon-soup I/O. The
// mesh is kept for the isobath stage and resampled to a grid for depth queries.
#include "grid_fill.h"
#include "libwave/bathymetry.h"
#include "libwave/errors.h"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace wave {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;

// Writes z of every triangle into the grid nodes its xy projection covers; where
// triangles overlap (overhangs, folded meshes) the highest surface wins.
void rasterise(const SeafloorMesh& m, ElevationGrid& g, std::vector<char>& covered) {
    const double inf = std::numeric_limits<double>::infinity();
    std::fill(g.z.begin(), g.z.end(), -inf);
    for (std::size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
        const double* a = &m.xyz[3 * m.triangles[t]];
        const double* b = &m.xyz[3 * m.triangles[t + 1]];
        const double* c = &m.xyz[3 * m.triangles[t + 2]];
        const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if (std::abs(det) < 1e-300) continue;  // vertical or degenerate: covers no area
        const auto lo_i = static_cast<std::ptrdiff_t>(std::ceil((std::min({a[0], b[0], c[0]}) - g.x0) / g.dx));
        const auto hi_i = static_cast<std::ptrdiff_t>(std::floor((std::max({a[0], b[0], c[0]}) - g.x0) / g.dx));
        const auto lo_j = static_cast<std::ptrdiff_t>(std::ceil((std::min({a[1], b[1], c[1]}) - g.y0) / g.dy));
        const auto hi_j = static_cast<std::ptrdiff_t>(std::floor((std::max({a[1], b[1], c[1]}) - g.y0) / g.dy));
        constexpr double kEdge = -1e-9;  // nodes on shared edges belong to both triangles
        for (auto j = std::max<std::ptrdiff_t>(lo_j, 0); j <= std::min<std::ptrdiff_t>(hi_j, static_cast<std::ptrdiff_t>(g.ny) - 1); ++j) {
            for (auto i = std::max<std::ptrdiff_t>(lo_i, 0); i <= std::min<std::ptrdiff_t>(hi_i, static_cast<std::ptrdiff_t>(g.nx) - 1); ++i) {
                const double x = g.x0 + static_cast<double>(i) * g.dx;
                const double y = g.y0 + static_cast<double>(j) * g.dy;
                const double l1 = ((b[1] - c[1]) * (x - c[0]) + (c[0] - b[0]) * (y - c[1])) / det;
                const double l2 = ((c[1] - a[1]) * (x - c[0]) + (a[0] - c[0]) * (y - c[1])) / det;
                const double l3 = 1.0 - l1 - l2;
                if (l1 < kEdge || l2 < kEdge || l3 < kEdge) continue;
                const double z = l1 * a[2] + l2 * b[2] + l3 * c[2];
                const std::size_t n = static_cast<std::size_t>(j) * g.nx + static_cast<std::size_t>(i);
                g.z[n] = std::max(g.z[n], z);
                covered[n] = 1;
            }
        }
    }
}

}  // namespace

Seafloor read_mesh_file(const std::string& path, const ReadOptions& o) {
    if (!std::filesystem::exists(path)) throw InputError(path + ": file not found");
    std::vector<Kernel::Point_3> points;
    std::vector<std::vector<std::size_t>> polygons;
    if (!CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false)))
        throw InputError(path + ": not a readable OFF/OBJ/PLY/STL triangle mesh");

    const ValueSign sign = o.sign.value_or(ValueSign::elevation);
    const double s = sign == ValueSign::elevation ? 1.0 : -1.0;
    Seafloor out;
    out.source = path;
    out.frame = "local metres (the mesh's own x/y)";
    SeafloorMesh& m = out.mesh;
    m.xyz.reserve(3 * points.size());
    for (std::size_t v = 0; v < points.size(); ++v) {
        const auto& p = points[v];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
            throw InputError(path + ": vertex " + std::to_string(v + 1) + " has a NaN or infinite coordinate");
        m.xyz.insert(m.xyz.end(), {p.x() * o.horizontal_scale, p.y() * o.horizontal_scale,
                                   s * (p.z() * o.vertical_scale + o.vertical_offset)});
    }
    for (std::size_t f = 0; f < polygons.size(); ++f) {
        const auto& poly = polygons[f];
        for (std::size_t v : poly)
            if (v >= points.size())
                throw InputError(path + ": face " + std::to_string(f + 1) + " names vertex " +
                                 std::to_string(v + 1) + " of " + std::to_string(points.size()));
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)  // fan-triangulate polygons
            m.triangles.insert(m.triangles.end(), {static_cast<std::uint32_t>(poly[0]),
                                                   static_cast<std::uint32_t>(poly[k]),
                                                   static_cast<std::uint32_t>(poly[k + 1])});
    }
    if (m.triangles.empty()) throw InputError(path + ": the mesh has no triangles");

    double x_lo = HUGE_VAL, x_hi = -HUGE_VAL, y_lo = HUGE_VAL, y_hi = -HUGE_VAL;
    for (std::size_t v = 0; v < m.xyz.size(); v += 3) {
        x_lo = std::min(x_lo, m.xyz[v]);
        x_hi = std::max(x_hi, m.xyz[v]);
        y_lo = std::min(y_lo, m.xyz[v + 1]);
        y_hi = std::max(y_hi, m.xyz[v + 1]);
    }
    if (!(x_hi > x_lo && y_hi > y_lo))
        throw InputError(path + ": the mesh has no horizontal extent (all vertices on a vertical line or plane)");
    // Default spacing: about one node per mesh vertex over the bounding box.
    const double spacing = o.resample_spacing > 0.0
        ? o.resample_spacing
        : std::sqrt((x_hi - x_lo) * (y_hi - y_lo) / static_cast<double>(points.size()));
    const auto nx = static_cast<std::size_t>(std::floor((x_hi - x_lo) / spacing)) + 1;
    const auto ny = static_cast<std::size_t>(std::floor((y_hi - y_lo) / spacing)) + 1;
    detail::check_grid_size(path, nx, ny, o);
    ElevationGrid& g = out.grid;
    g.nx = nx;
    g.ny = ny;
    g.x0 = x_lo;
    g.y0 = y_lo;
    g.dx = g.dy = spacing;
    g.z.assign(nx * ny, 0.0);
    std::vector<char> covered(nx * ny, 0);
    rasterise(m, g, covered);
    std::vector<char> missing(nx * ny);
    std::transform(covered.begin(), covered.end(), missing.begin(), [](char c) { return c ? 0 : 1; });
    // Values are already elevations: convert only fills the uncovered nodes.
    ReadOptions fill = o;
    fill.sign = ValueSign::elevation;
    fill.vertical_scale = 1.0;
    fill.vertical_offset = 0.0;
    const auto where = [&](std::size_t i, std::size_t j) {
        return "grid node (" + detail::format_number(g.x0 + static_cast<double>(i) * g.dx) + ", " +
               detail::format_number(g.y0 + static_cast<double>(j) * g.dy) + ") is covered by no triangle and";
    };
    out.nodata_count = detail::convert_to_elevation(g.z, std::nullopt, missing, ValueSign::elevation,
                                                    fill, path, where, nx);
    return out;
}

}  // namespace wave
