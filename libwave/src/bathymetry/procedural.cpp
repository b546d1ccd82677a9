// Procedural seafloors: the scenes of the papers and the classic benchmarks.
#include "grid_fill.h"
#include "libwave/bathymetry.h"
#include "libwave/errors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wave {
namespace {

void require(bool ok, const std::string& what) {
    if (!ok) throw InputError(what);
}

// A grid over [x_min, x_max] × [y_min, y_max] with the given spacing, filled by
// elevation(x, y).
template <class Elevation>
ElevationGrid sample_grid(const std::string& name, double x_min, double x_max, double y_min,
                          double y_max, double spacing, Elevation&& elevation) {
    require(spacing > 0.0 && std::isfinite(spacing), name + ": spacing must be > 0 m, got " + detail::format_number(spacing));
    require(x_max > x_min && y_max > y_min, name + ": the domain must have a positive size");
    ElevationGrid g;
    g.nx = static_cast<std::size_t>(std::llround((x_max - x_min) / spacing)) + 1;
    g.ny = static_cast<std::size_t>(std::llround((y_max - y_min) / spacing)) + 1;
    detail::check_grid_size(name, g.nx, g.ny, ReadOptions{});
    g.x0 = x_min;
    g.y0 = y_min;
    g.dx = g.dy = spacing;
    g.z.resize(g.nx * g.ny);
    for (std::size_t j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < g.nx; ++i)
            g.at(i, j) = elevation(x_min + static_cast<double>(i) * spacing,
                                   y_min + static_cast<double>(j) * spacing);
    return g;
}

Seafloor named(std::string source, ElevationGrid grid) {
    Seafloor s;
    s.source = std::move(source);
    s.frame = "local metres";
    s.grid = std::move(grid);
    return s;
}

std::string fmt(double v) { return detail::format_number(v); }

}  // namespace

Seafloor make_planar_beach(const PlanarBeachParams& p) {
    require(p.slope > 0.0, "planar-beach: slope must be > 0, got " + fmt(p.slope));
    require(p.max_depth > 0.0, "planar-beach: max_depth must be > 0 m");
    const double ox = std::cos(p.offshore_angle), oy = std::sin(p.offshore_angle);
    const double cx = 0.5 * p.size_x - ox * p.shore_distance;  // a point on the shoreline
    const double cy = 0.5 * p.size_y - oy * p.shore_distance;
    auto grid = sample_grid("planar-beach", 0.0, p.size_x, 0.0, p.size_y, p.spacing, [&](double x, double y) {
        const double offshore = (x - cx) * ox + (y - cy) * oy;
        return std::clamp(-p.slope * offshore, -p.max_depth, p.land_height);
    });
    return named("planar-beach (slope " + fmt(p.slope) + ", offshore angle " + fmt(p.offshore_angle) + " rad)",
                 std::move(grid));
}

Seafloor make_gonzato_bay(const GonzatoBayParams& p) {
    require(p.slope > 0.0 && p.max_depth > 0.0, "gonzato-bay: slope and max_depth must be > 0");
    require(p.head_y > p.headland_y, "gonzato-bay: head_y must lie inland of headland_y");
    auto grid = sample_grid("gonzato-bay", 0.0, p.size, 0.0, p.size, p.spacing, [&](double x, double y) {
        const double u = (x - 0.5 * p.size) / (0.5 * p.size);  // −1 at a headland, 0 mid-bay
        const double shore_y = p.headland_y + (p.head_y - p.headland_y) * (1.0 - u * u);
        return std::clamp(-p.slope * (shore_y - y), -p.max_depth, p.land_height);
    });
    return named("gonzato-bay (100 m bay, slope " + fmt(p.slope) + ")", std::move(grid));
}

Seafloor make_gonzato_island(const GonzatoIslandParams& p) {
    require(p.semi_axis_x > 0.0 && p.semi_axis_y > 0.0, "gonzato-island: semi-axes must be > 0 m");
    require(p.slope > 0.0 && p.max_depth > 0.0, "gonzato-island: slope and max_depth must be > 0");
    auto grid = sample_grid("gonzato-island", 0.0, p.size, 0.0, p.size, p.spacing, [&](double x, double y) {
        const double ex = (x - p.center_x) / p.semi_axis_x, ey = (y - p.center_y) / p.semi_axis_y;
        const double r = std::sqrt(ex * ex + ey * ey);  // 1 on the shoreline
        return std::clamp(p.slope * p.semi_axis_x * (1.0 - r), -p.max_depth, p.top_height);
    });
    return named("gonzato-island (elliptic island " + fmt(p.semi_axis_x) + " x " + fmt(p.semi_axis_y) + " m)",
                 std::move(grid));
}

