// Jeschke, Birkholz & Schumann (WSCG 2003): a procedural breaker whose shape (§4,
// table 1) and foam (§3.1) are pure functions of space and time, parametrised here from
// the traced rays instead of by hand (the paper's stated future work).
#include "core/smoothstep.h"
#include "core/splitmix.h"
#include "libwave/errors.h"
#include "libwave/motion.h"
#include "surface/triangle_locator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>

namespace wave {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * std::numbers::pi;
// jeschke_drawn_lips: a breaking section is drawn in full where its slope passes 8°
// (a round crest's steepest is atan(π H/W), 6° at 5H/W = 0.2): its face and lip, and
// the crest's back that runs forward with them; the weight rises with the slope from
// flat water, so that it is continuous in time (radians).
constexpr double kDrawnSlope = 8.0 * pi / 180.0;

double lerp(double a, double b, double t) noexcept { return a + (b - a) * t; }

// x^p for x in [0, 1]; 0^0 = 1 as in the formulas (only ever multiplied by a k that is
// 0 there: see the note on table 1 in jeschke_constants).
double power(double x, double p) noexcept { return p == 1.0 ? x : p == 0.0 ? 1.0 : std::pow(x, p); }

// x^p on [0, 1], with a finite slope at x = 0 when p < 1: the mirrored power
// 1 − (1 − x)^{1/p} rises the same way (from 0 to 1, concave), as back_half does for
// k1. Table 1's powers below 1 otherwise have an infinite slope where they start: in s
// (s2^k4, the exponential term, and s2^k6, the rotation, at the wave's edge s2 = 0,
// where a vertex passes from one crest to the next: 17 c early in the breaking phase,
// k4 = 4t) and in time (t^0.85 as breaking starts, t^0.7 as collapsing starts).
double finite_power(double x, double p) noexcept {
    if (p >= 1.0 || p <= 0.0) return power(x, p);
    return 1.0 - std::pow(1.0 - x, 1.0 / p);
}

// The shape's point for one half (s1, s2 of §4 and that half's constants).
BreakerShapePoint half_point(double s1, double s2, const BreakerConstants& c, double curl) noexcept {
    const auto& k = c.k;
    const double z1 = k[2] * (1.0 + std::cos((s2 - 1.0) * pi)) / 2.0 + (k[3] != 0.0 ? k[3] * finite_power(s2, k[4]) : 0.0);
    const double phi = k[5] != 0.0 ? pi * curl * k[5] * finite_power(s2, k[6]) / 2.0 : 0.0;
    const double a = 0.5 - s1;
    if (phi == 0.0) return {a + 0.5, z1 * k[7]};  // the round phase: no rotation (most of the sea)
    const double cp = std::cos(phi), sp = std::sin(phi);
    return {a * cp - z1 * sp + 0.5, (a * sp + z1 * cp) * k[7]};
}

// The seam that joins the two halves at the lip where their constants give different
// lip points (the collapsing phase: the back's jet is thrown forward while the front's
// face subsides). Its half width (in s) grows with the gap, so that the seam's own
// slope, ¾ gap / width, stays below ⅜ of the wave per unit s: a fixed 0.03 drew the
// jet across a 0.36 W gap in 6 % of a period, at 7.6 × the phase speed.
constexpr double lip_seam_min = 0.03, lip_seam_max = 0.3, lip_seam_per_gap = 2.0;

// The ratio scale/width (5H/L) at which the seam's gap weighs the shape's vertical
// moves against its horizontal ones.
constexpr double height_ratio = 0.25;

double lip_seam(const BreakerShapePoint& lb, const BreakerShapePoint& lf) noexcept {
    const double gap = std::hypot(lb.y - lf.y, height_ratio * (lb.z - lf.z));
    return std::clamp(lip_seam_per_gap * gap, lip_seam_min, lip_seam_max);
}

}  // namespace

BreakerConstants jeschke_constants(BreakerPhase phase, double t, bool front) noexcept {
    // Table 1 with every constant entry blended from the previous phase's final value
    // (round → breaking → collapsing). The breaking k5, printed 3/t², is read as t^{3/2}:
    // the one reading continuous at both ends (0 where the round phase ends, 1 = the
    // collapsing phase's constant) — the lip turns through 90° and falls onto the water
    // ahead (figure 3b); 3t² would turn it through 270°, back under the wave.
    t = std::clamp(t, 0.0, 1.0);
    BreakerConstants c;
    auto& k = c.k;
    switch (phase) {
        case BreakerPhase::round:
            k = {0.0, 1.0, 0.25, 0.0, 0.0, 0.0, 0.0, 0.8 * t};
            break;
        case BreakerPhase::breaking:
            if (front)
                k = {0.0, lerp(1.0, 2.0, t), (1.0 - finite_power(t, 0.85)) / 4.0, finite_power(t, 0.85) / 4.0, lerp(0.0, 4.0, t),
                     t * std::sqrt(t), lerp(0.0, 16.0, t), (4.0 + t) / 5.0};
            else
                k = {0.0, lerp(1.0, 0.7, t), 0.25, 0.0, 0.0, t * std::sqrt(t), lerp(0.0, 4.0, t), (4.0 + t) / 5.0};
            break;
        case BreakerPhase::collapsing:
        case BreakerPhase::dead:
            if (phase == BreakerPhase::dead) t = 1.0;
            if (front)
                k = {0.0, 2.0, 0.0, (1.0 - t) / 4.0, 4.0, 1.0, 16.0, 1.0 - t};
            else
                k = {0.0, lerp(0.7, 0.5, t), 0.25, finite_power(t, 0.7) / 2.0, lerp(0.0, 40.0, t), 1.0, 4.0, 1.0 - t};
            break;
    }
    return c;
}

