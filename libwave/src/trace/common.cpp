#include "common.h"

#include "core/format.h"
#include "libwave/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace wave::detail {

void validate_wave_train(const WaveTrain& t, const std::string& where) {
    if (!(t.period > 0.0) || !std::isfinite(t.period))
        throw InputError(where + "period must be > 0 s, got " + format_number(t.period));
    if (!(t.amplitude > 0.0) || !std::isfinite(t.amplitude))
        throw InputError(where + "amplitude must be > 0 m, got " + format_number(t.amplitude));
    if (!(std::hypot(t.direction_x, t.direction_y) > 0.0) || !std::isfinite(t.direction_x) || !std::isfinite(t.direction_y))
        throw InputError(where + "direction must be a non-zero vector, got (" + format_number(t.direction_x) + ", " +
                         format_number(t.direction_y) + ")");
}

bool clip(const Box& b, double px, double py, double dx, double dy, double& t0, double& t1) {
    t0 = -std::numeric_limits<double>::infinity();
    t1 = std::numeric_limits<double>::infinity();
    const auto slab = [&](double p, double d, double lo, double hi) {
        if (d == 0.0) return p >= lo && p <= hi;
        double a = (lo - p) / d, c = (hi - p) / d;
        if (a > c) std::swap(a, c);
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
        return t0 <= t1;
    };
    return slab(px, dx, b.x0, b.x1) && slab(py, dy, b.y0, b.y1);
}