Seafloor make_tso_contours(const TsoContoursParams& p) {
    require(p.depths.size() >= 2, "tso-contours: at least two contour depths are needed");
    require(p.size > 0.0, "tso-contours: size must be > 0 m");
    Seafloor s;
    s.source = "tso-contours (depths of Ts'o & Barsky 1987, figure 5; shapes reconstructed)";
    s.frame = "local metres";
    DepthContours& c = s.contours;
    c.offsets.push_back(0);
    const std::size_t lines = p.depths.size();
    constexpr int kPoints = 41;
    for (std::size_t n = 0; n < lines; ++n) {
        // Topmost (first, deepest) at large y; each line a gentle sinusoid whose phase
        // shifts from line to line, so the contours bend differently like a real coast.
        const double base = p.size * (0.92 - 0.84 * static_cast<double>(n) / static_cast<double>(lines - 1));
        const double phase = 0.7 * static_cast<double>(n);
        for (int k = 0; k < kPoints; ++k) {
            const double x = p.size * k / (kPoints - 1);
            c.xy.push_back(x);
            c.xy.push_back(base + p.waviness * std::sin(2.0 * std::numbers::pi * x / p.size + phase));
        }
        c.depth.push_back(p.depths[n]);
        c.closed.push_back(0);
        c.offsets.push_back(c.xy.size() / 2);
    }
    s.grid = grid_from_contours(c, p.spacing);
    return s;
}

Seafloor make_berkhoff_shoal(const BerkhoffShoalParams& p) {
    const double c20 = std::cos(20.0 * std::numbers::pi / 180.0), s20 = std::sin(20.0 * std::numbers::pi / 180.0);
    auto grid = sample_grid("berkhoff-shoal", p.x_min, p.x_max, p.y_min, p.y_max, p.spacing, [&](double x, double y) {
        const double xr = x * c20 - y * s20, yr = x * s20 + y * c20;
        double h = xr < -5.82 ? 0.45 : 0.45 - 0.02 * (5.82 + xr);
        if ((xr / 3.0) * (xr / 3.0) + (yr / 4.0) * (yr / 4.0) <= 1.0)
            h -= -0.3 + 0.5 * std::sqrt(1.0 - (xr / 3.75) * (xr / 3.75) - (yr / 5.0) * (yr / 5.0));
        return -h;
    });
    return named("berkhoff-shoal (Berkhoff, Booy & Radder 1982)", std::move(grid));
}

Seafloor make_conical_island(const ConicalIslandParams& p) {
    require(p.toe_radius > p.crest_radius && p.crest_radius >= 0.0,
            "conical-island: toe_radius must exceed crest_radius >= 0");
    auto grid = sample_grid("conical-island", 0.0, p.size_x, 0.0, p.size_y, p.spacing, [&](double x, double y) {
        const double r = std::hypot(x - p.center_x, y - p.center_y);
        const double rise = std::clamp((p.toe_radius - r) / (p.toe_radius - p.crest_radius), 0.0, 1.0);
        return -p.water_depth + p.height * rise;
    });
    return named("conical-island (Briggs et al. 1995)", std::move(grid));
}

Seafloor make_barred_beach(const BarredBeachParams& p) {
    require(p.offshore_depth > 0.0 && p.shore_x > 0.0, "barred-beach: offshore_depth and shore_x must be > 0");
    require(p.bar_width > 0.0 && p.gap_width >= 0.0, "barred-beach: bar_width must be > 0 and gap_width >= 0");
    const double slope = p.offshore_depth / p.shore_x;
    auto grid = sample_grid("barred-beach", 0.0, p.size_x, 0.0, p.size_y, p.spacing, [&](double x, double y) {
        const double bx = (x - p.bar_x) / p.bar_width, gy = p.gap_width > 0.0 ? (y - p.gap_y) / p.gap_width : 1e9;
        const double bar = p.bar_height * std::exp(-0.5 * bx * bx) * (1.0 - 0.7 * std::exp(-0.5 * gy * gy));
        return std::min(-slope * (p.shore_x - x) + bar, p.land_height);
    });
    return named("barred-beach (slope " + fmt(slope) + ", a bar " + fmt(p.bar_height) + " m high at x = " + fmt(p.bar_x) + " m)",
                 std::move(grid));
}

const std::vector<std::string>& procedural_seafloor_names() {
    static const std::vector<std::string> names{"planar-beach", "gonzato-bay", "gonzato-island", "tso-contours",
                                                "berkhoff-shoal", "conical-island", "barred-beach"};
    return names;
}

Seafloor make_named_seafloor(const std::string& name) {
    if (name == "planar-beach") return make_planar_beach();
    if (name == "gonzato-bay") return make_gonzato_bay();
    if (name == "gonzato-island") return make_gonzato_island();
    if (name == "tso-contours") return make_tso_contours();
    if (name == "berkhoff-shoal") return make_berkhoff_shoal();
    if (name == "conical-island") return make_conical_island();
    if (name == "barred-beach") return make_barred_beach();
    std::string valid;
    for (const auto& n : procedural_seafloor_names()) valid += (valid.empty() ? "" : ", ") + n;
    throw InputError("unknown procedural seafloor '" + name + "'; valid names: " + valid);
}

}  // namespace wave
