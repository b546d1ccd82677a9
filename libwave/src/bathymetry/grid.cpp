// Bicubic depth queries, statistics and the shared value conversion of the readers.
#include "grid_fill.h"
#include "libwave/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wave {
namespace {

// Catmull–Rom weights (Keys 1981, a = −½) for the nodes −1, 0, 1, 2 at t ∈ [0, 1],
// and their derivatives d/dt.
struct CubicWeights {
    double w[4];
    double dw[4];
};

// The weights alone (depth_at) and with their derivatives (sample_depth): the same
// expressions, so both give the same bits; inlined into the ray tracer's hot queries.
[[gnu::always_inline]] inline void catmull_rom_weights(double t, double (&w)[4]) {
    const double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t3 + 2 * t2 - t);
    w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
    w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
    w[3] = 0.5 * (t3 - t2);
}

[[gnu::always_inline]] inline CubicWeights catmull_rom(double t) {
    CubicWeights c;
    catmull_rom_weights(t, c.w);
    const double t2 = t * t;
    c.dw[0] = 0.5 * (-3 * t2 + 4 * t - 1);
    c.dw[1] = 0.5 * (9 * t2 - 10 * t);
    c.dw[2] = 0.5 * (-9 * t2 + 8 * t + 1);
    c.dw[3] = 0.5 * (3 * t2 - 2 * t);
    return c;
}

// Whether the 4 × 4 nodes round a cell all lie inside the grid (no ghost nodes).
bool interior(const ElevationGrid& g, std::ptrdiff_t cell_x, std::ptrdiff_t cell_y) {
    return cell_x >= 1 && cell_x + 2 < static_cast<std::ptrdiff_t>(g.nx) && cell_y >= 1 &&
           cell_y + 2 < static_cast<std::ptrdiff_t>(g.ny);
}

// Cell index and fraction along one axis, clamping outside positions to the border.
struct AxisPosition {
    std::ptrdiff_t cell;  // left node of the cell, in [0, n − 2]
    double t;             // fraction in [0, 1]
    bool clamped;
};

AxisPosition locate(double coord, double origin, double spacing, std::size_t n) {
    const double u = (coord - origin) / spacing;
    const double last = static_cast<double>(n - 1);
    AxisPosition p{0, 0.0, false};
    double uc = u;
    if (!(u >= 0.0)) {  // also catches NaN
        uc = 0.0;
        p.clamped = true;
    } else if (u > last) {
        uc = last;
        p.clamped = true;
    }
    auto cell = static_cast<std::ptrdiff_t>(std::floor(uc));
    cell = std::min<std::ptrdiff_t>(cell, static_cast<std::ptrdiff_t>(n) - 2);
    p.cell = cell;
    p.t = uc - static_cast<double>(cell);
    return p;
}

// Node value with linear extrapolation one node beyond the border (ghost nodes), so
// that planes are reproduced exactly up to the edge.
double node(const ElevationGrid& g, std::ptrdiff_t i, std::ptrdiff_t j) {
    const auto nx = static_cast<std::ptrdiff_t>(g.nx), ny = static_cast<std::ptrdiff_t>(g.ny);
    auto value = [&](std::ptrdiff_t a, std::ptrdiff_t b) {
        return g.z[static_cast<std::size_t>(b * nx + a)];
    };
    auto extrapolate_i = [&](std::ptrdiff_t jj) {
        if (i < 0) return 2.0 * value(0, jj) - value(1, jj);
        if (i >= nx) return 2.0 * value(nx - 1, jj) - value(nx - 2, jj);
        return value(i, jj);
    };
    if (j < 0) return 2.0 * extrapolate_i(0) - extrapolate_i(1);
    if (j >= ny) return 2.0 * extrapolate_i(ny - 1) - extrapolate_i(ny - 2);
    return extrapolate_i(j);
}

}  // namespace