namespace {

// One up-wave side of the box: from the up-wave corner along the unit tangent t (d·t >
// 0) for `length` metres; n is its outward normal.
struct UpwaveSide {
    double cx, cy, tx, ty, nx, ny, length;
};

// The apron's wave along one side (EntryPoint): the reference wave refracted to the
// depth at u metres from the corner.
struct SideWave {
    struct At {
        double depth = 0.0, k = 0.0, k_t = 0.0, shoaling = 0.0;  // k_t = 0 over land
    };
    const ElevationGrid& grid;
    const UpwaveSide& side;
    const EntryWave& train;
    double k_reference, k_n, k_t_reference;
    At at(double u) const {
        const double h = depth_at(grid, side.cx + u * side.tx, side.cy + u * side.ty);
        if (h == last.depth) return last;  // a side of constant depth: one dispersion solve
        At a;
        a.depth = h;
        if (h > 0.0) {
            const LinearWave w = linear_wave(train.omega, h, train.dispersion);
            a.k = w.k;
            a.k_t = std::sqrt(std::max(0.0, w.k * w.k - k_n * k_n));
            a.shoaling = w.shoaling;
        }
        return last = a;
    }
    mutable At last{std::numeric_limits<double>::quiet_NaN()};
    // The width the tube had in the reference over its width across the train here.
    double tube(double k_t) const { return k_t > k_t_reference ? k_t_reference / k_t : 1.0; }
    // Depth-limited breaking, 2 A∞ K_s K_r >= γ h, as the tracers cap the amplitude; over
    // the apron K_r² = cos θ_ref / cos θ, the angles from the side's tangent.
    bool broken(const At& a) const {
        if (!(a.depth > 0.0)) return false;
        const double kr2 = a.k_t > k_t_reference ? (k_t_reference / k_reference) * a.k / a.k_t : 1.0;  // as tube()
        return 2.0 * train.deep_amplitude * a.shoaling * std::sqrt(kr2) >= train.breaker_index * a.depth;
    }
};

// A walk along a side from where its rays come from, one way, by the midpoint rule on
// steps of at most `step` metres: the side's phase ∫ k_t, and an apron ray's own phase
// ∫ k²/k_t (the ray runs k/k_t metres per metre of side, gaining k per metre), with its
// value where the wave first broke. k_t is smooth but for its 1/√h rise at a shoreline
// the side crosses, and k²/k_t for its 1/√ rise at a turning point: the midpoints keep
// both integrals finite.
struct SideWalk {
    const SideWave& wave;
    double u, step;
    double phase = 0.0, ray_phase = 0.0, ray_phase_at_break = std::numeric_limits<double>::quiet_NaN();
    double last_mid = std::numeric_limits<double>::quiet_NaN();  // the last unbroken sample
    void to(double target) {
        const auto n = static_cast<std::size_t>(std::ceil(std::abs(target - u) / step));
        const double du = n == 0 ? 0.0 : (target - u) / static_cast<double>(n), length = std::abs(du);
        for (std::size_t i = 0; i < n; ++i) {
            const double start = u + static_cast<double>(i) * du, mid = start + 0.5 * du;
            const SideWave::At a = wave.at(mid);
            phase += a.k_t * length;
            const double per_metre = a.k_t > 0.0 ? a.k * a.k / a.k_t : 0.0;
            if (std::isnan(ray_phase_at_break)) {
                if (wave.broken(a)) {
                    const double at = std::isnan(last_mid) ? mid : where_it_breaks(last_mid, mid);
                    ray_phase_at_break = ray_phase + (at - start) * (du >= 0.0 ? 1.0 : -1.0) * per_metre;  // from this step's start
                } else {
                    last_mid = mid;
                }
            }
            ray_phase += per_metre * length;
        }
        u = target;
    }
    // Between an unbroken and a broken sample, where the wave first breaks (bisection
    // to a thousandth of the step: a break phase to ~1e-3 rad).
    double where_it_breaks(double unbroken, double broken) const {
        for (int k = 0; k < 10; ++k) {
            const double mid = 0.5 * (unbroken + broken);
            (wave.broken(wave.at(mid)) ? broken : unbroken) = mid;
        }
        return 0.5 * (unbroken + broken);
    }
};

// The up-wave sides meeting at the corner the unit direction (dx, dy) reaches first:
// two for an oblique train, one for a train along an axis.
std::vector<UpwaveSide> upwave_sides(const Box& box, double dx, double dy) {
    const double cx = dx >= 0.0 ? box.x0 : box.x1, cy = dy >= 0.0 ? box.y0 : box.y1;
    std::vector<UpwaveSide> sides;
    if (dx != 0.0)  // the side x = cx, tangent along y away from the corner
        sides.push_back({cx, cy, 0.0, dy >= 0.0 ? 1.0 : -1.0, dx > 0.0 ? -1.0 : 1.0, 0.0, box.y1 - box.y0});
    if (dy != 0.0)
        sides.push_back({cx, cy, dx >= 0.0 ? 1.0 : -1.0, 0.0, 0.0, dy > 0.0 ? -1.0 : 1.0, box.x1 - box.x0});
    return sides;
}

// Where each ray's line along (dx, dy), `spacing` apart across it, meets the box: the
// plane wave of direction d, to be refracted by start_on_side.
std::vector<EntryPoint> place_entries(const ElevationGrid& grid, const UpwaveSide& corner, double dx, double dy, double spacing,
                                      std::size_t max_rays) {
    const Box box = domain_box(grid);
    const double ex = -dy, ey = dx;  // along the start line
    double s_min = HUGE_VAL, s_max = -HUGE_VAL;
    for (const auto& [cx, cy] : {std::pair{box.x0, box.y0}, {box.x1, box.y0}, {box.x1, box.y1}, {box.x0, box.y1}}) {
        s_min = std::min(s_min, cx * ex + cy * ey);
        s_max = std::max(s_max, cx * ex + cy * ey);
    }
    const double n = std::floor((s_max - s_min) / spacing);
    if (n > static_cast<double>(max_rays))
        throw LimitError("trace: " + format_number(n) + " rays would enter, more than the limit of " +
                         std::to_string(max_rays) + " (TraceOptions::max_rays, scene key /trace/max_rays; raise it or widen /trace/ray_spacing)");
    const double t_min = corner.cx * dx + corner.cy * dy;
    std::vector<EntryPoint> out;
    const auto count = static_cast<std::size_t>(n);
    for (std::size_t i = 0; i < count; ++i) {
        const double s = s_min + (static_cast<double>(i) + 0.5) * spacing;
        const double lx = s * ex + t_min * dx, ly = s * ey + t_min * dy;
        double t0 = 0.0, t1 = 0.0;
        if (!clip(box, lx, ly, dx, dy, t0, t1) || t1 <= t0) continue;
        EntryPoint e;
        e.x = lx + t0 * dx;
        e.y = ly + t0 * dy;
        e.s = s;
        e.depth = depth_at(grid, e.x, e.y);
        e.dx = dx;
        e.dy = dy;
        out.push_back(e);
    }
    return out;
}

// The wet entries on a side, by their distance from the corner.
std::vector<std::pair<double, std::size_t>> entries_on(const UpwaveSide& f, const std::vector<EntryPoint>& entries) {
    std::vector<std::pair<double, std::size_t>> on;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const double off = (entries[i].x - f.cx) * f.nx + (entries[i].y - f.cy) * f.ny;
        if (std::abs(off) <= 1e-9 * (1.0 + f.length) && entries[i].depth > 0.0)
            on.emplace_back(std::max(0.0, (entries[i].x - f.cx) * f.tx + (entries[i].y - f.cy) * f.ty), i);
    }
    std::sort(on.begin(), on.end());
    return on;
}

