// Ts'o–Barsky height field: wave lists deposited on a grid (§3.2.4), superposed, and
// a Beta2-spline surface whose tension rises with height (§3.3).
#include "libwave/beta_spline.h"
#include "core/format.h"
#include "core/limits.h"
#include "libwave/errors.h"
#include "libwave/surface.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <sstream>

namespace wave {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string fmt(double v) { return detail::format_number(v); }

void validate(const HeightFieldOptions& o) {
    if (o.nx < 2 || o.ny < 2)
        throw InputError("surface: the grid needs at least 2 x 2 control vertices, got " + std::to_string(o.nx) +
                         " x " + std::to_string(o.ny));
    if (o.samples_per_span < 1)
        throw InputError("surface: samples_per_span must be >= 1, got " + std::to_string(o.samples_per_span));
    if (!(o.tension_per_metre >= 0.0) || !(o.max_tension >= 0.0))
        throw InputError("surface: tension_per_metre and max_tension must be >= 0");
    if (!(o.footprint_radius > 0.0)) throw InputError("surface: footprint_radius must be > 0 cells, got " + fmt(o.footprint_radius));
    if (!(o.repeat_time >= 0.0) || !std::isfinite(o.repeat_time))
        throw InputError("surface: repeat_time must be >= 0 s, got " + fmt(o.repeat_time));
}

// Continued-fraction approximation of x by p/q with q <= max_q; exact within tol or none.
bool as_fraction(double x, long max_q, long& p, long& q) {
    long p0 = 0, q0 = 1, p1 = 1, q1 = 0;
    double r = x;
    for (int n = 0; n < 64; ++n) {
        const double a = std::floor(r);
        const long ai = static_cast<long>(a);
        const long p2 = ai * p1 + p0, q2 = ai * q1 + q0;
        if (q2 > max_q) break;
        p0 = p1, q0 = q1, p1 = p2, q1 = q2;
        if (std::abs(static_cast<double>(p1) / static_cast<double>(q1) - x) <= 1e-9 * x) {
            p = p1;
            q = q1;
            return true;
        }
        if (r - a < 1e-15) break;
        r = 1.0 / (r - a);
    }
    return false;
}

// Per train and node: Σ w a e^{iφ} and Σ w.
struct Deposit {
    std::vector<double> re, im, weight;
    void add(std::size_t at, double w, double a, double phi) {
        re[at] += w * a * std::cos(phi);
        im[at] += w * a * std::sin(phi);
        weight[at] += w;
    }
};

}  // namespace

double loop_period(std::span<const double> periods) {
    if (periods.empty()) return 0.0;
    // Each period as a fraction of the first, T_n = T_0 p_n / q_n in lowest terms. The
    // LCM of fractions is lcm(p) / gcd(q), and gcd(q) = 1 because T_0 / T_0 = 1/1.
    long multiple = 1;
    for (double t : periods) {
        long p = 0, q = 0;
        if (!(t > 0.0) || !as_fraction(t / periods[0], 1000, p, q)) return 0.0;
        multiple = std::lcm(multiple, p / std::gcd(p, q));
        if (multiple > 1'000'000) return 0.0;
    }
    return periods[0] * static_cast<double>(multiple);
}