DepthSample sample_depth(const ElevationGrid& g, double x, double y) noexcept {
    const AxisPosition px = locate(x, g.x0, g.dx, g.nx);
    const AxisPosition py = locate(y, g.y0, g.dy, g.ny);
    const CubicWeights wx = catmull_rom(px.t), wy = catmull_rom(py.t);
    const bool inner = interior(g, px.cell, py.cell);
    double z = 0.0, dz_du = 0.0, dz_dv = 0.0;
    const auto nx = static_cast<std::ptrdiff_t>(g.nx);
    for (int b = 0; b < 4; ++b) {
        double row = 0.0, drow = 0.0;
        if (inner) {  // the branch outside the sums: they unroll
            const double* v = &g.z[static_cast<std::size_t>((py.cell - 1 + b) * nx + px.cell - 1)];
            for (int a = 0; a < 4; ++a) {
                row += wx.w[a] * v[a];
                drow += wx.dw[a] * v[a];
            }
        } else {
            for (int a = 0; a < 4; ++a) {
                const double v = node(g, px.cell - 1 + a, py.cell - 1 + b);
                row += wx.w[a] * v;
                drow += wx.dw[a] * v;
            }
        }
        z += wy.w[b] * row;
        dz_du += wy.w[b] * drow;
        dz_dv += wy.dw[b] * row;
    }
    DepthSample s;
    s.depth = -z;  // depth is minus elevation
    s.dh_dx = px.clamped ? 0.0 : -dz_du / g.dx;
    s.dh_dy = py.clamped ? 0.0 : -dz_dv / g.dy;
    s.inside = !(px.clamped || py.clamped);
    return s;
}

// The value alone, summed in sample_depth's order (the same bits), the 16 nodes read
// directly when the cell is away from the border: the ray searches call it most.
double depth_at(const ElevationGrid& g, double x, double y) noexcept {
    const AxisPosition px = locate(x, g.x0, g.dx, g.nx);
    const AxisPosition py = locate(y, g.y0, g.dy, g.ny);
    double wx[4], wy[4];
    catmull_rom_weights(px.t, wx);
    catmull_rom_weights(py.t, wy);
    const auto nx = static_cast<std::ptrdiff_t>(g.nx);
    const bool inner = interior(g, px.cell, py.cell);
    double z = 0.0;
    for (int b = 0; b < 4; ++b) {
        double row = 0.0;
        if (inner) {
            const double* v = &g.z[static_cast<std::size_t>((py.cell - 1 + b) * nx + px.cell - 1)];
            for (int a = 0; a < 4; ++a) row += wx[a] * v[a];
        } else {
            for (int a = 0; a < 4; ++a) row += wx[a] * node(g, px.cell - 1 + a, py.cell - 1 + b);
        }
        z += wy[b] * row;
    }
    return -z;
}

SeafloorStats seafloor_stats(const Seafloor& s) {
    const ElevationGrid& g = s.grid;
    SeafloorStats st;
    st.nx = g.nx;
    st.ny = g.ny;
    st.x_min = g.x0;
    st.y_min = g.y0;
    st.x_max = g.x_max();
    st.y_max = g.y_max();
    st.dx = g.dx;
    st.dy = g.dy;
    st.nodata_count = s.nodata_count;
    st.mesh_triangles = s.mesh.triangles.size() / 3;
    st.contour_lines = s.contours.size();
    if (g.z.empty()) return st;
    const auto [lo, hi] = std::minmax_element(g.z.begin(), g.z.end());
    st.depth_min = -*hi;
    st.depth_max = -*lo;
    const auto land = std::count_if(g.z.begin(), g.z.end(), [](double z) { return z >= 0.0; });
    st.land_fraction = static_cast<double>(land) / static_cast<double>(g.z.size());
    return st;
}