// A side's deepest point (the first of equals from the corner), sampled every `step`
// metres: its distance from the corner and its depth.
std::pair<double, double> deepest_point(const ElevationGrid& grid, const UpwaveSide& f, double step) {
    const auto samples = static_cast<std::size_t>(std::ceil(f.length / step));
    double deepest = -HUGE_VAL, at = 0.0;
    for (std::size_t j = 0; j <= samples; ++j) {
        const double u = f.length * static_cast<double>(j) / static_cast<double>(samples);
        const double h = depth_at(grid, f.cx + u * f.tx, f.cy + u * f.ty);
        if (h > deepest) deepest = h, at = u;
    }
    return {at, deepest};
}

// Starts a side's entries on the apron's wave, walking away from `u0` (where the side's
// rays come from) both ways: downstream in order, upstream in reverse.
void start_on_side(const SideWave& wave, double u0, double step, const std::vector<std::pair<double, std::size_t>>& on,
                   std::vector<EntryPoint>& entries) {
    const UpwaveSide& f = wave.side;
    const auto start = [&](const SideWalk& walk, std::size_t i) {
        EntryPoint& e = entries[i];
        const double k_t = (walk.u >= u0 ? 1.0 : -1.0) * wave.at(walk.u).k_t;
        const double kx = wave.k_n * f.nx + k_t * f.tx, ky = wave.k_n * f.ny + k_t * f.ty, k = std::hypot(kx, ky);
        e.dx = kx / k;
        e.dy = ky / k;
        e.phase = walk.phase;
        e.tube = wave.tube(std::abs(k_t));
        e.break_phase = walk.phase - (walk.ray_phase - walk.ray_phase_at_break);  // NaN: unbroken
    };
    const auto split = std::lower_bound(on.begin(), on.end(), std::pair{u0, std::size_t{0}});
    SideWalk down{wave, u0, step};
    for (auto it = split; it != on.end(); ++it) {
        down.to(it->first);
        start(down, it->second);
    }
    SideWalk up{wave, u0, step};
    for (auto it = std::make_reverse_iterator(split); it != on.rend(); ++it) {
        up.to(it->first);
        start(up, it->second);
    }
}

}  // namespace