HeightFieldPlan plan_height_field(const Seafloor& seafloor, const RaySet& rays, std::span<const WaveTrain> trains,
                                  const HeightFieldOptions& o) {
    validate(o);
    if (trains.empty()) throw InputError("surface: no wave train given");
    HeightFieldPlan plan;
    const ElevationGrid& g = seafloor.grid;
    plan.nx = o.nx;
    plan.ny = o.ny;
    plan.x0 = g.x0;
    plan.y0 = g.y0;
    plan.dx = (g.x_max() - g.x0) / static_cast<double>(o.nx - 1);
    plan.dy = (g.y_max() - g.y0) / static_cast<double>(o.ny - 1);
    plan.samples_per_span = o.samples_per_span;
    plan.tension_per_metre = o.tension_per_metre;
    plan.max_tension = o.max_tension;
    // Sizes saturate (core/limits.h): control vertices near 2^62 must not wrap round
    // to a small vertex count that passes the limit.
    const auto S = static_cast<std::size_t>(o.samples_per_span);
    const std::size_t vnx = detail::add_sat(detail::mul_sat(S, o.nx - 1), 1);
    const std::size_t vny = detail::add_sat(detail::mul_sat(S, o.ny - 1), 1);
    const std::size_t vertices = detail::mul_sat(vnx, vny);
    if (vertices > o.max_vertices)
        throw LimitError("surface: " + detail::format_count(vnx) + " x " + detail::format_count(vny) +
                         " vertices exceed max_vertices = " + detail::format_count(o.max_vertices) +
                         " (HeightFieldOptions::max_vertices, scene key /surface/max_vertices; or lower /surface/grid or "
                         "/surface/samples_per_span)");
    plan.vertex_nx = vnx;
    plan.vertex_ny = vny;

    // Frequencies, and the loop they repeat after.
    std::vector<double> periods, omega(trains.size());
    for (const WaveTrain& t : trains) periods.push_back(t.period);
    if (o.repeat_time > 0.0) {
        plan.loop_period = o.repeat_time;
        for (std::size_t n = 0; n < trains.size(); ++n)  // Tessendorf eq. 18 (physics.h)
            omega[n] = quantize_frequency(kTwoPi / trains[n].period, o.repeat_time);
    } else {
        plan.loop_period = loop_period(periods);
        if (plan.loop_period == 0.0) {
            std::string list;
            for (double p : periods) list += (list.empty() ? "" : ", ") + fmt(p);
            throw InputError("surface: the wave periods (" + list + " s) have no common multiple; set "
                             "repeat_time to quantise the frequencies (Tessendorf eq. 18)");
        }
        for (std::size_t n = 0; n < trains.size(); ++n) omega[n] = kTwoPi / trains[n].period;
    }

    const std::size_t nodes = o.nx * o.ny;
    Deposit dep{std::vector<double>(nodes * trains.size()), std::vector<double>(nodes * trains.size()),
                std::vector<double>(nodes * trains.size())};
    const double cell = std::min(plan.dx, plan.dy);
    const double radius = o.footprint_radius * cell, sigma = 0.5 * radius;
    const auto node_x = [&](std::ptrdiff_t i) { return plan.x0 + static_cast<double>(i) * plan.dx; };
    const auto node_y = [&](std::ptrdiff_t j) { return plan.y0 + static_cast<double>(j) * plan.dy; };
    const auto inside = [&](std::ptrdiff_t i, std::ptrdiff_t j) {
        return i >= 0 && j >= 0 && i < static_cast<std::ptrdiff_t>(o.nx) && j < static_cast<std::ptrdiff_t>(o.ny);
    };

    for (std::size_t ray = 0; ray < rays.ray_count(); ++ray) {
        const std::size_t base = rays.train[ray] * nodes;
        for (std::size_t p = rays.offsets[ray]; p + 1 < rays.offsets[ray + 1]; ++p) {
            const double ax = rays.x[p], ay = rays.y[p], length = rays.arc_length[p + 1] - rays.arc_length[p];
            if (!(length > 0.0) || !(rays.depth[p] > 0.0)) continue;
            const double ux = rays.dir_x[p], uy = rays.dir_y[p];
            // The wave on this leg at node (i, j): φ = φ_p + k (s − s_p), s along the leg.
            const auto deposit = [&](std::ptrdiff_t i, std::ptrdiff_t j, double w) {
                const double s = std::clamp((node_x(i) - ax) * ux + (node_y(j) - ay) * uy, 0.0, length);
                dep.add(base + static_cast<std::size_t>(j) * o.nx + static_cast<std::size_t>(i), w, rays.amplitude[p],
                        rays.phase[p] + rays.k[p] * s);
            };
            const double fx0 = (ax - plan.x0) / plan.dx, fy0 = (ay - plan.y0) / plan.dy;
            const double fx1 = (rays.x[p + 1] - plan.x0) / plan.dx, fy1 = (rays.y[p + 1] - plan.y0) / plan.dy;
            if (o.footprint == Footprint::bresenham) {
                auto i = static_cast<std::ptrdiff_t>(std::lround(fx0)), j = static_cast<std::ptrdiff_t>(std::lround(fy0));
                const auto i1 = static_cast<std::ptrdiff_t>(std::lround(fx1)), j1 = static_cast<std::ptrdiff_t>(std::lround(fy1));
                const std::ptrdiff_t di = std::abs(i1 - i), dj = -std::abs(j1 - j);
                const std::ptrdiff_t si = i < i1 ? 1 : -1, sj = j < j1 ? 1 : -1;
                std::ptrdiff_t err = di + dj;
                for (;;) {  // Bresenham's line over the grid nodes
                    if (inside(i, j)) deposit(i, j, 1.0);
                    if (i == i1 && j == j1) break;
                    const std::ptrdiff_t e2 = 2 * err;
                    if (e2 >= dj) err += dj, i += si;
                    if (e2 <= di) err += di, j += sj;
                }
            } else {
                // The footprint's box, clipped to the grid before it becomes an index:
                // a radius larger than the grid visits the grid's nodes, no more.
                const auto node_index = [](double f, std::size_t count) {
                    return static_cast<std::ptrdiff_t>(std::clamp(f, -1.0, static_cast<double>(count)));
                };
                const auto lo_i = node_index(std::floor(std::min(fx0, fx1) - radius / plan.dx), o.nx);
                const auto hi_i = node_index(std::ceil(std::max(fx0, fx1) + radius / plan.dx), o.nx);
                const auto lo_j = node_index(std::floor(std::min(fy0, fy1) - radius / plan.dy), o.ny);
                const auto hi_j = node_index(std::ceil(std::max(fy0, fy1) + radius / plan.dy), o.ny);
                for (std::ptrdiff_t j = lo_j; j <= hi_j; ++j)
                    for (std::ptrdiff_t i = lo_i; i <= hi_i; ++i) {
                        if (!inside(i, j)) continue;
                        // Only nodes abreast of this leg (projection in [0, L)): each node
                        // takes the wave from exactly one leg of a ray, never a phase
                        // clamped at a leg's end.
                        const double ex = node_x(i) - ax, ey = node_y(j) - ay;
                        const double s = ex * ux + ey * uy;
                        if (s < 0.0 || s >= length) continue;
                        const double d2 = (ex - s * ux) * (ex - s * ux) + (ey - s * uy) * (ey - s * uy);
                        if (d2 <= radius * radius) deposit(i, j, std::exp(-0.5 * d2 / (sigma * sigma)));
                    }
            }
        }
    }

    plan.term_offsets.assign(1, 0);
    for (std::size_t j = 0; j < o.ny; ++j)
        for (std::size_t i = 0; i < o.nx; ++i) {
            const std::size_t v = j * o.nx + i;
            const bool wet = depth_at(g, node_x(static_cast<std::ptrdiff_t>(i)), node_y(static_cast<std::ptrdiff_t>(j))) > 0.0;
            for (std::size_t n = 0; wet && n < trains.size(); ++n) {
                const std::size_t at = n * nodes + v;
                if (!(dep.weight[at] > 0.0)) continue;
                // Mean of the orthogonals of one train that reached this node (a complex
                // mean: phases do not average linearly); trains then superpose (§3.2.4).
                const double re = dep.re[at] / dep.weight[at], im = dep.im[at] / dep.weight[at];
                plan.term_amplitude.push_back(std::hypot(re, im));
                plan.term_phase.push_back(std::atan2(im, re));
                plan.term_omega.push_back(omega[n]);
            }
            plan.term_offsets.push_back(plan.term_amplitude.size());
        }

    plan.triangles = grid_triangles(plan.vertex_nx, plan.vertex_ny);
    return plan;
}