namespace {

// One half of the shape away from the lip seam (§4's s1, s2 of that half).
BreakerShapePoint back_half(double s, const BreakerConstants& back, double curl) noexcept {
    // k1 < 1 (the back half while breaking and collapsing) printed as (2s)^k1 has an
    // infinite slope at the back edge: points at the trough would race as crests
    // pass. The mirrored power 1 − (1 − 2s)^{1/k1} spreads the points the same way
    // (sparse at the trough, dense towards the lip) with a finite slope; the curve
    // itself does not depend on k1 (s1 and s2 are both functions of it).
    const double k1 = back.k[1];
    const double u = k1 >= 1.0 ? power(2.0 * s, k1) : 1.0 - std::pow(1.0 - 2.0 * s, 1.0 / k1);
    return half_point(u / 2.0, u, back, curl);
}

BreakerShapePoint front_half(double s, const BreakerConstants& front, double curl) noexcept {
    const double u = power(2.0 * s - 1.0, front.k[1]);
    return half_point((1.0 + u) / 2.0, 1.0 - u, front, curl);
}

}  // namespace

BreakerShapePoint jeschke_shape(double s, const BreakerConstants& back, const BreakerConstants& front, double curl) noexcept {
    s = std::clamp(s, 0.0, 1.0);
    const bool is_front = s >= 0.5;
    BreakerShapePoint p = is_front ? front_half(s, front, curl) : back_half(s, back, curl);
    const double d = std::abs(s - 0.5);
    if (d >= lip_seam_max) return p;
    const BreakerShapePoint lb = half_point(0.5, 1.0, back, curl), lf = half_point(0.5, 1.0, front, curl);
    if (const double seam = lip_seam(lb, lf); d < seam) {
        // Both halves meet at their mean lip point; the blend fades over the seam.
        const double w = 1.0 - d / seam, w2 = w * w * (3.0 - 2.0 * w);  // smoothstep
        const double sign = is_front ? 1.0 : -1.0;  // back moves by −D/2, front by +D/2
        p.y += sign * 0.5 * (lb.y - lf.y) * w2;
        p.z += sign * 0.5 * (lb.z - lf.z) * w2;
    }
    return p;
}

BreakerLife jeschke_life(double psi, double rise, double break_phase, double breaking_length, double end_phase,
                         double start) noexcept {
    if (psi >= end_phase) return {BreakerPhase::dead, 1.0};
    const double collapse_start = break_phase + breaking_length;
    if (psi >= collapse_start) return {BreakerPhase::collapsing, (psi - collapse_start) / (end_phase - collapse_start)};
    if (psi >= break_phase) return {BreakerPhase::breaking, (psi - break_phase) / breaking_length};
    return {BreakerPhase::round, rise > 0.0 ? std::clamp((psi - start) / rise, 0.0, 1.0) : 1.0};
}

namespace {

// Foam produced by a crest at the moment it passes phase ψ: none while round, ramping
// up over the first `onset` of the breaking phase, full while breaking and collapsing.
double foam_yield(const BreakerLife& life, double onset) noexcept {
    switch (life.phase) {
        case BreakerPhase::breaking:
            return onset > 0.0 ? std::min(1.0, life.t / onset) : 1.0;
        case BreakerPhase::collapsing:
            return 1.0;
        default:
            return 0.0;
    }
}

// A fixed, platform-independent draw per wave (core/splitmix.h).
using detail::splitmix64;

double unit_draw(std::uint64_t x) noexcept {  // in [−1, 1)
    return static_cast<double>(splitmix64(x) >> 11) * 0x1.0p-52 - 1.0;
}

// The crest nearest a vertex in phase: ωt − Φ = 2πn + δ, δ ∈ [−π, π).
long long crest_index(double wt_minus_phase) noexcept {
    return static_cast<long long>(std::floor((wt_minus_phase + pi) / two_pi));
}

// How far vertex v's crests trail the phase whose life they live (JeschkeMotionPlan::lag).
double lag_of(const JeschkeMotionPlan& p, std::size_t v) noexcept { return p.lag.empty() ? 0.0 : p.lag[v]; }

// Where the life vertex v lives begins (JeschkeMotionPlan::life_start).
double start_of(const JeschkeMotionPlan& p, std::size_t v) noexcept {
    return p.life_start.empty() ? 0.0 : static_cast<double>(p.life_start[v]);
}

void check_lags(const JeschkeMotionPlan& p, const char* what) {
    if (!p.lag.empty() && p.lag.size() != p.vertex_count())
        throw InputError(std::string(what) + ": " + std::to_string(p.lag.size()) + " lags for " + std::to_string(p.vertex_count()) + " vertices");
    if (!p.life_start.empty() && p.life_start.size() != p.vertex_count())
        throw InputError(std::string(what) + ": " + std::to_string(p.life_start.size()) + " life starts for " +
                         std::to_string(p.vertex_count()) + " vertices");
}

// Break/end phases of crest n at vertex v, when it stands at phase ψ (the plan's own
// when crests are alike, or when ψ lies seaward of any crest's break: there every
// crest is round, and no crest breaks more than variation · 2π early).
CrestPhases crest_phases(const JeschkeMotionPlan& p, std::size_t v, long long n, double psi) noexcept {
    if (p.loop_periods() == 1 || psi < static_cast<double>(p.break_phase[v]) - p.variation * two_pi)
        return {p.break_phase[v], p.breaking_length[v], p.end_phase[v]};
    const long long m = static_cast<long long>(p.crest_draws.size());
    return vary_crest(start_of(p, v) + p.rise[v], p.break_phase[v], p.breaking_length[v], p.end_phase[v],
                      p.crest_draws[static_cast<std::size_t>(((n % m) + m) % m)], p.variation);
}

void check_options(const JeschkeBreakerOptions& o) {
    const auto check = [](double v, double lo, double hi, const char* name) {
        if (!(v >= lo && v <= hi))
            throw InputError(std::string("breakers: ") + name + " must be in [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "], got " + std::to_string(v));
    };
    check(o.breaker_index, 0.1, 2.0, "breaker_index");
    check(o.breaking_share, 0.01, 0.99, "breaking_share");
    check(o.max_breaking_wavelengths, 0.05, 100.0, "max_breaking_wavelengths");
    check(o.min_surf_zone_wavelengths, 0.0, 100.0, "min_surf_zone_wavelengths");
    check(o.rise_wavelengths, 0.0, 100.0, "rise_wavelengths");
    if (!(o.stable_index > 0.0 && o.stable_index <= 2.0))
        throw InputError("breakers: stable_index must be in (0, 2], got " + std::to_string(o.stable_index));
    check(o.min_reform_wavelengths, 0.05, 100.0, "min_reform_wavelengths");
    check(o.foam_fade_time, 1e-3, 1e6, "foam_fade_time");
    check(o.foam_onset, 0.0, 1.0, "foam_onset");
    for (double c : {o.curl_spilling, o.curl_plunging, o.curl_collapsing, o.curl_surging}) check(c, 0.0, 2.0, "curl");
    check(o.wave_variation, 0.0, 0.5, "wave_variation");
    check(o.varied_waves, 1, 16, "varied_waves");
}

}  // namespace