std::vector<EntryPoint> entry_points(const ElevationGrid& grid, double dx, double dy, const EntryWave& train, double spacing,
                                     std::size_t max_rays) {
    const std::vector<UpwaveSide> sides = upwave_sides(domain_box(grid), dx, dy);
    const UpwaveSide& corner = sides.front();
    std::vector<EntryPoint> out = place_entries(grid, corner, dx, dy, spacing, max_rays);
    // The reference depth is the deepest of the sides': no entry is deeper, so none lies
    // past a turning point (k < |k_n|), where no wave from the reference would arrive.
    const double step = 0.5 * std::min(grid.dx, grid.dy);
    std::vector<std::pair<double, double>> deepest;
    double h_reference = -HUGE_VAL;
    for (const UpwaveSide& f : sides) h_reference = std::max(h_reference, deepest.emplace_back(deepest_point(grid, f, step)).second);
    if (!(h_reference > 0.0)) return out;  // the up-wave sides are dry: no ray starts
    const double k_reference = linear_wave(train.omega, h_reference, train.dispersion).k;
    const bool wet_corner = depth_at(grid, corner.cx, corner.cy) > 0.0;
    for (std::size_t side = 0; side < sides.size(); ++side) {
        const UpwaveSide& f = sides[side];
        const double along = dx * f.tx + dy * f.ty;
        const SideWave wave{grid, f, train, k_reference, k_reference * (dx * f.nx + dy * f.ny), k_reference * std::abs(along)};
        // Where the side's rays come from: the corner, through the water beyond it; or,
        // with a dry corner or a train along the side's normal, the side's deepest point,
        // from which they run both ways.
        const double u0 = wet_corner && along > 1e-12 ? 0.0 : deepest[side].first;
        start_on_side(wave, u0, step, entries_on(f, out), out);
    }
    return out;
}

std::optional<IsobathCrossing> next_crossing(const IsobathIndex& index, double px, double py, double dx, double dy,
                                             double max_distance, double scale, const CrossingSkip& skip) {
    constexpr double first_reach = 1.0 / 64.0;  // of the domain size
    CrossingQuery q;
    q.x = px;
    q.y = py;
    q.dx = dx;
    q.dy = dy;
    q.min_distance = 1e-12 * scale;
    q.skip_segment = skip.segment;
    std::optional<IsobathCrossing> hit;
    for (double reach = first_reach * scale;; reach *= 4.0) {
        q.max_distance = std::min(reach, max_distance);
        hit = index.first_crossing(q);
        // A vertex crossing lies on both neighbouring segments: do not re-cross it.
        while (hit && (hit->segment == skip.previous || hit->segment == skip.next) && hit->distance <= 1e-9 * scale) {
            q.min_distance = hit->distance;
            hit = index.first_crossing(q);
        }
        if (hit || q.max_distance >= max_distance) return hit;
    }
}

CrossingSkip skip_after(const IsobathIndex& index, const IsobathCrossing& hit) {
    return {hit.segment, index.previous_segment(hit.segment), index.next_segment(hit.segment)};
}

bool refract_at_contour(const IsobathCrossing& hit, double celerity_before, double celerity_after, double& dx,
                        double& dy) {
    double nx = -hit.tangent_y, ny = hit.tangent_x;
    if (nx * dx + ny * dy < 0.0) nx = -nx, ny = -ny;
    const double tx = hit.tangent_x, ty = hit.tangent_y;
    const double sin_i = dx * tx + dy * ty;  // signed component along the contour
    const double sin_r = sin_i * celerity_after / celerity_before;
    if (std::abs(sin_r) > 1.0) {
        // Total reflection: mirror across the contour.
        const double dn = dx * nx + dy * ny;
        dx -= 2.0 * dn * nx;
        dy -= 2.0 * dn * ny;
        return false;
    }
    const double cos_r = std::sqrt(1.0 - sin_r * sin_r);
    dx = sin_r * tx + cos_r * nx;
    dy = sin_r * ty + cos_r * ny;
    const double len = std::hypot(dx, dy);  // renormalise rounding only
    dx /= len;
    dy /= len;
    return true;
}