std::vector<std::uint32_t> grid_triangles(std::size_t nx, std::size_t ny) {
    std::vector<std::uint32_t> tris;
    if (nx < 2 || ny < 2) return tris;
    tris.reserve(6 * (nx - 1) * (ny - 1));
    for (std::size_t b = 0; b + 1 < ny; ++b)
        for (std::size_t a = 0; a + 1 < nx; ++a) {
            const auto v00 = static_cast<std::uint32_t>(b * nx + a);
            const auto v10 = v00 + 1, v01 = static_cast<std::uint32_t>(v00 + nx), v11 = v01 + 1;
            tris.insert(tris.end(), {v00, v10, v11, v00, v11, v01});
        }
    return tris;
}

void evaluate_control_heights(const HeightFieldPlan& plan, double t, std::span<float> heights) {
    // Evaluate at t modulo the loop so that frame k and frame k + loop are bit-identical.
    const double tl = plan.loop_period > 0.0 ? std::fmod(t, plan.loop_period) : t;
    for (std::size_t v = 0; v < plan.control_count(); ++v) {
        double eta = 0.0;
        for (std::size_t k = plan.term_offsets[v]; k < plan.term_offsets[v + 1]; ++k)
            eta += plan.term_amplitude[k] * std::sin(plan.term_phase[k] - plan.term_omega[k] * tl);  // Ts'o eq. 3.5
        heights[v] = static_cast<float>(eta);
    }
}

