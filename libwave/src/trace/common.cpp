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

std::vector<EntryPoint> entry_points(const Box& box, double dx, double dy, double spacing, std::size_t max_rays,
                                     double& phase_origin) {
    const double ex = -dy, ey = dx;  // along the start line
    double s_min = HUGE_VAL, s_max = -HUGE_VAL, t_min = HUGE_VAL;
    for (const auto& [cx, cy] : {std::pair{box.x0, box.y0}, {box.x1, box.y0}, {box.x1, box.y1}, {box.x0, box.y1}}) {
        s_min = std::min(s_min, cx * ex + cy * ey);
        s_max = std::max(s_max, cx * ex + cy * ey);
        t_min = std::min(t_min, cx * dx + cy * dy);
    }
    phase_origin = t_min;
    std::vector<EntryPoint> out;
    const double n = std::floor((s_max - s_min) / spacing);
    if (n > static_cast<double>(max_rays))
        throw LimitError("trace: " + format_number(n) + " rays would enter, more than the limit of " +
                         std::to_string(max_rays) + " (TraceOptions::max_rays, scene key /trace/max_rays; raise it or widen /trace/ray_spacing)");
    const auto count = static_cast<std::size_t>(n);
    for (std::size_t i = 0; i < count; ++i) {
        const double s = s_min + (static_cast<double>(i) + 0.5) * spacing;
        const double lx = s * ex + t_min * dx, ly = s * ey + t_min * dy;
        double t0 = 0.0, t1 = 0.0;
        if (!clip(box, lx, ly, dx, dy, t0, t1) || t1 <= t0) continue;
        out.push_back({lx + t0 * dx, ly + t0 * dy, s});
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
// f(k) = g k tanh(k h) − ω²: from the last node's k √h, two or three steps reach the
// root to 1e-15, each with one tanh (1/cosh² = 1 − tanh², and 2x / sinh 2x =
// x (1 − tanh² x) / tanh x for the group velocity). Returns false when it does not
// converge, for the general solver to take over.
bool gravity_wave_from(double omega, double h, double k0, double& k, double& shoaling) {
    const double w2 = omega * omega;
    k = k0;
    for (int step = 0; step < 20; ++step) {
        const double t = std::tanh(k * h);
        const double f = kGravity * k * t - w2, df = kGravity * (t + k * h * (1.0 - t * t));
        const double next = k - f / df;
        const bool done = std::abs(next - k) <= 1e-15 * k;
        k = next;
        if (!done) continue;
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
    k_root_h_.resize(nodes);
    shoaling_quarter_h_.resize(nodes);
    // Node by node from the shallow end, each solve started from the last node's k √h
    // (smooth in s): a third of the full solver's cost, which was a sixth of a trace.
    for (std::size_t i = 1; i < nodes; ++i) {
        const double s = ds_ * static_cast<double>(i), h = s * s;
        double k = 0.0, shoaling = 0.0;
        if (i == 1 || !gravity_wave_from(omega, h, k_root_h_[i - 1] / s, k, shoaling)) {
            const LinearWave w = linear_wave(omega, h, options);
            k = w.k;
            shoaling = w.shoaling;
        }
        k_root_h_[i] = k * s;
        shoaling_quarter_h_[i] = shoaling * std::sqrt(s);
    }
}

WaveTable::Entry WaveTable::exact(double depth) const {
    const LinearWave w = linear_wave(omega_, depth, options_);
    return {w.k, w.celerity, w.shoaling};
}

WaveTable::Entry WaveTable::at(double depth) const {
    if (!(depth > 0.0)) return {};
    const double s = std::sqrt(depth);
    if (k_root_h_.empty() || s < ds_ || s >= s_max_) return exact(depth);
    const double u = s / ds_;
    const std::size_t i = static_cast<std::size_t>(u);
    const double f = u - static_cast<double>(i);
    const double k = ((1.0 - f) * k_root_h_[i] + f * k_root_h_[i + 1]) / s;
    const double ks = ((1.0 - f) * shoaling_quarter_h_[i] + f * shoaling_quarter_h_[i + 1]) / std::sqrt(s);
    return {k, omega_ / k, ks};
}

}  // namespace wave::detail