namespace {

// A gravity wave's k and K_s at depth h, Newton from the guess k0 on
// f(k) = g k tanh(k h) − ω², each step with one tanh (1/cosh² = 1 − tanh², and
// 2x / sinh 2x = x (1 − tanh² x) / tanh x for the group velocity). Newton converges
// quadratically: once a step is below 1e-8 k, the error left is of order 1e-16 k, below
// rounding, and the step is the last. From the table's extrapolated start one step
// does it (two tanh a node with the group velocity's; the check of a 1e-15 step took
// four). Returns false when it does not converge, for the general solver to take over.
bool gravity_wave_from(double omega, double h, double k0, double& k, double& shoaling) {
    const double w2 = omega * omega;
    k = k0;
    for (int step = 0; step < 20; ++step) {
        const double t = std::tanh(k * h);
        const double f = kGravity * k * t - w2, df = kGravity * (t + k * h * (1.0 - t * t));
        const double correction = f / df;
        k -= correction;
        if (!(std::abs(correction) <= 1e-8 * k)) continue;
        const double x = k * h, tx = std::tanh(x);
        const double n = x < 1e-4 ? 1.0 - x * x / 3.0 : 0.5 * (1.0 + x * (1.0 - tx * tx) / tx);  // C_g / C
        shoaling = std::sqrt((0.5 * kGravity / omega) / (n * omega / k));
        return std::isfinite(k) && k > 0.0 && std::isfinite(shoaling);
    }
    return false;
}

}  // namespace

WaveTable::WaveTable(double omega, double max_depth, const DispersionOptions& options, std::size_t nodes)
    : omega_(omega), options_(options) {
    if (options.capillary_length > 0.0 || !(max_depth > 0.0) || nodes < 2) return;  // exact solver only
    s_max_ = std::sqrt(max_depth);
    ds_ = s_max_ / static_cast<double>(nodes - 1);
    inverse_ds_ = 1.0 / ds_;
    k_root_h_.resize(nodes);
    celerity_per_root_h_.resize(nodes);
    shoaling_quarter_h_.resize(nodes);
    // Node by node from the shallow end, each solve started from k √h (smooth in s)
    // extrapolated through the last three nodes, off by ~1e-11: one Newton step.
    const auto start = [&](std::size_t i) {
        const std::vector<double>& v = k_root_h_;
        return i < 4 ? v[i - 1] : 3.0 * v[i - 1] - 3.0 * v[i - 2] + v[i - 3];
    };
    for (std::size_t i = 1; i < nodes; ++i) {
        const double s = ds_ * static_cast<double>(i), h = s * s;
        double k = 0.0, shoaling = 0.0;
        if (i == 1 || !gravity_wave_from(omega, h, start(i) / s, k, shoaling)) {
            const LinearWave w = linear_wave(omega, h, options);
            k = w.k;
            shoaling = w.shoaling;
        }
        k_root_h_[i] = k * s;
        celerity_per_root_h_[i] = omega / (k * s);
        shoaling_quarter_h_[i] = shoaling * std::sqrt(s);
    }
}

WaveTable::Entry WaveTable::exact(double depth) const {
    const LinearWave w = linear_wave(omega_, depth, options_);
    return {w.k, w.celerity, w.shoaling};
}

namespace {
// Node i and the fraction f of the way to node i + 1 for s in [ds, s_max).
struct TablePlace {
    std::size_t i;
    double f;
};
TablePlace place(double s, double inverse_ds) {
    const double u = s * inverse_ds;
    const auto i = static_cast<std::size_t>(u);
    return {i, u - static_cast<double>(i)};
}
double lerp(const std::vector<double>& v, TablePlace p) { return (1.0 - p.f) * v[p.i] + p.f * v[p.i + 1]; }
}  // namespace

WaveTable::Entry WaveTable::at(double depth) const {
    if (!(depth > 0.0)) return {};
    const double s = std::sqrt(depth);
    if (!tabulated(s)) return exact(depth);
    const TablePlace p = place(s, inverse_ds_);
    const double inverse_s = 1.0 / s;
    return {lerp(k_root_h_, p) * inverse_s, lerp(celerity_per_root_h_, p) * s,
            lerp(shoaling_quarter_h_, p) * std::sqrt(inverse_s)};
}

double WaveTable::celerity(double depth) const {
    if (!(depth > 0.0)) return 0.0;
    const double s = std::sqrt(depth);
    if (!tabulated(s)) return exact(depth).celerity;
    return lerp(celerity_per_root_h_, place(s, inverse_ds_)) * s;
}

}  // namespace wave::detail
