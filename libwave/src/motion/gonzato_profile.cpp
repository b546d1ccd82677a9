// Gonzato & Le Saëc's wave profile (§2.3–2.5, eq. 7) with the misprints read as in docs/conventions.md
// corrected: τ'_β = √(1 − τ_β²), and Orientation / Displacement as piecewise-linear
// functions of the phase over the descending front, the trough and the ascending back.
#include "libwave/motion.h"

#include "libwave/errors.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wave {
namespace {

constexpr double pi = std::numbers::pi;
constexpr int kSpeedSamples = 64;  // points over one period where the profile's speed is checked

// The phases u = φ − Φ_min where the profile's slope jumps: the displacement's ends on
// the front face and the rear face (see gonzato_offset), and the crest.
constexpr double kFrontEnd = -pi / 3.0, kBackStart = 7.0 * pi / 8.0;

// A bound on |dO/dΦ| over the whole profile: |E'| ≤ the major semi-axis, the stretch's
// ≤ 2 St/π, the displacement's ≤ D w' √(1 + (w dθ/dw)²) with w' ≤ 8/π (the rear face)
// and the orientation θ turning by π/4 + β.
double offset_slope_bound(const ProfileShape& s) noexcept {
    const double turn = pi / 4.0 + s.bottom_angle;
    return s.major + 2.0 * s.stretch / pi + s.displacement * (8.0 / pi) * std::sqrt(1.0 + turn * turn);
}

// The chords of phase over which both shares below are checked (u = φ − Φ_min).
constexpr double kChord = 1e-6;

// The smallest of bound(u0, u1) ∈ [0, 1] over chords of kChord: each side of 64 phases
// spread over the period, each side of the kinks, and each side of the crest (u = ±π),
// clamped to [0, 1]. Between the samples the slopes of the smooth pieces (sines and a
// parabola) change by little.
template <class Chord>
double least_over_chords(const Chord& bound) {
    double share = 1.0;
    const auto both_sides = [&](double u) { share = std::min({share, bound(u - kChord, u), bound(u, u + kChord)}); };
    for (int i = 0; i < kSpeedSamples; ++i) both_sides(-pi + 2.0 * pi * (i + 0.5) / kSpeedSamples);
    for (double u : {kFrontEnd, kBackStart}) both_sides(u);
    share = std::min({share, bound(-pi, -pi + kChord), bound(pi - kChord, pi - 1e-12)});  // the crest, each side
    return std::clamp(share, 0.0, 1.0);
}

// The largest share σ ∈ [0, 1] of the stretch and the displacement with which no point
// of profile s moves faster than `ratio` × the phase speed.
double speed_share(const ProfileShape& s, double k, double ratio) noexcept {
    // The offset is O(u) = E(u) + σ X(u): the ellipse E, and the stretch and the
    // displacement X, both proportional to their size. A point runs through the phase
    // at ω, so it moves at ω |O'(u)| against the phase speed ω/k: the bound is
    // k |E'(u) + σ X'(u)| ≤ ratio. O' (each side of a point, for the kinks) at the
    // samples and the kinks gives the largest σ with |a + σ b| ≤ r, a = E'Δ, b = X'Δ
    // over a small Δ (kChord), r = ratio Δ / k, at least_over_chords' chords.
    if (!(s.stretch > 0.0 || s.displacement > 0.0) || !(k > 0.0)) return 1.0;
    // Most points are slow enough by a bound on the slopes.
    if (k * offset_slope_bound(s) <= ratio) return 1.0;
    ProfileShape ellipse = s, rest = s;
    ellipse.stretch = ellipse.displacement = 0.0;
    rest.major = rest.minor = 0.0;
    const double r = ratio * kChord / k;
    const auto bound = [&](double u0, double u1) {  // the chord from u0 to u1 = u0 + Δ
        const ProfileOffset e0 = gonzato_offset(ellipse, s.trough_phase + u0), e1 = gonzato_offset(ellipse, s.trough_phase + u1);
        const ProfileOffset x0 = gonzato_offset(rest, s.trough_phase + u0), x1 = gonzato_offset(rest, s.trough_phase + u1);
        const double ax = e1.forward - e0.forward, az = e1.up - e0.up, bx = x1.forward - x0.forward, bz = x1.up - x0.up;
        const double aa = ax * ax + az * az, ab = ax * bx + az * bz, bb = bx * bx + bz * bz;
        if (aa >= r * r) return 0.0;  // the orbit alone is faster (no disc limit)
        if (!(bb > 0.0)) return 1.0;
        // |a + σ b|² = r² at σ = (−ab + √(ab² − bb (aa − r²))) / bb, the positive root.
        return (-ab + std::sqrt(ab * ab - bb * (aa - r * r))) / bb;
    };
    return least_over_chords(bound);
}

// The largest share β ∈ [0, 1] of the offset along the ray with which the section
// packs its rest spacing no tighter than `pack` (GonzatoProfileOptions::min_packing).
// Per unit of rest length the section's tangent is (1 + β a, b), a = k dforward/du and
// b = k dup/du over a small step of phase. Where a < 0 and |b| < pack, |1 + β a| ≥
// √(pack² − b²) on the branch that does not fold gives β ≤ (1 − √(pack² − b²))/(−a).
// Checked at least_over_chords' chords, as the speed bound is, and taken 2 % inside,
// which keeps the bound between them.
double packing_share(const ProfileShape& s, double k, double pack) noexcept {
    if (!(pack > 0.0) || !(k > 0.0)) return 1.0;
    if (k * offset_slope_bound(s) <= 1.0 - pack) return 1.0;  // dx/dx₀ ≥ 1 − k|dO/dΦ| ≥ pack everywhere
    const auto bound = [&](double u0, double u1) {
        const ProfileOffset o0 = gonzato_offset(s, s.trough_phase + u0), o1 = gonzato_offset(s, s.trough_phase + u1);
        const double a = k * (o1.forward - o0.forward) / (u1 - u0), b = k * (o1.up - o0.up) / (u1 - u0);
        if (a >= 0.0 || b * b >= pack * pack) return 1.0;
        return 0.98 * (1.0 - std::sqrt(pack * pack - b * b)) / -a;
    };
    return least_over_chords(bound);
}

}  // namespace