CrestPhases vary_crest(double rise, double break_phase, double breaking_length, double end_phase,
                       const CrestVariation& draw, double variation) noexcept {
    if (!std::isfinite(break_phase) || variation <= 0.0) return {break_phase, breaking_length, end_phase};
    const double collapse = end_phase - break_phase - breaking_length;  // the collapse zone (rad)
    // Later by at most a quarter of the collapse zone and earlier end by at most
    // variation (<= ½) of it: at least ¼ of it remains, so no crest skips collapsing.
    const double shifted = break_phase + draw.break_shift * variation * two_pi;
    const double b = std::clamp(shifted, std::min(rise, break_phase), break_phase + 0.25 * collapse);
    const double e = end_phase - 0.5 * (1.0 + draw.end_shift) * variation * collapse;
    return {b, breaking_length, e};
}

namespace {

// One ray's breaker: where it breaks and the lengths of its life (rad along the ray).
// A ray that breaks, re-forms and breaks again lives several: `first` is the first of
// its vertices (offshore to its end) that lives this one, `start` the phase where it
// begins (0, or where the previous surf zone ended).
struct RayLife {
    RayBreak rb;
    double start = 0.0, rise = 0.0, breaking = 0.0, curl = 1.0, end = 0.0;
    bool breaks_at_start = false;  // capped on its first vertex, with no earlier break given
    std::size_t first = 0;        // index into the ray's vertices
    std::size_t break_vertex = 0;  // index of the first vertex at or past the break
};

constexpr double kNever = std::numeric_limits<double>::infinity();

// Where a quantity going linearly from `a` to `b` crosses 0 (a and b on its two sides, or
// b on it), as a share of the way: the break's and the re-form's place between two vertices.
double crossing_share(double a, double b) noexcept { return a != b ? std::clamp(a / (a - b), 0.0, 1.0) : 1.0; }
// The least surf zone (local wavelengths) of a crest that re-forms behind it.
constexpr double kReformedSurfZone = 1.5;

// The life of the ray through `vs` (its vertices from offshore to its end). A ray
// capped on its first vertex broke before it: at `before` when that is given (the
// apron beyond the side it entered across, or its neighbours' break where it was
// inserted), and it lives the rest of that life here, not a new one from that vertex.
// The search for the break starts at vertex `from` (0: the ray's first life).
RayLife ray_life(const RayStrips& strips, std::uint32_t id, const std::vector<std::uint32_t>& vs, std::size_t from, double before,
                 double deep_height, double deep_wavelength, const JeschkeBreakerOptions& o) {
    // Depth-limited breaking H = 2A >= γh (dry counts): the first crossing of
    // f = 2A − γh, located between the two vertices by linear interpolation.
    const auto f = [&](std::uint32_t v) {
        return strips.depth[v] <= 0.0 ? 1.0 : 2.0 * strips.amplitude[v] - o.breaker_index * strips.depth[v];
    };
    RayLife life;
    RayBreak& rb = life.rb;
    rb.ray = id;
    rb.end_phase = strips.phase[vs.back()];
    std::size_t i = from;
    while (i < vs.size() && f(vs[i]) < 0.0) ++i;
    life.first = from;
    life.break_vertex = i;
    life.rise = o.rise_wavelengths * two_pi;
    life.end = kNever;  // where a crest dies: the ray's end, or later
    if (i == vs.size()) {
        rb.break_phase = rb.end_phase = kNever;
        return life;
    }
    rb.breaks = true;
    const std::uint32_t b = vs[i];
    double w = 0.0;  // share of the way from the previous vertex to b
    if (i > from) {
        w = crossing_share(f(vs[i - 1]), f(b));
    }
    const std::uint32_t a = i > from ? vs[i - 1] : b;
    const auto at = [&](const std::vector<double>& q) { return q[a] + w * (q[b] - q[a]); };
    rb.break_phase = at(strips.phase);
    const bool broke_before = i == 0 && before < rb.break_phase;  // false for NaN
    life.breaks_at_start = i == 0 && !broke_before;
    if (broke_before) rb.break_phase = before;
    rb.x = at(strips.x);
    rb.y = at(strips.y);
    rb.depth = std::max(0.0, at(strips.depth));
    rb.height = 2.0 * at(strips.amplitude);
    // Mean bottom slope over one local wavelength seaward of the break.
    const double k_b = strips.k[a] > 0.0 && std::isfinite(strips.k[a]) ? strips.k[a] : 2.0 * pi / deep_wavelength;
    const double wavelength = two_pi / k_b;
    double run = 0.0, h_back = rb.depth;
    double px = rb.x, py = rb.y;
    for (std::size_t j = i; j-- > 0 && run < wavelength;) {
        run += std::hypot(strips.x[vs[j]] - px, strips.y[vs[j]] - py);
        px = strips.x[vs[j]];
        py = strips.y[vs[j]];
        h_back = strips.depth[vs[j]];
    }
    // A ray capped on its first vertex (it entered broken, or was inserted in the surf
    // zone) has nothing seaward: the bottom's rise along it there. It used to count as
    // flat, ξ = 0, a spilling breaker whose lip curled less than its plunging
    // neighbours': a notch in the lip where such rays run.
    const double slope = std::max(0.0, run > 0.0 ? (h_back - rb.depth) / run : strips.rise[b]);
    rb.iribarren = iribarren_number(slope, deep_height, deep_wavelength);
    rb.type = classify_breaker(rb.iribarren, o.thresholds);
    life.curl = rb.type == BreakerType::spilling     ? o.curl_spilling
                : rb.type == BreakerType::plunging   ? o.curl_plunging
                : rb.type == BreakerType::collapsing ? o.curl_collapsing
                                                     : o.curl_surging;
    // A steep shore ends the ray a few metres past the break: breaking and collapsing
    // squeezed into that run moved lip vertices at 13 c (breaking Okushiri's islet).
    // The crest's life spans at least min_surf_zone_wavelengths; the shore cuts it.
    life.end = std::max(rb.end_phase, rb.break_phase + o.min_surf_zone_wavelengths * two_pi);
    life.breaking = std::min(o.breaking_share * (life.end - rb.break_phase), o.max_breaking_wavelengths * two_pi);
    if (!(life.breaking > 0.0)) life.breaking = 1e-6;  // breaks on its last vertex
    if (!broke_before) life.rise = std::min(life.rise, rb.break_phase);  // else the rise, too, was before
    return life;
}

// Rays capped on their first vertex with no earlier break given — inserted where
// neighbours drifted apart in the surf zone, or entering where the apron gives none —
// break where the rays beside their first vertex broke (the mean of those that broke
// there or before), in order of ray id: an inserted ray's neighbours are older.
void inherit_breaks(const RayStrips& strips, const std::map<std::uint32_t, std::vector<std::uint32_t>>& rays,
                    std::map<std::uint32_t, RayLife>& lives, double deep_height, double deep_wavelength,
                    const JeschkeBreakerOptions& o) {
    std::map<std::uint32_t, std::vector<std::uint32_t>> beside;  // first vertex → the rays of the vertices beside it
    for (const auto& [id, life] : lives)
        if (life.breaks_at_start) beside[rays.at(id).front()];
    if (beside.empty()) return;
    for (std::size_t t = 0; t + 2 < strips.triangles.size(); t += 3)
        for (std::size_t c = 0; c < 3; ++c)
            if (const auto it = beside.find(strips.triangles[t + c]); it != beside.end())
                for (std::size_t d = 1; d < 3; ++d) it->second.push_back(strips.ray[strips.triangles[t + (c + d) % 3]]);
    for (auto& [id, life] : lives) {
        if (!life.breaks_at_start) continue;
        const std::uint32_t first = rays.at(id).front();
        double sum = 0.0;
        std::size_t count = 0;
        std::vector<std::uint32_t> others = beside.at(first);
        std::sort(others.begin(), others.end());
        others.erase(std::unique(others.begin(), others.end()), others.end());
        for (const std::uint32_t r : others) {
            const RayBreak& n = lives.at(r).rb;
            if (r != id && n.breaks && n.break_phase <= strips.phase[first]) sum += n.break_phase, ++count;
        }
        if (count > 0) life = ray_life(strips, id, rays.at(id), 0, sum / static_cast<double>(count), deep_height, deep_wavelength, o);
    }
}

// The lives a ray lives after its first (`first`, whose end and breaking length are cut
// back when the crest re-forms): past each break, the crest re-forms where its height
// falls below Γh in water (the wave field's stop: its heights re-form behind a bar)
// and breaks again where H >= γh once more — a new life from still water at the end of
// the surf zone before. A re-formed stretch shorter than min_reform_wavelengths is
// broken through (one surf zone); a crest that never breaks again lives on as before.
std::vector<RayLife> reformed_lives(const RayStrips& strips, std::uint32_t id, const std::vector<std::uint32_t>& vs, RayLife& first,
                                    double deep_height, double deep_wavelength, const JeschkeBreakerOptions& o) {
    std::vector<RayLife> later;
    const double stable = std::min(o.stable_index, o.breaker_index);
    const auto g = [&](std::uint32_t v) { return 2.0 * strips.amplitude[v] - stable * strips.depth[v]; };
    const auto life = [&]() -> RayLife& { return later.empty() ? first : later.back(); };
    std::size_t i = first.break_vertex;
    while (life().rb.breaks && i < vs.size()) {
        while (i < vs.size() && !(strips.depth[vs[i]] > 0.0 && g(vs[i]) < 0.0)) ++i;
        if (i >= vs.size()) break;
        // Where the height fell below Γh, between vertex i − 1 and i.
        double reform = strips.phase[vs[i]];
        if (i > 0) {
            const std::uint32_t a = vs[i - 1], b = vs[i];
            reform = strips.phase[a] + crossing_share(g(a), g(b)) * (strips.phase[b] - strips.phase[a]);
        }
        RayLife next = ray_life(strips, id, vs, i, std::nan(""), deep_height, deep_wavelength, o);
        if (!next.rb.breaks) break;  // it never breaks again: the surf zone runs on to the ray's end
        RayLife& now = life();
        // A bar's surf zone is short (half a wavelength on the test's bar): squeezed into
        // it, breaking and collapsing moved vertices at 2.6 c (1.8 c over one wavelength).
        // The broken crest collapses over at least 1.5 wavelengths (≤ 1.5 c), a bore
        // carried on into the trough, before the wave re-forms.
        const double end = std::max(reform, now.rb.break_phase + std::max(o.min_surf_zone_wavelengths, kReformedSurfZone) * two_pi);
        if (next.rb.break_phase - end < o.min_reform_wavelengths * two_pi) {  // broken through
            i = next.break_vertex;
            continue;
        }
        now.end = end;
        now.breaking = std::min(o.breaking_share * (end - now.rb.break_phase), o.max_breaking_wavelengths * two_pi);
        next.start = end;
        next.rise = std::min(std::max(o.rise_wavelengths, o.min_reform_wavelengths) * two_pi, next.rb.break_phase - end);
        next.first = now.break_vertex;
        while (next.first < next.break_vertex && strips.phase[vs[next.first]] < end) ++next.first;
        next.rb.surf_zone = now.rb.surf_zone + 1;
        i = next.break_vertex;
        later.push_back(next);
    }
    return later;
}

}  // namespace

