// Ts'o–Barsky wave tracing in isobath mode: straight legs between exact isobath
// crossings, Snell's law at each crossing, amplitude from the spacing of neighbouring
// rays (Ts'o & Barsky 1987 §3.1.3, §3.2.1–3.2.3).
#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/trace.h"
#include "common.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace wave {
namespace {

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

std::string fmt(double v) { return detail::format_number(v); }

using detail::Box;
using detail::clip;

void validate(std::span<const WaveTrain> trains, const TraceOptions& o) {
    if (trains.empty()) throw InputError("trace: no wave train given");
    for (std::size_t n = 0; n < trains.size(); ++n)
        detail::validate_wave_train(trains[n], "trace: wave train " + std::to_string(n) + ": ");
    if (!(o.ray_spacing > 0.0) || !std::isfinite(o.ray_spacing))
        throw InputError("trace: ray_spacing must be > 0 m, got " + fmt(o.ray_spacing));
    if (!(o.breaker_index > 0.0)) throw InputError("trace: breaker_index must be > 0, got " + fmt(o.breaker_index));
    if (!(o.doubt_factor >= 1.0)) throw InputError("trace: doubt_factor must be >= 1, got " + fmt(o.doubt_factor));
}

// Appends points to a RaySet; crossing_contour records, per point, the isobath crossed
// there (kNone for start / end points) for the amplitude pass.
struct Writer {
    RaySet& rays;
    std::vector<std::size_t>& crossing_contour;
    void point(double px, double py, double dx, double dy, double s, double phase, const LinearWave& w,
               RayEvent e, std::size_t contour) {
        rays.x.push_back(px);
        rays.y.push_back(py);
        rays.dir_x.push_back(dx);
        rays.dir_y.push_back(dy);
        rays.arc_length.push_back(s);
        rays.phase.push_back(phase);
        rays.depth.push_back(w.depth);
        rays.k.push_back(w.k);
        rays.omega.push_back(w.omega);
        rays.celerity.push_back(w.celerity);
        rays.group_velocity.push_back(w.group_velocity);
        rays.shoaling.push_back(w.shoaling);
        rays.event.push_back(e);
        crossing_contour.push_back(contour);
    }
};

// Traces one ray from its entry point; returns false when it enters on land.
bool trace_one(const IsobathIndex& index, const Box& box,
               const detail::EntryPoint& entry, double omega, const TraceOptions& o, Writer& out) {
    if (!(entry.depth > 0.0)) return false;
    LinearWave w = linear_wave(omega, entry.depth, o.dispersion);
    double px = entry.x, py = entry.y, s = 0.0, dx = entry.dx, dy = entry.dy;
    // The entry's phase (the reference plane wave refracted over the apron), so that
    // neighbouring rays start on one wave front.
    double phase = entry.phase;
    out.point(px, py, dx, dy, s, phase, w, RayEvent::start, kNone);
    const double scale = std::max(box.x1 - box.x0, box.y1 - box.y0);
    detail::CrossingSkip skip;
    for (std::size_t crossings = 0;; ++crossings) {
        if (crossings >= o.max_crossings)
            throw LimitError("trace: a ray crossed isobaths more than " + std::to_string(o.max_crossings) +
                             " times (TraceOptions::max_crossings, scene key /trace/max_crossings; raise it, or coarsen the isobaths)");
        double t0 = 0.0, t1 = 0.0;
        clip(box, px, py, dx, dy, t0, t1);
        const double to_exit = std::max(t1, 0.0);
        const std::optional<IsobathCrossing> hit = detail::next_crossing(index, px, py, dx, dy, to_exit, scale, skip);
        if (!hit) {
            s += to_exit;
            phase += w.k * to_exit;
            out.point(px + dx * to_exit, py + dy * to_exit, dx, dy, s, phase, w, RayEvent::left_domain, kNone);
            return true;
        }
        s += hit->distance;
        phase += w.k * hit->distance;
        px = hit->x;
        py = hit->y;
        skip = detail::skip_after(index, *hit);
        if (hit->depth <= 0.0) {
            out.point(px, py, dx, dy, s, phase, linear_wave(omega, 0.0, o.dispersion), RayEvent::aground, hit->contour);
            return true;
        }
        const LinearWave next = linear_wave(omega, hit->depth, o.dispersion);
        if (!detail::refract_at_contour(*hit, w.celerity, next.celerity, dx, dy)) {
            out.point(px, py, dx, dy, s, phase, w, RayEvent::reflected, hit->contour);  // stays in the same band
            continue;
        }
        w = next;
        out.point(px, py, dx, dy, s, phase, w, RayEvent::refracted, hit->contour);
    }
}

// K_r = sqrt(b0 / b) at each crossing from the neighbouring rays' crossings of the same
// isobath; amplitude A∞ K_s K_r with the caustic cap. `first`/`last` bound one train.
void amplitudes(RaySet& r, const std::vector<std::size_t>& contour_at, std::size_t first, std::size_t last,
                double deep_amplitude, const TraceOptions& o) {
    const auto spacing_to = [&](std::size_t i, std::size_t ray) -> double {
        double best = std::numeric_limits<double>::infinity(), across = 0.0;
        for (std::size_t j = r.offsets[ray]; j < r.offsets[ray + 1]; ++j) {
            if (contour_at[j] != contour_at[i]) continue;
            const double ex = r.x[j] - r.x[i], ey = r.y[j] - r.y[i];
            const double d2 = ex * ex + ey * ey;
            if (d2 < best) best = d2, across = std::abs(ex * r.dir_y[i] - ey * r.dir_x[i]);
        }
        return std::isinf(best) ? -1.0 : across;
    };
    for (std::size_t ray = first; ray < last; ++ray) {
        double kr = 1.0;
        for (std::size_t i = r.offsets[ray]; i < r.offsets[ray + 1]; ++i) {
            if (contour_at[i] != kNone) {
                double sum = 0.0;
                int n = 0;
                for (std::size_t nb : {ray - 1, ray + 1}) {
                    if (ray == first && nb == ray - 1) continue;
                    if (nb >= last) continue;
                    const double b = spacing_to(i, nb);
                    if (b >= 0.0) sum += b, ++n;
                }
                if (n > 0) {
                    const double b = sum / n;
                    kr = b > 0.0 ? std::sqrt(r.spacing_start[ray] / b) : std::numeric_limits<double>::infinity();
                }
            }
            std::uint8_t flags = 0;
            if (kr < 1.0 / o.doubt_factor || kr > o.doubt_factor) flags |= kRefractionDoubtful;
            double a = deep_amplitude * r.shoaling[i] * kr;
            const double cap = 0.5 * o.breaker_index * std::max(r.depth[i], 0.0);
            if (a > cap) {
                // Converging rays (a caustic) would give an unbounded amplitude: the wave
                // breaks first, so H = 2A is limited to γ h.
                if (r.event[i] != RayEvent::aground) flags |= kAmplitudeCapped;
                a = cap;
            }
            r.refraction.push_back(std::isfinite(kr) ? kr : std::numeric_limits<double>::max());
            r.amplitude.push_back(a);
            r.flags.push_back(flags);
        }
    }
}

}  // namespace