ProfileShape gonzato_shape(double R, double k, double h, double rise, const GonzatoProfileOptions& o) {
    ProfileShape s;
    if (!(h > 0.0) || !(R > 0.0) || !(k > 0.0)) return s;  // dry or still: the point stays put
    // §2.4: a bottom that deepens along the ray would break the wave backwards.
    s.bottom_angle = std::atan(std::max(rise, 0.0));
    s.tilt_sin = std::sin(s.bottom_angle) * std::exp(-o.k0 * h);  // τ_β
    s.tilt_cos = std::sqrt(1.0 - s.tilt_sin * s.tilt_sin);         // τ'_β (printed √(1 − τ_β))
    const double sx = 1.0 / -std::expm1(-o.kx * h);                // S_x: 1 in deep water, → ∞ at the shore
    const double sz = sx * -std::expm1(-o.kz * h);                 // S_z: → K_z / K_x at the shore
    s.major = R * sx;
    // S_z flattens the orbit towards the shore (K_z < K_x: S_z from 1 down to K_z/K_x);
    // it never raises it: R is the ray's amplitude, shoaling already in it. With K_x
    // far below K_z (a schema-valid K_x of 1e-3 /m), S_z reached 60 at 10 m and a 0.3 m
    // swell stood ±5.55 m high, at Gerstner's disc below (docs/hardening.md).
    s.minor = R * std::min(sz, 1.0);
    // §2.3: the major axis stays in Gerstner's disc (no loops; waves reach the beach);
    // the minor axis R S_z < R S_x is left as it is.
    if (o.limit_to_disc) s.major = std::min(s.major, 1.0 / k);
    s.minor = std::min(s.minor, s.major);
    // Eq. 5, with the sign that makes eq. 7 lowest there: dz/dφ = a τ cos φ + b τ' sin φ = 0.
    s.trough_phase = -std::atan2(s.major * s.tilt_sin, s.minor * s.tilt_cos);
    const double height = 2.0 * R;  // the paper's A = 2R
    s.stretch = o.stretch_max * height * std::exp(-o.stretch_depth_factor * h);
    s.displacement = height * std::exp(-o.displacement_depth_factor * h);
    if (o.max_speed_ratio > 0.0) {
        const double share = speed_share(s, k, o.max_speed_ratio);
        s.stretch *= share;
        s.displacement *= share;
    }
    // Last, on the whole section (the orbit too: at Gerstner's limit 1/k its crest is a cusp).
    s.forward_scale = packing_share(s, k, o.min_packing);
    return s;
}