JeschkeMotionPlan plan_jeschke_breakers(const RayStrips& strips, double deep_height, double deep_wavelength,
                                        const JeschkeBreakerOptions& o) {
    check_options(o);
    if (!(deep_height > 0.0) || !(deep_wavelength > 0.0))
        throw InputError("breakers: the wave train needs a deep-water height and wavelength > 0");
    const std::size_t n = strips.vertex_count();
    JeschkeMotionPlan p;
    p.omega = strips.omega;
    p.foam_fade_time = o.foam_fade_time;
    p.foam_onset = o.foam_onset;
    p.variation = o.varied_waves > 1 ? o.wave_variation : 0.0;
    for (std::uint32_t i = 0; i < o.varied_waves && p.variation > 0.0; ++i)
        p.crest_draws.push_back({unit_draw(o.variation_seed * 0x100000001B3ull + 2 * i),
                                 unit_draw(o.variation_seed * 0x100000001B3ull + 2 * i + 1)});
    p.x = strips.x;
    p.y = strips.y;
    p.dir_x = strips.dir_x;
    p.dir_y = strips.dir_y;
    p.phase = strips.phase;

    // Each ray's vertices from offshore to its end, and its life.
    std::map<std::uint32_t, std::vector<std::uint32_t>> rays;
    for (std::size_t v = 0; v < n; ++v) rays[strips.ray[v]].push_back(static_cast<std::uint32_t>(v));
    std::map<std::uint32_t, RayLife> lives;
    for (auto& [id, vs] : rays) {
        std::sort(vs.begin(), vs.end(), [&](std::uint32_t a, std::uint32_t b) { return strips.step[a] < strips.step[b]; });
        const double before = id < strips.entry_break_phase.size() ? strips.entry_break_phase[id] : std::nan("");
        lives.emplace(id, ray_life(strips, id, vs, 0, before, deep_height, deep_wavelength, o));
    }
    inherit_breaks(strips, rays, lives, deep_height, deep_wavelength, o);
    p.break_phase.resize(n);
    p.end_phase.resize(n);
    p.rise.resize(n);
    p.breaking_length.resize(n);
    p.curl.resize(n);
    std::vector<float> life_start(n, 0.0f);
    bool reforms = false;
    for (auto& [id, first] : lives) {
        const std::vector<std::uint32_t>& vs = rays.at(id);
        std::vector<RayLife> all{first};
        for (RayLife& later : reformed_lives(strips, id, vs, all.front(), deep_height, deep_wavelength, o)) all.push_back(later);
        reforms = reforms || all.size() > 1;
        for (std::size_t k = 0; k < all.size(); ++k) {
            const RayLife& life = all[k];
            const std::size_t last = k + 1 < all.size() ? all[k + 1].first : vs.size();
            for (std::size_t j = life.first; j < last; ++j) {
                const std::uint32_t v = vs[j];
                p.break_phase[v] = static_cast<float>(life.rb.break_phase);
                p.end_phase[v] = static_cast<float>(life.end);
                p.rise[v] = static_cast<float>(life.rise);
                p.breaking_length[v] = static_cast<float>(life.breaking);
                p.curl[v] = static_cast<float>(life.curl);
                life_start[v] = static_cast<float>(life.start);
            }
            p.rays.push_back(life.rb);
        }
    }
    if (reforms) p.life_start = std::move(life_start);

    if (o.lip == BreakerLip::outer || o.lip == BreakerLip::curl) {
        const auto [lo, hi] = std::minmax({o.curl_spilling, o.curl_plunging, o.curl_collapsing, o.curl_surging});
        p.sections = plan_breaker_sections(lo, hi, o.section_bounds);
        if (o.lip == BreakerLip::curl) p.curl_sections = plan_breaker_sections(lo, hi, o.section_bounds, true);
    }

    // Shape size per vertex, the still-water mean removed, and the foam a crest leaves.
    p.width.resize(n);
    p.scale.resize(n);
    p.mean_level.resize(n);
    p.foam_yield.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
        const double k = strips.k[v];
        const bool wet = strips.depth[v] > 0.0 && k > 0.0 && std::isfinite(k);
        p.width[v] = wet ? static_cast<float>(two_pi / k) : 0.0f;
        p.scale[v] = wet ? static_cast<float>(5.0 * 2.0 * strips.amplitude[v]) : 0.0f;
        const BreakerLife here = jeschke_life(p.phase[v], p.rise[v], p.break_phase[v], p.breaking_length[v], p.end_phase[v], start_of(p, v));
        // The round shape's mean (k7/8 of the scale) centres the offshore swell on still
        // water; it is held through breaking (the crest then stands ~0.75 H above still
        // water, as breaker crests do) and fades with k7 while the wave collapses.
        p.mean_level[v] = static_cast<float>(p.scale[v] * std::min(0.8, jeschke_constants(here.phase, here.t, false).k[7]) / 8.0);
        p.foam_yield[v] = static_cast<float>(foam_yield(here, o.foam_onset));
    }
    return p;
}

