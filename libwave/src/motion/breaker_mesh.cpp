// The water mesh graded down over the band where the breakers break (motion.h,
// surf_zone_edge_size): a tube the mesh can carry needs a mesh finer than the tube.
// docs/inspect.md, "The water mesh".
#include "libwave/errors.h"
#include "libwave/motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace wave {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

// A value per cell of a regular grid over the seafloor's rectangle, read bilinearly.
struct SizeRaster {
    double x0 = 0.0, y0 = 0.0, h = 1.0;
    std::size_t nx = 0, ny = 0;
    std::vector<double> v;
    double& at(std::size_t i, std::size_t j) { return v[j * nx + i]; }
    double read(double x, double y) const noexcept {
        const double fx = std::clamp((x - x0) / h, 0.0, static_cast<double>(nx - 1));
        const double fy = std::clamp((y - y0) / h, 0.0, static_cast<double>(ny - 1));
        const std::size_t i = std::min(static_cast<std::size_t>(fx), nx - 2), j = std::min(static_cast<std::size_t>(fy), ny - 2);
        const double wx = fx - static_cast<double>(i), wy = fy - static_cast<double>(j);
        const double* r0 = &v[j * nx + i];
        const double* r1 = r0 + nx;
        return (1.0 - wy) * ((1.0 - wx) * r0[0] + wx * r0[1]) + wy * ((1.0 - wx) * r1[0] + wx * r1[1]);
    }
};

}  // namespace

bool in_breaking_band(const JeschkeMotionPlan& p, std::size_t v, double margin_wavelengths) noexcept {
    if (!(p.width[v] > 0.0f) || !std::isfinite(p.break_phase[v])) return false;
    const double reach = two_pi * (p.variation + margin_wavelengths);
    const double first = static_cast<double>(p.break_phase[v]) - reach;
    const double last = std::min(static_cast<double>(p.end_phase[v]),
                                 static_cast<double>(p.break_phase[v]) + static_cast<double>(p.breaking_length[v]) + reach);
    return p.phase[v] >= first && p.phase[v] <= last;
}

EdgeSize surf_zone_edge_size(EdgeSize size, const JeschkeMotionPlan& plan, const ElevationGrid& seafloor, const SurfZoneMesh& o) {
    if (!size) throw InputError("surf zone mesh: no size function");
    if (!(o.height_fraction >= 0.0 && o.height_fraction <= 1.0))
        throw InputError("surf zone mesh: height_fraction must be in [0, 1], got " + std::to_string(o.height_fraction));
    if (!(o.min_edge > 0.0) || !(o.grade > 0.0) || !(o.margin_wavelengths >= 0.0) || !std::isfinite(o.min_edge + o.grade + o.margin_wavelengths))
        throw InputError("surf zone mesh: min_edge and grade must be > 0 and margin_wavelengths ≥ 0");
    if (o.height_fraction == 0.0 || plan.vertex_count() == 0) return size;
    // The band's vertices and their target edges, fraction × H (H = scale / 5).
    double finest = std::numeric_limits<double>::infinity();
    std::vector<std::size_t> band;
    for (std::size_t v = 0; v < plan.vertex_count(); ++v)
        if (in_breaking_band(plan, v, o.margin_wavelengths)) {
            band.push_back(v);
            finest = std::min(finest, std::max(o.min_edge, o.height_fraction * plan.scale[v] / 5.0));
        }
    if (band.empty()) return size;
    SizeRaster r;
    const double wx = seafloor.x_max() - seafloor.x0, wy = seafloor.y_max() - seafloor.y0;
    r.h = std::max(2.0 * finest, std::sqrt(wx * wy / 4e6));  // at most ~4 M cells
    r.x0 = seafloor.x0, r.y0 = seafloor.y0;
    r.nx = static_cast<std::size_t>(std::ceil(wx / r.h)) + 2, r.ny = static_cast<std::size_t>(std::ceil(wy / r.h)) + 2;
    constexpr double far = 1e9;
    r.v.assign(r.nx * r.ny, far);
    // Each band vertex holds its target over a disc of a tenth of its wavelength (the
    // strips' rays lie a few metres apart), at least two cells.
    for (const std::size_t v : band) {
        const double target = std::max(o.min_edge, o.height_fraction * plan.scale[v] / 5.0);
        const double radius = std::max(0.1 * plan.width[v], 2.0 * r.h);
        const double cx = (plan.x[v] - r.x0) / r.h, cy = (plan.y[v] - r.y0) / r.h, cr = radius / r.h;
        const long i0 = std::max(0L, static_cast<long>(std::floor(cx - cr))), i1 = std::min(static_cast<long>(r.nx) - 1, static_cast<long>(std::ceil(cx + cr)));
        const long j0 = std::max(0L, static_cast<long>(std::floor(cy - cr))), j1 = std::min(static_cast<long>(r.ny) - 1, static_cast<long>(std::ceil(cy + cr)));
        for (long j = j0; j <= j1; ++j)
            for (long i = i0; i <= i1; ++i)
                if (std::hypot(static_cast<double>(i) - cx, static_cast<double>(j) - cy) <= cr) {
                    double& c = r.at(static_cast<std::size_t>(i), static_cast<std::size_t>(j));
                    c = std::min(c, target);
                }
    }
    // Graded out: a cell's size at most its neighbour's + grade × the step (two chamfer
    // passes over the 8-neighbourhood).
    const double straight = o.grade * r.h, diagonal = o.grade * r.h * std::numbers::sqrt2;
    const long nx = static_cast<long>(r.nx), ny = static_cast<long>(r.ny);
    const auto relax = [&](long i, long j, long di, long dj) {
        const long a = i + di, b = j + dj;
        if (a < 0 || b < 0 || a >= nx || b >= ny) return;
        double& c = r.at(static_cast<std::size_t>(i), static_cast<std::size_t>(j));
        c = std::min(c, r.at(static_cast<std::size_t>(a), static_cast<std::size_t>(b)) + (di != 0 && dj != 0 ? diagonal : straight));
    };
    for (long j = 0; j < ny; ++j)
        for (long i = 0; i < nx; ++i) relax(i, j, -1, 0), relax(i, j, -1, -1), relax(i, j, 0, -1), relax(i, j, 1, -1);
    for (long j = ny - 1; j >= 0; --j)
        for (long i = nx - 1; i >= 0; --i) relax(i, j, 1, 0), relax(i, j, 1, 1), relax(i, j, 0, 1), relax(i, j, -1, 1);
    return [size = std::move(size), r = std::move(r)](double x, double y) { return std::min(size(x, y), r.read(x, y)); };
}

}  // namespace wave