ProfileOffset gonzato_offset(const ProfileShape& s, double phi) noexcept {
    // u = φ − Φ_min in [−π, π): the trough at 0, the crest at ±π.
    double u = std::fmod(phi - s.trough_phase + pi, 2.0 * pi);
    if (u < 0.0) u += 2.0 * pi;
    u -= pi;
    phi = s.trough_phase + u;
    const double sin_phi = std::sin(phi), cos_phi = std::cos(phi);
    // Fournier–Reeves tilted ellipse.
    double forward = s.major * s.tilt_cos * sin_phi + s.minor * s.tilt_sin * cos_phi;
    double up = -s.minor * s.tilt_cos * cos_phi + s.major * s.tilt_sin * sin_phi;
    // Stretch (eq. 6): (St_max / π²)(φ − Φ_min)², along the major axis.
    const double stretch = s.stretch * (u / pi) * (u / pi);
    forward += stretch * s.tilt_cos;
    up += stretch * s.tilt_sin;
    // Orientation and Displacement: from the crest (−π/4, A) down the front face to
    // (β, 0) at Φ_min − π/3; (β, 0) over the trough; back up the short rear face from
    // Φ_min + 7π/8 to the crest.
    if (s.displacement > 0.0) {
        double w = 0.0;  // share of the displacement, 1 at the crest
        if (u < kFrontEnd) w = (kFrontEnd - u) / (kFrontEnd + pi);
        else if (u >= kBackStart) w = (u - kBackStart) / (pi - kBackStart);
        if (w > 0.0) {
            const double orientation = s.bottom_angle + (-pi / 4.0 - s.bottom_angle) * w;
            forward += w * s.displacement * std::cos(orientation);
            up += w * s.displacement * std::sin(orientation);
        }
    }
    return {forward * s.forward_scale, up};
}

GonzatoMotionPlan plan_gonzato_motion(const RayStrips& strips, const GonzatoProfileOptions& o) {
    const auto check = [](double v, const char* name) {
        if (!(v >= 0.0) || !std::isfinite(v))
            throw InputError(std::string("gonzato profile: ") + name + " must be a finite number >= 0");
    };
    check(o.k0, "k0");
    check(o.kx, "kx");
    check(o.kz, "kz");
    check(o.stretch_max, "stretch_max");
    check(o.stretch_depth_factor, "stretch_depth_factor");
    check(o.displacement_depth_factor, "displacement_depth_factor");
    check(o.max_speed_ratio, "max_speed_ratio");
    check(o.min_packing, "min_packing");
    if (!(o.min_packing < 1.0)) throw InputError("gonzato profile: min_packing must be < 1");
    if (!(o.kx > 0.0) || !(o.kz > 0.0)) throw InputError("gonzato profile: kx and kz must be > 0 (1/m)");
    GonzatoMotionPlan p;
    const std::size_t n = strips.vertex_count();
    p.omega = strips.omega;
    p.x = strips.x;
    p.y = strips.y;
    p.dir_x = strips.dir_x;
    p.dir_y = strips.dir_y;
    p.phase = strips.phase;
    p.shape.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v)
            p.shape[v] = gonzato_shape(strips.amplitude[v], strips.k[v], strips.depth[v], strips.rise[v], o);
    });
    return p;
}

void evaluate_gonzato_motion(const GonzatoMotionPlan& p, double t, std::span<float> positions) {
    const std::size_t n = p.vertex_count();
    if (positions.size() != 3 * n)
        throw InputError("gonzato motion: positions hold " + std::to_string(positions.size()) + " floats, expected " +
                         std::to_string(3 * n));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const ProfileOffset d = gonzato_offset(p.shape[v], p.phase[v] - p.omega * t);  // Φ = −ωt + Σ k Δs
            positions[3 * v] = static_cast<float>(p.x[v] + d.forward * p.dir_x[v]);
            positions[3 * v + 1] = static_cast<float>(p.y[v] + d.forward * p.dir_y[v]);
            positions[3 * v + 2] = static_cast<float>(d.up);
        }
    });
}

}  // namespace wave