JeschkeMotionPlan resample_jeschke_breakers(const JeschkeMotionPlan& src, std::span<const std::uint32_t> triangles,
                                            std::span<const double> x, std::span<const double> y) {
    if (x.size() != y.size()) throw InputError("resample breakers: x and y differ in length");
    const std::size_t n = x.size(), nt = triangles.size() / 3;
    JeschkeMotionPlan p;
    p.omega = src.omega;
    p.foam_fade_time = src.foam_fade_time;
    p.foam_onset = src.foam_onset;
    p.crest_draws = src.crest_draws;
    p.variation = src.variation;
    p.sections = src.sections;
    p.curl_sections = src.curl_sections;
    p.rays = src.rays;
    p.x.assign(x.begin(), x.end());
    p.y.assign(y.begin(), y.end());
    p.dir_x.assign(n, 1.0);
    p.dir_y.assign(n, 0.0);
    p.phase.assign(n, 0.0);
    constexpr float never = std::numeric_limits<float>::infinity();
    for (auto* f : {&p.width, &p.scale, &p.mean_level, &p.rise, &p.breaking_length, &p.curl, &p.foam_yield}) f->assign(n, 0.0f);
    p.break_phase.assign(n, never);
    p.end_phase.assign(n, never);
    if (!src.life_start.empty()) p.life_start.assign(n, 0.0f);
    if (nt == 0 || n == 0) return p;

    const detail::TriangleLocator locator(src.x, src.y, triangles);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            detail::TriangleLocator::Hit h;
            if (!locator.locate(x[v], y[v], h)) continue;
            const std::uint32_t a = h.a, b = h.b, c = h.c;
            double wa = h.wa, wb = h.wb, wc = h.wc;
            p.phase[v] = wa * src.phase[a] + wb * src.phase[b] + wc * src.phase[c];
            if (!src.life_start.empty()) {
                // A corner's life holds from its start to its end (the next life's start
                // on a ray that re-forms; past the ray's end on its last). Only corners
                // whose lives hold at the point's phase are blended: beside a re-form,
                // one life collapsing into still water and the next rising from it; across
                // rays (a bar's edge, a rip channel), the lives there blend as lives do.
                const double phi = p.phase[v];
                const auto holds = [&](std::uint32_t q) {
                    constexpr double slack = 1e-3;  // rad: the float phases' rounding
                    return src.life_start[q] <= phi + slack && !(phi > static_cast<double>(src.end_phase[q]) + slack);
                };
                const double ha = holds(a) ? wa : 0.0, hb = holds(b) ? wb : 0.0, hc = holds(c) ? wc : 0.0, sum = ha + hb + hc;
                if (sum > 0.0) {
                    wa = ha / sum, wb = hb / sum, wc = hc / sum;
                } else {  // none holds (rounding at a ray's end): the nearest corner's
                    const int pick = wa >= wb && wa >= wc ? 0 : wb >= wc ? 1 : 2;
                    wa = pick == 0 ? 1.0 : 0.0, wb = pick == 1 ? 1.0 : 0.0, wc = pick == 2 ? 1.0 : 0.0;
                }
                p.life_start[v] = static_cast<float>(wa * src.life_start[a] + wb * src.life_start[b] + wc * src.life_start[c]);
            }
            const auto mix = [&](const auto& f) { return wa * f[a] + wb * f[b] + wc * f[c]; };
            const auto mixf = [&](const std::vector<float>& f) {
                // A ray that never breaks (+inf) keeps the point round.
                if (!std::isfinite(f[a]) || !std::isfinite(f[b]) || !std::isfinite(f[c])) return never;
                return static_cast<float>(mix(f));
            };
            const double dx = mix(src.dir_x), dy = mix(src.dir_y), dl = std::hypot(dx, dy);
            if (dl > 0.0) p.dir_x[v] = dx / dl, p.dir_y[v] = dy / dl;
            for (auto [to, from] : {std::pair{&p.width, &src.width}, {&p.scale, &src.scale}, {&p.mean_level, &src.mean_level},
                                    {&p.rise, &src.rise}, {&p.breaking_length, &src.breaking_length},
                                    {&p.curl, &src.curl}, {&p.foam_yield, &src.foam_yield}})
                (*to)[v] = static_cast<float>(mix(*from));
            p.break_phase[v] = mixf(src.break_phase);
            p.end_phase[v] = mixf(src.end_phase);
        }
    });
    return p;
}