const char* to_string(RayEvent e) noexcept {
    switch (e) {
        case RayEvent::start: return "start";
        case RayEvent::refracted: return "refracted";
        case RayEvent::reflected: return "reflected";
        case RayEvent::aground: return "aground";
        case RayEvent::left_domain: return "left_domain";
    }
    return "unknown";
}

RaySet trace_rays(const Seafloor& seafloor, const DepthContours& isobaths, std::span<const WaveTrain> trains,
                  const TraceOptions& o) {
    validate(trains, o);
    if (isobaths.size() == 0)
        throw InputError("trace: the isobath set is empty; give depth levels inside the seafloor's depth range");
    const ElevationGrid& g = seafloor.grid;
    const Box box = detail::domain_box(g);
    const IsobathIndex index(isobaths);
    RaySet rays;
    std::vector<std::size_t> contour_at;
    Writer out{rays, contour_at};

    for (std::size_t n = 0; n < trains.size(); ++n) {
        const WaveTrain& t = trains[n];
        const double len = std::hypot(t.direction_x, t.direction_y);
        const double dx = t.direction_x / len, dy = t.direction_y / len;
        const double omega = 2.0 * std::numbers::pi / t.period;
        const std::vector<detail::EntryPoint> entries =
            detail::entry_points(g, dx, dy, {omega, t.amplitude, o.breaker_index, o.dispersion}, o.ray_spacing, o.max_rays - rays.ray_count());
        if (rays.ray_count() + entries.size() > o.max_rays)
            throw LimitError("trace: " + std::to_string(rays.ray_count() + entries.size()) + " rays exceed the limit of " +
                             std::to_string(o.max_rays) + " (TraceOptions::max_rays, scene key /trace/max_rays; raise it or widen /trace/ray_spacing)");
        const std::size_t first_ray = rays.ray_count();
        for (const detail::EntryPoint& e : entries) {
            if (!trace_one(index, box, e, omega, o, out)) continue;
            rays.offsets.push_back(rays.point_count());
            rays.train.push_back(static_cast<std::uint32_t>(n));
            rays.spacing_start.push_back(o.ray_spacing * e.tube);
        }
        amplitudes(rays, contour_at, first_ray, rays.ray_count(), t.amplitude, o);
    }
    return rays;
}

std::string rays_to_csv(const RaySet& r) {
    std::ostringstream out;
    out.precision(17);
    out << "ray,step,x,y,dir_x,dir_y,depth,k,omega,celerity,group_velocity,amplitude,flag\n";
    for (std::size_t ray = 0; ray < r.ray_count(); ++ray)
        for (std::size_t i = r.offsets[ray]; i < r.offsets[ray + 1]; ++i) {
            out << ray << ',' << i - r.offsets[ray] << ',' << r.x[i] << ',' << r.y[i] << ',' << r.dir_x[i] << ','
                << r.dir_y[i] << ',' << r.depth[i] << ',' << r.k[i] << ',' << r.omega[i] << ',' << r.celerity[i]
                << ',' << r.group_velocity[i] << ',' << r.amplitude[i] << ',' << to_string(r.event[i]);
            if (r.flags[i] & kAmplitudeCapped) out << "+capped";
            if (r.flags[i] & kRefractionDoubtful) out << "+doubtful";
            out << '\n';
        }
    return out.str();
}

}  // namespace wave