void evaluate_height_field(const HeightFieldPlan& plan, double t, std::span<float> heights, std::span<float> pos) {
    evaluate_control_heights(plan, t, heights);
    const auto nx = static_cast<std::ptrdiff_t>(plan.nx), ny = static_cast<std::ptrdiff_t>(plan.ny);
    // Control height with linearly extrapolated phantom vertices one beyond the border.
    const auto z = [&](std::ptrdiff_t i, std::ptrdiff_t j) -> double {
        const auto at = [&](std::ptrdiff_t a, std::ptrdiff_t b) { return static_cast<double>(heights[static_cast<std::size_t>(b * nx + a)]); };
        const auto row = [&](std::ptrdiff_t b) {
            if (i < 0) return 2.0 * at(0, b) - at(1, b);
            if (i >= nx) return 2.0 * at(nx - 1, b) - at(nx - 2, b);
            return at(i, b);
        };
        if (j < 0) return 2.0 * row(0) - row(1);
        if (j >= ny) return 2.0 * row(ny - 1) - row(ny - 2);
        return row(j);
    };
    const auto tension = [&](std::ptrdiff_t i, std::ptrdiff_t j) {
        return std::min(plan.max_tension, plan.tension_per_metre * std::max(0.0, z(i, j)));  // 0 in troughs
    };
    const auto quintic = [](double u) { return u * u * u * (10.0 + u * (-15.0 + 6.0 * u)); };
    const std::size_t S = static_cast<std::size_t>(plan.samples_per_span);
    for (std::size_t b = 0; b < plan.vertex_ny; ++b) {
        const auto cj = static_cast<std::ptrdiff_t>(std::min(b / S, plan.ny - 2));
        const double v = static_cast<double>(b - static_cast<std::size_t>(cj) * S) / static_cast<double>(S);
        for (std::size_t a = 0; a < plan.vertex_nx; ++a) {
            const auto ci = static_cast<std::ptrdiff_t>(std::min(a / S, plan.nx - 2));
            const double u = static_cast<double>(a - static_cast<std::size_t>(ci) * S) / static_cast<double>(S);
            // Continuously shaped Beta-spline: β2 blended from the patch's corner knots.
            const double qu = quintic(u), qv = quintic(v);
            const double beta2 = (1 - qu) * (1 - qv) * tension(ci, cj) + qu * (1 - qv) * tension(ci + 1, cj) +
                                 (1 - qu) * qv * tension(ci, cj + 1) + qu * qv * tension(ci + 1, cj + 1);
            double wu[4], wv[4];
            beta_spline_basis(u, 1.0, beta2, wu);
            beta_spline_basis(v, 1.0, beta2, wv);
            double px = 0, py = 0, pz = 0;
            for (int s = 0; s < 4; ++s) {
                const std::ptrdiff_t j = cj - 1 + s;
                for (int r = 0; r < 4; ++r) {
                    const std::ptrdiff_t i = ci - 1 + r;
                    const double w = wu[r] * wv[s];
                    px += w * (plan.x0 + static_cast<double>(i) * plan.dx);
                    py += w * (plan.y0 + static_cast<double>(j) * plan.dy);
                    pz += w * z(i, j);
                }
            }
            float* out = &pos[3 * (b * plan.vertex_nx + a)];
            out[0] = static_cast<float>(px);
            out[1] = static_cast<float>(py);
            out[2] = static_cast<float>(pz);
        }
    }
}

}  // namespace wave
