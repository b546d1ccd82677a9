// Gonzato & Le Saëc's dynamic wave tracing (§3.3): fronts of rays advanced step by
// step, refracted by the local depth gradient, flagged ALIVE / FLAT / AGROUND / DEAD,
// with rays inserted where neighbours diverge.
#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/trace.h"
#include "common.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>

namespace wave {
namespace {

// A ray still moving after this many straight crossings of the domain along the swell
// is trapped (guided along a coast, round a cove: its turns cancel, so max_turn misses it).
constexpr double kTrappedCrossings = 3.0;

struct Ray {
    std::uint32_t id;
    double x, y, dx, dy, phase;
    RayFlag flag;
    double turn = 0.0;  // total signed turning (rad): a full orbit means a trapped ray
    // Isobath mode: the depth that represents the band the ray is in (Ts'o: the
    // isobath crossed last), the segments it stands on, and whether it crossed the shore.
    double band = 0.0;
    detail::CrossingSkip skip{};
    bool ashore = false;
    DepthSample here{};  // the seafloor at (x, y), kept from the end of the last step
    double slope = 0.0;  // |∇h| there
    detail::WaveTable::Entry wave{};  // waves.at(here.depth): k, C and K_s there
};

// |(x, y)|: hypot's care for overflow only when the squares overflow (gradients,
// directions and steps are far from it; hypot was a tenth of a trace).
double norm(double x, double y) {
    const double r = std::sqrt(x * x + y * y);
    return r < HUGE_VAL ? r : std::hypot(x, y);
}

// The seafloor and the wave at the ray's position, kept with it: each step, the front's
// record and the next step read them (three table lookups of one depth otherwise).
void settle(Ray& r, const ElevationGrid& g, const detail::WaveTable& waves) {
    r.here = sample_depth(g, r.x, r.y);
    r.slope = norm(r.here.dh_dx, r.here.dh_dy);
    r.wave = waves.at(r.here.depth);
}

// Isobath mode's per-scene state.
struct IsobathMode {
    const IsobathIndex* index = nullptr;
    double scale = 0.0;  // domain size, for the crossing search's tolerances
};

void validate(const WaveTrain& t, const FrontOptions& o) {
    const auto positive = [](double v, const char* name, const char* unit) {
        if (!(v > 0.0) || !std::isfinite(v))
            throw InputError(std::string("fronts: ") + name + " must be > 0 " + unit + ", got " + detail::format_number(v));
    };
    detail::validate_wave_train(t, "fronts: ");
    positive(o.ray_spacing, "ray_spacing", "m");
    positive(o.step, "step", "m");
    positive(o.split_distance, "split_distance", "m");
    if (!(o.flat_amplitude >= 0.0)) throw InputError("fronts: flat_amplitude must be >= 0 m");
    positive(o.breaker_index, "breaker_index", "");
    positive(o.max_turn_degrees, "max_turn_degrees", "degrees");
    if (o.max_turn_degrees > 720.0)
        throw InputError("fronts: max_turn_degrees must be in (0, 720] degrees, got " + detail::format_number(o.max_turn_degrees));
}

bool inside(const detail::Box& b, double x, double y) { return x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1; }

// Removes the dead rays of a front in place; each dead ray's tube joins the gap before
// its next living neighbour. gaps[i] is the tube between ray i and ray i + 1.
void remove_dead(std::vector<Ray>& front, std::vector<double>& gaps) {
    std::size_t kept = 0;
    double carry = 0.0;
    for (std::size_t i = 0; i < front.size(); ++i) {
        if (front[i].flag == RayFlag::dead) {
            if (i < gaps.size()) carry += gaps[i];
            continue;
        }
        if (kept > 0) gaps[kept - 1] = carry;  // kept − 1 < i: gaps[i] is still unread
        carry = i < gaps.size() ? gaps[i] : 0.0;
        if (kept != i) front[kept] = front[i];
        ++kept;
    }
    front.resize(kept);
    gaps.resize(kept > 0 ? kept - 1 : 0);
}

// Aground rays that mark no shore a neighbour does not: one between two aground rays,
// and one at an end of the front beside an aground ray. Left to walk, an end ray follows
// the shoreline with its phase frozen (follow_shore adds none): on the breaking beach a
// ray entering 0.22 m deep on the west side walked 161 m along the shore.
void retire_walkers(std::vector<Ray>& front) {
    const auto aground = [&](std::size_t i) { return front[i].flag == RayFlag::aground; };
    for (std::size_t i = 1; i + 1 < front.size(); ++i)
        if (aground(i) && aground(i - 1) && aground(i + 1)) front[i].flag = RayFlag::dead;
    const std::size_t n = front.size();
    if (n < 2) return;
    if (aground(0) && aground(1)) front[0].flag = RayFlag::dead;
    if (aground(n - 1) && aground(n - 2)) front[n - 1].flag = RayFlag::dead;
}

// Room for a trace's points, estimated from the rays entering and the straight
// crossing: the arrays grow once or not at all.
void reserve_points(FrontSet& f, std::size_t points) {
    f.ray.reserve(points);
    for (std::vector<double>* v : {&f.x, &f.y, &f.dir_x, &f.dir_y, &f.phase, &f.k, &f.depth, &f.slope, &f.rise, &f.amplitude})
        v->reserve(points);
    f.flag.reserve(points);
    f.caustic.reserve(points);
}

// The signed angle from a direction to the next, given their cross and dot products:
// atan2, but for the small turns of almost every step (|z| = |cross/dot| ≤ 1/8) its
// series z − z³/3 + z⁵/5 − z⁷/7, which is off by less than z⁹/9 < 1e-9 rad. The total
// turn is only compared with max_turn (a trapped ray's orbit); atan2 was 4 % of a trace.
double turn_angle(double cross, double dot) {
    if (!(dot > 0.0) || !(std::abs(cross) <= 0.125 * dot)) return std::atan2(cross, dot);
    const double z = cross / dot, z2 = z * z;
    return z * (1.0 - z2 * (1.0 / 3.0 - z2 * (1.0 / 5.0 - z2 * (1.0 / 7.0))));
}

// One refraction step of an ALIVE or FLAT ray (gradient mode): the contour normal is
// the depth gradient; Snell's law between the depth here and one step ahead keeps
// the component along the contour over C constant (Gonzato eq. 8).
void advance(Ray& r, const ElevationGrid& g, const detail::WaveTable& waves, const FrontOptions& o) {
    const DepthSample& here = r.here;
    const double slope = r.slope;
    const detail::WaveTable::Entry w1 = r.wave;
    // Near grazing incidence, the direction at mid-step from the ray equation
    // dθ/ds = −(1/C) ∂C/∂m (m the ray's left normal) decides where Snell's "ahead" is. A
    // ray running exactly along a contour is at its turning point, where the depth
    // straight ahead equals the depth here and Snell alone never turns it, while a ray a
    // hair off the contour turns shorewards within steps: a swell grazing a straight shore
    // made thousands of spurious caustics that [1, 1e-9] did not. With the midpoint
    // direction both turn towards the slower, shallower side. The correction fades out
    // linearly by kGrazing (|cos| of the angle to the contour normal), so it is continuous
    // in the angle and leaves every ray beyond ~3° of grazing as plain Snell had it.
    constexpr double kGrazing = 0.05, kMaxHalfTurn = 0.1;
    double pdx = r.dx, pdy = r.dy;
    if (slope > 1e-12 && here.depth > 0.0) {
        // Nearly every step is far from grazing: one product rules it out before the two
        // divisions (the margin keeps the test's rounding on the safe side).
        const double across = std::abs(r.dx * here.dh_dx + r.dy * here.dh_dy);
        const double grazing = across > 1.001 * kGrazing * slope ? 0.0 : std::max(0.0, 1.0 - across / slope / kGrazing);
        if (grazing > 0.0) {
            const double eps = std::max(1e-6, 1e-3 * here.depth);
            const double dlnc_dh = (waves.celerity(here.depth + eps) / w1.celerity - 1.0) / eps;
            const double half_turn = grazing * std::clamp(-0.5 * o.step * dlnc_dh * (here.dh_dy * r.dx - here.dh_dx * r.dy),
                                                          -kMaxHalfTurn, kMaxHalfTurn);
            pdx = r.dx * std::cos(half_turn) - r.dy * std::sin(half_turn);
            pdy = r.dx * std::sin(half_turn) + r.dy * std::cos(half_turn);
        }
    }
    const double ahead = depth_at(g, r.x + o.step * pdx, r.y + o.step * pdy);
    if (slope > 1e-12 && here.depth > 0.0 && ahead > 0.0) {
        const double nx = here.dh_dx / slope, ny = here.dh_dy / slope;  // towards deeper water
        const double tx = -ny, ty = nx;
        double a = r.dx * nx + r.dy * ny, b = r.dx * tx + r.dy * ty;
        const double b2 = b * waves.celerity(ahead) / w1.celerity;
        if (std::abs(b2) > 1.0) {
            a = -a;  // total reflection at the depth change
        } else {
            // Across the contours the ray heads where its mid-step direction does (past
            // its turning point, if it reached one within the step).
            a = std::copysign(std::sqrt(1.0 - b2 * b2), pdx * nx + pdy * ny);
            b = b2;
        }
        const double len = norm(a, b);
        const double ndx = (a * nx + b * tx) / len, ndy = (a * ny + b * ty) / len;
        r.turn += turn_angle(r.dx * ndy - r.dy * ndx, r.dx * ndx + r.dy * ndy);
        r.dx = ndx;
        r.dy = ndy;
    }
    const double x0 = r.x, y0 = r.y, depth0 = here.depth;  // (here is r.here: replaced below)
    double run = o.step;
    r.x += run * r.dx;
    r.y += run * r.dy;
    settle(r, g, waves);
    if (depth0 > 0.0 && r.here.depth <= 0.0) {
        // The step crossed the shoreline: the ray ends on it (depth interpolated along
        // the step), as its neighbours that follow the shore do — a vertex left on dry
        // land beyond them folded the strip's last cells (tests/test_properties.cpp).
        run *= depth0 / (depth0 - r.here.depth);
        r.x = x0 + run * r.dx;
        r.y = y0 + run * r.dy;
        settle(r, g, waves);
        r.ashore = true;
    }
    // Σ k Δs = ∫ ω/C ds with C averaged over the step: 2ω Δs / (C₀ + C₁), the
    // trapezoid rule on the celerity. It is exact in deep water (C constant) and in
    // shallow water over a depth that varies linearly along the step (C = √(g h),
    // ∫ ds/√h = 2 Δs / (√h₀ + √h₁)), up to the shoreline, where C = 0 and the last
    // step adds 2 k₀ Δs. The trapezoid rule on k (k taken as 0 on the shoreline, where
    // it diverges) added ½ k₀ Δs there: a ray's phase at landfall was short by up to
    // 1.5 k₀ Δs depending on how far before the shore its last wet vertex fell, and
    // Jeschke's breakers, whose lives end at that phase, stepped from ray to ray.
    const double c_sum = w1.celerity + (r.ashore ? 0.0 : r.wave.celerity);
    if (c_sum > 0.0) r.phase += 2.0 * waves.omega() * run / c_sum;
}

// One step of an ALIVE or FLAT ray in isobath mode: straight to each exact isobath
// crossing inside the step, Snell's law there (Ts'o–Barsky §3.2.2), on to the end of
// the step; stops on the shoreline.
void advance_isobath(Ray& r, const IsobathMode& m, const ElevationGrid& g, const detail::WaveTable& waves,
                     const FrontOptions& o) {
    double left = o.step;
    detail::WaveTable::Entry w = waves.at(r.band);
    for (int crossings = 0; left > 0.0; ++crossings) {
        if (crossings > 10'000)
            throw LimitError("fronts: a ray crossed more than 10000 isobaths in one step (shorten FrontOptions::step, scene key /fronts/step, "
                             "or coarsen the isobaths)");
        const auto hit = detail::next_crossing(*m.index, r.x, r.y, r.dx, r.dy, left, m.scale, r.skip);
        const double run = hit ? hit->distance : left;
        r.x += run * r.dx;
        r.y += run * r.dy;
        r.phase += w.k * run;
        left -= run;
        if (!hit) break;
        r.x = hit->x;
        r.y = hit->y;
        r.skip = detail::skip_after(*m.index, *hit);
        if (hit->depth <= 0.0) {
            r.ashore = true;
            break;
        }
        const detail::WaveTable::Entry next = waves.at(hit->depth);
        const double ox = r.dx, oy = r.dy;
        if (detail::refract_at_contour(*hit, w.celerity, next.celerity, r.dx, r.dy)) {
            w = next;
            r.band = hit->depth;
        }
        r.turn += turn_angle(ox * r.dy - oy * r.dx, ox * r.dx + oy * r.dy);
    }
    settle(r, g, waves);
}

// Moves an AGROUND ray onto h = 0 by Newton steps along the depth gradient: one is
// exact on a plane; a curved shore (a small island) needs a few, or the vertex stays
// on dry land (tests/test_properties.cpp).
void onto_shore(Ray& r, const ElevationGrid& g, const detail::WaveTable& waves) {
    for (int newton = 0; newton < 6; ++newton) {
        const DepthSample s = sample_depth(g, r.x, r.y);
        const double slope = norm(s.dh_dx, s.dh_dy);
        if (!(slope > 1e-12) || std::abs(s.depth) < 1e-9) break;
        r.x -= s.depth * s.dh_dx / (slope * slope);
        r.y -= s.depth * s.dh_dy / (slope * slope);
    }
    settle(r, g, waves);
}

// An AGROUND ray follows the shoreline: one step along the contour through it, in the
// sense closest to its travel, then back onto h = 0.
void follow_shore(Ray& r, const ElevationGrid& g, const detail::WaveTable& waves, const FrontOptions& o) {
    DepthSample s = sample_depth(g, r.x, r.y);
    double slope = norm(s.dh_dx, s.dh_dy);
    if (!(slope > 1e-12)) return;
    double tx = -s.dh_dy / slope, ty = s.dh_dx / slope;
    if (tx * r.dx + ty * r.dy < 0.0) tx = -tx, ty = -ty;
    r.dx = tx;
    r.dy = ty;
    r.x += o.step * tx;
    r.y += o.step * ty;
    onto_shore(r, g, waves);
}

}  // namespace

const char* to_string(RayFlag f) noexcept {
    switch (f) {
        case RayFlag::alive: return "alive";
        case RayFlag::flat: return "flat";
        case RayFlag::aground: return "aground";
        case RayFlag::dead: return "dead";
    }
    return "unknown";
}

FrontSet trace_fronts(const Seafloor& seafloor, const WaveTrain& t, const FrontOptions& o,
                      const DepthContours* isobaths) {
    validate(t, o);
    const bool isobath_mode = o.refraction == FrontRefraction::isobath;
    if (isobath_mode && (isobaths == nullptr || isobaths->size() == 0))
        throw InputError("fronts: isobath refraction needs isobaths (extract_isobaths), got none");
    std::optional<IsobathIndex> index;
    IsobathMode mode;
    if (isobath_mode) {
        index.emplace(*isobaths);
        mode.index = &*index;
    }
    const ElevationGrid& g = seafloor.grid;
    const detail::Box box = detail::domain_box(g);
    mode.scale = std::max(box.x1 - box.x0, box.y1 - box.y0);
    const double len = std::hypot(t.direction_x, t.direction_y);
    const double dx = t.direction_x / len, dy = t.direction_y / len;
    const double omega = 2.0 * std::numbers::pi / t.period;
    const double max_turn = o.max_turn_degrees * std::numbers::pi / 180.0;
    // Depths beyond the table (bicubic overshoot) fall back to the exact solver.
    const detail::WaveTable waves(omega, 1.05 * detail::deepest(g), o.dispersion);
    const auto entries =
        detail::entry_points(g, dx, dy, {omega, t.amplitude, o.breaker_index, o.dispersion}, o.ray_spacing, o.max_rays);
    // Refused up front when even a straight crossing of the domain along the swell needs
    // more fronts, or more points, than the guard rails allow: a tiny step would otherwise
    // run all max_steps fronts before the limit was found.
    const double crossing = std::abs(dx) * (box.x1 - box.x0) + std::abs(dy) * (box.y1 - box.y0);
    const double fronts_needed = crossing / o.step;
    if (fronts_needed > static_cast<double>(o.max_steps))
        throw LimitError("fronts: crossing the " + detail::format_number(crossing) + " m domain at a step of " +
                         detail::format_number(o.step) + " m takes " + detail::format_number(std::ceil(fronts_needed)) +
                         " fronts, more than " + std::to_string(o.max_steps) +
                         " (FrontOptions::max_steps, scene key /fronts/max_steps; lengthen /fronts/step)");
    // max_points, lowered to the points the memory limit holds (FrontSet's arrays alone).
    const double by_memory = std::floor(o.max_bytes / kRunBytesPerFrontPoint);
    const std::size_t max_points =
        by_memory < static_cast<double>(o.max_points) ? static_cast<std::size_t>(std::max(by_memory, 0.0)) : o.max_points;
    const auto memory_note = [&] {
        return max_points < o.max_points ? " (/fronts/max_points " + std::to_string(o.max_points) + " lowered to the " +
                                               detail::format_number(o.max_bytes / 1e9) + " GB memory limit at " +
                                               detail::format_number(kRunBytesPerFrontPoint) + " bytes a point at a run's peak; wave run --max-memory-gb)"
                                         : std::string();
    };
    if (fronts_needed * static_cast<double>(entries.size()) > static_cast<double>(max_points))
        throw LimitError("fronts: " + std::to_string(entries.size()) + " rays crossing the domain in " +
                         detail::format_number(std::ceil(fronts_needed)) + " fronts make more than " +
                         std::to_string(max_points) + " points" + memory_note() +
                         " (FrontOptions::max_points, scene key /fronts/max_points; lengthen /fronts/step or "
                         "raise /trace/ray_spacing)");

    FrontSet out;
    out.omega = omega;
    const auto points_expected = static_cast<std::size_t>(std::ceil(fronts_needed) + 1.0) * entries.size();
    reserve_points(out, std::min<std::size_t>(max_points, points_expected));
    std::vector<Ray> front;
    std::vector<double> gap_b0;  // the width the tube between ray i and i+1 had in the reference plane wave (EntryPoint)
    const detail::EntryPoint* last = nullptr;
    for (const auto& e : entries) {
        if (!(e.depth > 0.0)) continue;  // entering on land
        if (last) gap_b0.push_back((e.s - last->s) * 0.5 * (e.tube + last->tube));
        last = &e;
        Ray r{static_cast<std::uint32_t>(front.size()), e.x, e.y, e.dx, e.dy, e.phase, RayFlag::alive};
        out.entry_break_phase.push_back(e.break_phase);
        r.band = e.depth;
        settle(r, g, waves);
        front.push_back(r);
    }
    out.initial_rays = front.size();
    // Rays start ordered along e = (−dy, dx), so (next − ray) × direction starts at
    // e × d = −1: neighbours keep that sign until they cross.
    constexpr double side = -1.0;
    std::uint32_t next_id = static_cast<std::uint32_t>(front.size());

    // Records the front: amplitudes from the neighbours' spacing, flags.
    const auto record = [&]() {
        const std::size_t n = front.size();
        if (out.ray.size() + n > max_points)
            throw LimitError("fronts: more than " + std::to_string(max_points) + " front points" + memory_note() +
                             " (FrontOptions::max_points, scene key /fronts/max_points; lengthen the step, "
                             "raise split_distance or lower max_turn_degrees)");
        for (std::size_t i = 0; i < n; ++i) {
            Ray& r = front[i];
            const DepthSample& s = r.here;
            double b = 0.0, b0 = 0.0;
            int sides = 0;
            // Spacing across the ray (the width of the ray tube), not along the front:
            // entry points on a domain edge are farther apart than the tube is wide.
            const auto across = [&](const Ray& q) { return std::abs((q.x - r.x) * r.dy - (q.y - r.y) * r.dx); };
            if (i > 0) b += across(front[i - 1]), b0 += gap_b0[i - 1], ++sides;
            if (i + 1 < n) b += across(front[i + 1]), b0 += gap_b0[i], ++sides;
            const double kr = (sides > 0 && b > 0.0) ? std::sqrt(b0 / b) : 1.0;
            const detail::WaveTable::Entry& w = r.wave;
            double a = r.flag == RayFlag::aground ? 0.0 : t.amplitude * w.shoaling * kr;
            a = std::min(a, 0.5 * o.breaker_index * std::max(s.depth, 0.0));  // breaking / caustic cap
            if (r.flag == RayFlag::alive || r.flag == RayFlag::flat)
                r.flag = a < o.flat_amplitude ? RayFlag::flat : RayFlag::alive;
            out.ray.push_back(r.id);
            out.x.push_back(r.x);
            out.y.push_back(r.y);
            out.dir_x.push_back(r.dx);
            out.dir_y.push_back(r.dy);
            out.phase.push_back(r.phase);
            out.k.push_back(w.k);
            out.depth.push_back(s.depth);
            out.slope.push_back(r.slope);
            out.rise.push_back(-(s.dh_dx * r.dx + s.dh_dy * r.dy));
            out.amplitude.push_back(a);
            out.flag.push_back(r.flag);
            // A caustic: this ray and a neighbour have swapped sides (rays crossed).
            const auto flipped = [&](const Ray& p, const Ray& q) {
                const Ray& travel = p.flag == RayFlag::aground ? q : p;  // an aground ray points along the shore
                return side * ((q.x - p.x) * travel.dy - (q.y - p.y) * travel.dx) <= 0.0;
            };
            const bool caustic = r.flag != RayFlag::aground &&
                                 ((i > 0 && flipped(front[i - 1], r)) || (i + 1 < n && flipped(r, front[i + 1])));
            out.caustic.push_back(caustic ? 1 : 0);
            out.caustic_points += caustic;
        }
        out.front_offsets.push_back(out.ray.size());
    };

    record();
    // Neighbours a new ray goes between: they drifted apart (most pairs are well inside
    // the split distance, ruled out by the squared distance).
    const double split2 = o.split_distance * o.split_distance;
    const auto diverged = [&](const Ray& a, const Ray& b) {
        const bool both_flat = a.flag == RayFlag::flat && b.flag == RayFlag::flat;
        const bool both_aground = a.flag == RayFlag::aground && b.flag == RayFlag::aground;
        // Neighbours whose order across the front has flipped have crossed (a caustic,
        // kept as it is): the gap between them is not a diverging tube to fill. Nor
        // is a gap between rays heading apart by more than a right angle.
        const bool crossed = side * ((b.x - a.x) * a.dy - (b.y - a.y) * a.dx) <= 0.0 ||
                             a.dx * b.dx + a.dy * b.dy <= 0.0;
        if (both_flat || both_aground || crossed) return false;
        const double ex = b.x - a.x, ey = b.y - a.y;
        return !(ex * ex + ey * ey < 0.999 * split2) && norm(ex, ey) > o.split_distance;
    };
    std::vector<Ray> spare;  // the next front is built here, then swapped in (no allocation a step)
    std::vector<double> spare_gaps;
    for (std::size_t step = 0;; ++step) {
        const bool moving = std::any_of(front.begin(), front.end(),
                                        [](const Ray& r) { return r.flag == RayFlag::alive || r.flag == RayFlag::flat; });
        if (!moving) break;
        if (step >= o.max_steps)
            throw LimitError("fronts: more than " + std::to_string(o.max_steps) +
                             " steps (FrontOptions::max_steps, scene key /fronts/max_steps; raise it or lengthen the step)");
        const bool trapped_by_path = static_cast<double>(step + 1) > kTrappedCrossings * fronts_needed;
        for (Ray& r : front) {
            if (r.flag == RayFlag::aground) {
                follow_shore(r, g, waves, o);
            } else {
                if (isobath_mode) advance_isobath(r, mode, g, waves, o);
                else advance(r, g, waves, o);
                if (inside(box, r.x, r.y) && (r.ashore || r.here.depth <= 0.0)) {
                    r.flag = RayFlag::aground;
                    ++out.rays_aground;
                }
                // Refraction can trap rays on closed orbits (round an island's shelf):
                // a ray that has turned a full circle is not part of an advancing front;
                // nor is one still moving after three straight crossings of the domain
                // (guided along a coast or round a cove, its turns cancel).
                if (std::abs(r.turn) > max_turn || (trapped_by_path && r.flag != RayFlag::aground)) {
                    r.flag = RayFlag::dead;
                    ++out.rays_trapped;
                }
            }
            if (!inside(box, r.x, r.y)) r.flag = RayFlag::dead;
        }
        retire_walkers(front);
        remove_dead(front, gap_b0);
        // Over-sampling: a new ray midway between neighbours that drifted apart. Most
        // steps insert none, and then the front stays where it is.
        const auto first_gap = std::adjacent_find(front.begin(), front.end(), diverged);
        if (first_gap != front.end()) {
            std::vector<Ray>& grown = spare;
            std::vector<double>& grown_gaps = spare_gaps;
            const auto unchanged = static_cast<std::size_t>(first_gap - front.begin());
            grown.assign(front.begin(), first_gap);
            grown_gaps.assign(gap_b0.begin(), gap_b0.begin() + static_cast<std::ptrdiff_t>(unchanged));
            for (std::size_t i = unchanged; i < front.size(); ++i) {
                grown.push_back(front[i]);
                if (i + 1 == front.size()) break;
                const Ray& a = front[i];
                const Ray& b = front[i + 1];
                if (diverged(a, b)) {
                    if (out.initial_rays + out.inserted_rays >= o.max_rays)
                        throw LimitError("fronts: more than " + std::to_string(o.max_rays) +
                                         " rays (FrontOptions::max_rays, scene key /trace/max_rays; raise it or raise split_distance)");
                    Ray m{next_id++, 0.5 * (a.x + b.x), 0.5 * (a.y + b.y), a.dx + b.dx, a.dy + b.dy,
                          0.5 * (a.phase + b.phase), RayFlag::alive, 0.5 * (a.turn + b.turn)};
                    m.band = a.band;  // isobath mode: the new ray starts in its neighbour's band
                    settle(m, g, waves);
                    const double l = norm(m.dx, m.dy);
                    m.dx = l > 0.0 ? m.dx / l : a.dx;
                    m.dy = l > 0.0 ? m.dy / l : a.dy;
                    if (m.here.depth <= 0.0) {  // the gap's middle is on land: a new ray on its shore
                        m.flag = RayFlag::aground;
                        onto_shore(m, g, waves);
                    }
                    grown_gaps.push_back(0.5 * gap_b0[i]);
                    grown_gaps.push_back(0.5 * gap_b0[i]);
                    grown.push_back(m);
                    ++out.inserted_rays;
                } else {
                    grown_gaps.push_back(gap_b0[i]);
                }
            }
            front.swap(grown);
            gap_b0.swap(grown_gaps);
        }
        record();
    }
    out.entry_break_phase.resize(next_id, std::numeric_limits<double>::quiet_NaN());  // inserted rays: none
    return out;
}

std::string fronts_to_csv(const FrontSet& f) {
    std::ostringstream out;
    out.precision(17);
    out << "front,ray,x,y,dir_x,dir_y,phase,k,depth,slope,rise,amplitude,flag\n";
    for (std::size_t fr = 0; fr < f.front_count(); ++fr)
        for (std::size_t i = f.front_offsets[fr]; i < f.front_offsets[fr + 1]; ++i)
            out << fr << ',' << f.ray[i] << ',' << f.x[i] << ',' << f.y[i] << ',' << f.dir_x[i] << ',' << f.dir_y[i]
                << ',' << f.phase[i] << ',' << f.k[i] << ',' << f.depth[i] << ',' << f.slope[i] << ',' << f.rise[i]
                << ',' << f.amplitude[i] << ',' << to_string(f.flag[i]) << '\n';
    return out.str();
}

}  // namespace wave