namespace {

// Vertex v's point of its crest's section at label s: the outer section while the crest
// breaks or collapses (when the plan has them), else the paper's curve, its horizontal
// move faded with k7 as the wave dies (§4's scaling; k7 = 1 − t while collapsing: a
// dead crest leaves every point at rest).
BreakerSectionPoint section_point(const JeschkeMotionPlan& p, std::size_t v, const BreakerLife& life, double s) noexcept {
    const bool broken = life.phase == BreakerPhase::breaking || life.phase == BreakerPhase::collapsing;
    if (broken && !p.sections.empty()) {
        const double tau = life.phase == BreakerPhase::breaking ? life.t : 1.0 + life.t, ratio = p.scale[v] / p.width[v];
        const BreakerSectionPoint outer = breaker_section(p.sections, tau, p.curl[v], ratio, s);
        const double w = p.resolve.empty() || p.curl_sections.empty() ? 0.0 : static_cast<double>(p.resolve[v]);
        if (!(w > 0.0)) return outer;
        const BreakerSectionPoint curl = breaker_section(p.curl_sections, tau, p.curl[v], ratio, s);
        return {outer.x + w * (curl.x - outer.x), outer.z + w * (curl.z - outer.z)};
    }
    // Away from the lip seam only the half holding s is needed (k7, the scale, is the
    // same in both halves of every phase; the seam is never wider than lip_seam_max,
    // and the round phase's halves meet).
    BreakerShapePoint q;
    double k7 = 0.0;
    if (std::abs(s - 0.5) < lip_seam_max && life.phase != BreakerPhase::round) {
        const BreakerConstants back = jeschke_constants(life.phase, life.t, false);
        q = jeschke_shape(s, back, jeschke_constants(life.phase, life.t, true), p.curl[v]);
        k7 = back.k[7];
    } else {
        const bool is_front = s >= 0.5;
        const BreakerConstants half = jeschke_constants(life.phase, life.t, is_front);
        q = is_front ? front_half(std::min(s, 1.0), half, p.curl[v]) : back_half(std::max(s, 0.0), half, p.curl[v]);
        k7 = half.k[7];
    }
    const double fade = std::min(1.0, 1.25 * k7);
    return {s + (1.0 - q.y - s) * fade, q.z};
}

}  // namespace