namespace detail {

void check_grid_size(const std::string& path, std::size_t nx, std::size_t ny,
                     const ReadOptions& options) {
    if (nx < 2 || ny < 2)
        throw InputError(path + ": the grid is empty or degenerate (" + std::to_string(nx) +
                         " x " + std::to_string(ny) + " nodes); at least 2 x 2 are needed");
    if (nx > options.max_nodes / ny)
        throw LimitError(path + ": the grid has " + std::to_string(nx) + " x " +
                         std::to_string(ny) + " nodes, more than the limit of " +
                         std::to_string(options.max_nodes) +
                         " (ReadOptions::max_nodes, scene key /seafloor/max_nodes, CLI --max-nodes)");
}

namespace {
std::size_t checked_nodes(const std::string& path, double n, double extent, double spacing, const ReadOptions& options) {
    if (!(n <= static_cast<double>(options.max_nodes)))  // also NaN and infinity
        throw LimitError(path + ": a grid spacing of " + format_number(spacing) + " m over " + format_number(extent) +
                         " m needs more nodes than the limit of " + std::to_string(options.max_nodes) +
                         " (ReadOptions::max_nodes, scene key /seafloor/max_nodes, CLI --max-nodes; or a coarser --spacing)");
    return static_cast<std::size_t>(n);
}
}  // namespace

std::size_t nodes_along(const std::string& path, double extent, double spacing, std::size_t extra,
                        const ReadOptions& options) {
    return checked_nodes(path, std::floor(extent / spacing) + 1.0 + static_cast<double>(extra), extent, spacing, options);
}

std::size_t nodes_spanning(const std::string& path, double extent, double spacing, const ReadOptions& options) {
    // A ratio a rounding error above a whole number (100 / (100/11)) needs no extra node.
    return checked_nodes(path, std::ceil(extent / spacing * (1.0 - 1e-12)) + 1.0, extent, spacing, options);
}

std::size_t convert_to_elevation(std::vector<double>& values, std::optional<double> nodata,
                                 const std::vector<char>& missing, ValueSign file_sign,
                                 const ReadOptions& o, const std::string& path,
                                 const NodeLocator& where, std::size_t nx) {
    const ValueSign sign = o.sign.value_or(file_sign);
    const double s = sign == ValueSign::elevation ? 1.0 : -1.0;
    std::size_t count = 0;
    for (std::size_t n = 0; n < values.size(); ++n) {
        const double v = values[n];
        const bool is_missing = (!missing.empty() && missing[n]) || (nodata && v == *nodata);
        if (is_missing) {
            if (o.nodata_policy == NodataPolicy::error)
                throw InputError(path + ": " + where(n % nx, n / nx) +
                                 " has no data (NODATA); fill it or read with the 'land' "
                                 "NODATA policy");
            values[n] = o.nodata_elevation;
            ++count;
            continue;
        }
        if (!std::isfinite(v))
            throw InputError(path + ": " + where(n % nx, n / nx) + " holds " + format_number(v) +
                             ", not a finite elevation; mark missing values with the file's NODATA value");
        const double z = s * (v * o.vertical_scale + o.vertical_offset);
        if (!(std::abs(z) <= kMaxElevation))
            throw InputError(path + ": " + where(n % nx, n / nx) + " holds " + format_number(v) + ", an elevation of " +
                             format_number(z) + " m, beyond ±" + format_number(kMaxElevation) +
                             " m; mark missing values with the file's NODATA value (a damaged file reads as huge values)");
        values[n] = z;
    }
    return count;
}

}  // namespace detail

Seafloor seafloor_from_grid(const ElevationGrid& values, const std::vector<char>& missing, const ReadOptions& o,
                            const std::string& name) {
    const std::string& path = name;
    for (const auto& [value, what] : {std::pair{values.x0, "the origin's x"}, std::pair{values.y0, "the origin's y"}})
        if (!std::isfinite(value)) throw InputError(path + ": " + what + " is " + detail::format_number(value) + ", not finite");
    for (const auto& [value, what] : {std::pair{values.dx, "the spacing along x"}, std::pair{values.dy, "the spacing along y"}})
        if (!(value > 0.0 && std::isfinite(value)))
            throw InputError(path + ": " + what + " is " + detail::format_number(value) + " m; it must be > 0");
    detail::check_grid_size(path, values.nx, values.ny, o);
    if (values.z.size() != values.nx * values.ny)
        throw InputError(path + ": " + std::to_string(values.z.size()) + " values for a grid of " + std::to_string(values.nx) +
                         " × " + std::to_string(values.ny) + " nodes");
    if (!missing.empty() && missing.size() != values.z.size())
        throw InputError(path + ": the NODATA mask has " + std::to_string(missing.size()) + " entries for " +
                         std::to_string(values.z.size()) + " nodes");
    Seafloor out;
    out.source = path;
    out.frame = "local metres";
    out.grid = values;
    ElevationGrid& g = out.grid;
    g.x0 *= o.horizontal_scale, g.y0 *= o.horizontal_scale, g.dx *= o.horizontal_scale, g.dy *= o.horizontal_scale;
    const auto where = [&](std::size_t i, std::size_t j) {
        return "node (column " + std::to_string(i) + ", row " + std::to_string(j) + ")";
    };
    out.nodata_count = detail::convert_to_elevation(g.z, o.nodata_value, missing, ValueSign::elevation, o, path, where, g.nx);
    return out;
}

}  // namespace wave