void evaluate_jeschke_breakers(const JeschkeMotionPlan& p, double t, std::span<float> positions) {
    const std::size_t n = p.vertex_count();
    if (positions.size() != 3 * n)
        throw InputError("jeschke breakers: positions hold " + std::to_string(positions.size()) + " floats, expected " +
                         std::to_string(3 * n));
    check_lags(p, "jeschke breakers");
    const double wt = p.omega * t;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            if (p.width[v] == 0.0f) {  // dry, or off the traced water: at rest
                positions[3 * v] = static_cast<float>(p.x[v]);
                positions[3 * v + 1] = static_cast<float>(p.y[v]);
                positions[3 * v + 2] = -p.mean_level[v];
                continue;
            }
            // δ ∈ [−π, π): how far the nearest crest ψ = ωt − 2πn has run past this vertex
            // (past its phase, lag later: the life at phase + δ).
            const double ahead = wt - p.phase[v] - lag_of(p, v);
            const long long crest = crest_index(ahead);
            const double delta = ahead - two_pi * static_cast<double>(crest);
            const double psi = p.phase[v] + delta, s = 0.5 - delta / two_pi;
            const CrestPhases c = crest_phases(p, v, crest, psi);
            const BreakerLife life = jeschke_life(psi, p.rise[v], c.break_phase, c.breaking_length, c.end_phase, start_of(p, v));
            const BreakerSectionPoint q = section_point(p, v, life, s);
            const double forward = (q.x - s) * p.width[v];
            positions[3 * v] = static_cast<float>(p.x[v] + forward * p.dir_x[v]);
            positions[3 * v + 1] = static_cast<float>(p.y[v] + forward * p.dir_y[v]);
            positions[3 * v + 2] = static_cast<float>(p.scale[v] * q.z - p.mean_level[v]);
        }
    });
}

void jeschke_foam(const JeschkeMotionPlan& p, double t, std::span<float> foam) {
    const std::size_t n = p.vertex_count();
    if (foam.size() != n)
        throw InputError("jeschke foam: " + std::to_string(foam.size()) + " values for " + std::to_string(n) + " vertices");
    check_lags(p, "jeschke foam");
    const double wt = p.omega * t;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const double ahead = wt - p.phase[v] - lag_of(p, v);  // crests at the vertex: its phase's, lag later
            const double since = ahead - two_pi * std::floor(ahead / two_pi);
            const double tau = since / p.omega;
            if (p.loop_periods() == 1) {
                // Every crest passes here alike (a periodic swell): the latest one, τ ago,
                // holds the largest of the faded values (§3.1's maximum over the waves).
                const double left = std::max({0.0, 1.0 - tau / p.foam_fade_time, lip_foam_rise(two_pi - since)});
                foam[v] = p.foam_yield[v] <= 0.0f ? 0.0f : static_cast<float>(p.foam_yield[v] * left);
                continue;
            }
            // Varied crests: each recent one broke here or not; the largest faded value.
            // No crest breaks more than variation · 2π before the traced break point.
            if (!std::isfinite(p.break_phase[v]) || p.width[v] == 0.0f ||
                p.phase[v] < static_cast<double>(p.break_phase[v]) - p.variation * two_pi) {
                foam[v] = 0.0f;
                continue;
            }
            const long long latest = static_cast<long long>(std::floor(ahead / two_pi));
            const double period = two_pi / p.omega;
            // The crests repeat after loop_periods(): an older copy of a crest has faded
            // more than the newer one, so the newest loop_periods() crests hold the
            // maximum (a fade time of 10⁶ s otherwise looked at 200 000 crests per vertex).
            const auto crests = static_cast<long long>(p.loop_periods());
            double best = 0.0;
            for (long long j = 0; j < crests && tau + static_cast<double>(j) * period < p.foam_fade_time; ++j) {
                const CrestPhases c = crest_phases(p, v, latest - j, p.phase[v]);
                const BreakerLife life = jeschke_life(p.phase[v], p.rise[v], c.break_phase, c.breaking_length, c.end_phase, start_of(p, v));
                best = std::max(best, foam_yield(life, p.foam_onset) * (1.0 - (tau + static_cast<double>(j) * period) / p.foam_fade_time));
            }
            // The next crest's lip, if it breaks here.
            if (const double rise = lip_foam_rise(two_pi - since); rise > 0.0) {
                const CrestPhases c = crest_phases(p, v, latest + 1, p.phase[v]);
                const BreakerLife life = jeschke_life(p.phase[v], p.rise[v], c.break_phase, c.breaking_length, c.end_phase, start_of(p, v));
                best = std::max(best, foam_yield(life, p.foam_onset) * rise);
            }
            foam[v] = static_cast<float>(best);
        }
    });
}

}  // namespace wave

namespace wave {

CrestPhases jeschke_crest_phases(const JeschkeMotionPlan& p, std::size_t v, long long n) noexcept {
    return crest_phases(p, v, n, p.phase[v]);
}

BreakerLife jeschke_vertex_life(const JeschkeMotionPlan& p, std::size_t v, long long n) noexcept {
    const CrestPhases c = crest_phases(p, v, n, p.phase[v]);
    return jeschke_life(p.phase[v], p.rise[v], c.break_phase, c.breaking_length, c.end_phase, start_of(p, v));
}

namespace {

// Vertex v's label s on the crest nearest it at time t and that crest's life there.
struct CrestAt {
    double s = 0.0;
    BreakerLife life;
};
CrestAt crest_at(const JeschkeMotionPlan& p, std::size_t v, double wt) noexcept {
    const double ahead = wt - p.phase[v] - lag_of(p, v);
    const long long crest = crest_index(ahead);
    const double delta = ahead - two_pi * static_cast<double>(crest);
    const double psi = p.phase[v] + delta;
    const CrestPhases c = crest_phases(p, v, crest, psi);
    return {0.5 - delta / two_pi, jeschke_life(psi, p.rise[v], c.break_phase, c.breaking_length, c.end_phase, start_of(p, v))};
}

bool broken(const BreakerLife& life) noexcept {
    return life.phase == BreakerPhase::breaking || life.phase == BreakerPhase::collapsing;
}

}  // namespace

bool jeschke_draws_overturned(const JeschkeMotionPlan& p, double t, std::uint32_t a, std::uint32_t b, std::uint32_t c) noexcept {
    const std::size_t n = p.vertex_count();
    if (a >= n || b >= n || c >= n || p.sections.labels == 0) return false;
    const double wt = p.omega * t;
    const CrestAt at[3] = {crest_at(p, a, wt), crest_at(p, b, wt), crest_at(p, c, wt)};
    const double first = std::min({at[0].s, at[1].s, at[2].s}), last = std::max({at[0].s, at[1].s, at[2].s});
    if (!(last - first < 0.25)) return false;  // not one crest's labels
    // Each vertex's own section over the triangle's labels widened by one label step
    // of the tables either side (their multilinear blend of lives, curls and ratios
    // moves a lip by up to a step), at a quarter step: running backwards anywhere is
    // an overturn the model draws.
    const double table_step = 1.0 / static_cast<double>(p.sections.labels), step = 0.25 * table_step;
    const double lo = first - table_step, hi = last + table_step;
    const auto samples = static_cast<int>(std::ceil((hi - lo) / step)) + 1;
    const std::uint32_t vs[3] = {a, b, c};
    for (int i = 0; i < 3; ++i) {
        if (p.width[vs[i]] == 0.0f || !broken(at[i].life)) continue;
        double previous = section_point(p, vs[i], at[i].life, lo).x;
        for (int k = 1; k <= samples; ++k) {
            const double x = section_point(p, vs[i], at[i].life, std::min(hi, lo + step * k)).x;
            if (x < previous) return true;
            previous = x;
        }
    }
    return false;
}

void jeschke_drawn_lips(const JeschkeMotionPlan& p, double t, std::span<float> weight) {
    const std::size_t n = p.vertex_count();
    if (weight.size() != n)
        throw InputError("jeschke lips: " + std::to_string(weight.size()) + " values for " + std::to_string(n) + " vertices");
    check_lags(p, "jeschke lips");
    const double wt = p.omega * t;
    // The section's slope at a vertex, from its points half a label step either side
    // (a label step of the tables: the finest the section is known at).
    const double h = p.sections.labels > 0 ? 0.5 / static_cast<double>(p.sections.labels) : 1.0 / 128.0;
    const double drawn_slope = std::tan(kDrawnSlope);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            weight[v] = 0.0f;
            const float resolved = p.wall_resolve.empty() ? 0.0f : p.wall_resolve[v];
            if (!(resolved > 0.0f) || p.width[v] == 0.0f || p.sections.labels == 0) continue;
            const CrestAt at = crest_at(p, v, wt);
            if (!broken(at.life)) continue;
            const BreakerSectionPoint a = section_point(p, v, at.life, at.s - h), b = section_point(p, v, at.life, at.s + h);
            const double run = (b.x - a.x) * p.width[v], rise = std::abs(b.z - a.z) * p.scale[v];
            // Running backwards (the lip's underside) is drawn overturned.
            const double drawn = run <= 0.0 ? 1.0 : detail::smoothstep(0.0, drawn_slope, rise / run);
            weight[v] = static_cast<float>(drawn * resolved);

        }
    });
}

double jeschke_foam_yield(const BreakerLife& life, double onset) noexcept { return foam_yield(life, onset); }

}  // namespace wave
