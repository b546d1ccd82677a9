// The breaker's outer section at the mesh's scale (BreakerLip::outer): the upper
// envelope of Jeschke's curve, relabelled so that a section moving at c keeps every
// rest spacing of the mesh at least min_packing long and no point faster than
// frozen_speed × c. docs/motion.md, "The outer section".
#include "libwave/errors.h"
#include "libwave/motion.h"

#include "core/smoothstep.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace wave {
namespace {

constexpr std::size_t kCurveSamples = 1024;  // points of the paper's curve per section
constexpr std::size_t kColumns = 512;        // columns of the envelope over [0, 1]
constexpr std::size_t kLives = 129;          // life samples over [0, 2] (1/64 apart)
constexpr std::size_t kRatios = 13;          // 5H/W from 2⁻⁵ to 2¹, √2 apart
constexpr std::size_t kLabels = 64;          // label intervals per tabulated section

// The paper's constants and horizontal fade at life τ (0 … 1 breaking, 1 … 2 collapsing).
struct LifeShape {
    BreakerConstants back, front;
    double fade = 1.0;
};

LifeShape life_shape(double life) noexcept {
    const bool breaking = life < 1.0;
    const BreakerPhase phase = breaking ? BreakerPhase::breaking : BreakerPhase::collapsing;
    const double t = std::clamp(breaking ? life : life - 1.0, 0.0, 1.0);
    LifeShape s{jeschke_constants(phase, t, false), jeschke_constants(phase, t, true), 1.0};
    s.fade = std::min(1.0, 1.25 * s.back.k[7]);  // as evaluate_jeschke_breakers fades it
    return s;
}

// The upper envelope of the paper's section (x = s + fade (1 − y − s), z) on kColumns + 1
// columns over [0, 1]. The edge columns keep the section's own edges (z = 0), so that a
// vertex passing from one crest to the next does not jump: a jet thrown past the front
// edge ends in a drop there.
std::vector<double> envelope(double life, double curl) {
    const LifeShape ls = life_shape(life);
    std::vector<double> x(kCurveSamples + 1), z(kCurveSamples + 1);
    for (std::size_t i = 0; i <= kCurveSamples; ++i) {
        const double s = static_cast<double>(i) / kCurveSamples;
        const BreakerShapePoint q = jeschke_shape(s, ls.back, ls.front, curl);
        x[i] = s + ls.fade * (1.0 - q.y - s);
        z[i] = q.z;
    }
    constexpr double none = -std::numeric_limits<double>::infinity();
    std::vector<double> top(kColumns + 1, none);
    const double G = static_cast<double>(kColumns);
    for (std::size_t i = 0; i < kCurveSamples; ++i) {
        const double lo = std::min(x[i], x[i + 1]), hi = std::max(x[i], x[i + 1]);
        const auto first = static_cast<long>(std::ceil(std::max(lo, 0.0) * G));
        const auto last = static_cast<long>(std::floor(std::min(hi, 1.0) * G));
        for (long j = first; j <= last; ++j) {
            const double cx = static_cast<double>(j) / G;
            const double w = hi > lo ? (cx - x[i]) / (x[i + 1] - x[i]) : 0.0;
            const double cz = hi > lo ? z[i] + w * (z[i + 1] - z[i]) : std::max(z[i], z[i + 1]);
            top[static_cast<std::size_t>(j)] = std::max(top[static_cast<std::size_t>(j)], cz);
        }
    }
    top.front() = z.front();
    top.back() = z.back();
    // The curve runs continuously from x = 0 to x = 1, so it covers every column; a
    // column between two sample points that both jump over it takes its neighbour's.
    for (std::size_t j = 1; j < kColumns; ++j)
        if (top[j] == none) top[j] = top[j - 1];
    return top;
}

// Labels along the envelope for a height ratio 5H/W: per column segment of slope angle
// θ, surface length per unit label μ = max(p, min(1/cos θ, cos θ + √(v² − sin² θ))) —
// the rest spacing itself (the envelope as a height field: points move only up and
// down) until that moves a point faster than v (a point of a section moving at c moves
// at c √(1 − 2μ cos θ + μ²)), then the μ at which it moves at v; never below the
// packing p. All μ × κ, κ = Σ length/μ, so that the labels span [0, 1].
void relabel(const std::vector<double>& top, double ratio, const BreakerSectionBounds& b, std::size_t labels,
             std::vector<BreakerSectionPoint>& out) {
    const double dx = 1.0 / static_cast<double>(kColumns), v2 = b.frozen_speed * b.frozen_speed;
    std::vector<double> label(kColumns + 1, 0.0);
    for (std::size_t j = 0; j < kColumns; ++j) {
        const double dz = ratio * (top[j + 1] - top[j]), length = std::hypot(dx, dz);
        const double c = dx / length, sin2 = 1.0 - c * c;
        const double mu = std::max(b.min_packing, std::min(1.0 / c, c + std::sqrt(v2 - sin2)));
        label[j + 1] = label[j] + length / mu;
    }
    const double kappa = label.back();
    out.resize(labels + 1);
    std::size_t j = 0;
    for (std::size_t m = 0; m <= labels; ++m) {
        const double s = kappa * static_cast<double>(m) / static_cast<double>(labels);
        while (j + 1 < kColumns && label[j + 1] < s) ++j;
        const double w = std::clamp((s - label[j]) / (label[j + 1] - label[j]), 0.0, 1.0);
        out[m] = {(static_cast<double>(j) + w) * dx, top[j] + w * (top[j + 1] - top[j])};
    }
    out.front() = {0.0, top.front()};
    out.back() = {1.0, top.back()};
}

// The breaker's front at its own scale (BreakerLip::curl). The paper draws the shape in a
// unit square scaled by W across and 5H up, so at a real breaker's 5H/W ≈ 0.1–0.5 its
// front — from the crest over the lip to where the lip lands — is a quarter of a
// wavelength long and a fraction of a wavelength high: a long gentle slope with a
// knife-thin lip, where a real plunging breaker has a face about as high as it is wide
// (a tube about H across). The back stays at the wavelength's scale; ahead of the crest
// the envelope is pressed towards it by σ = 1 − e (1 − min(1, 5H/W)), so that the front
// has the proportions of the paper's figure (drawn with equal axes: 5H/W = 1), and the
// water it leaves ahead is still (the envelope's front edge, z = 0). The pressing sets in
// smoothly over the columns x ∈ [0.42, 0.52] (about the crest, which stands near 0.45–0.5
// through the life; no kink at the pivot) and over the first half of the breaking phase, e = smoothstep(0,
// ½, τ): τ = 0 is the round crest as before, so nothing jumps where breaking starts; it
// stays pressed while the wave collapses (the shape itself sinks to still water).
double front_pressing(double life) noexcept { return detail::smoothstep(0.0, 0.5, life); }

std::vector<double> press_front(const std::vector<double>& top, double ratio, double life) {
    const double sigma = 1.0 - front_pressing(life) * (1.0 - std::min(1.0, ratio));
    if (!(sigma < 1.0)) return top;
    const double dx = 1.0 / static_cast<double>(kColumns);
    // pressed_x(x) = ∫ 1 − (1 − σ) smoothstep(0.42, 0.52, x) dx on the columns, then the envelope
    // resampled at the columns: z(X) = top(x(X)); past pressed_x(1), the front edge's z.
    std::vector<double> pressed_x(kColumns + 1, 0.0);
    for (std::size_t j = 0; j < kColumns; ++j) {
        const double xm = (static_cast<double>(j) + 0.5) * dx;
        pressed_x[j + 1] = pressed_x[j] + dx * (1.0 - (1.0 - sigma) * detail::smoothstep(0.42, 0.52, xm));
    }
    std::vector<double> out(kColumns + 1, top.back());
    std::size_t i = 0;
    for (std::size_t j = 0; j <= kColumns; ++j) {
        const double xj = static_cast<double>(j) * dx;
        if (xj > pressed_x.back()) break;
        while (i + 1 < kColumns && pressed_x[i + 1] < xj) ++i;
        const double span = pressed_x[i + 1] - pressed_x[i], w = span > 0.0 ? std::clamp((xj - pressed_x[i]) / span, 0.0, 1.0) : 0.0;
        out[j] = top[i] + w * (top[i + 1] - top[i]);
    }
    out.front() = top.front();
    out.back() = top.back();
    return out;
}

// The overturning section (BreakerLip::curl): the envelope's wall — the steepest drop,
// where the lip hangs over the water ahead, from the crest's shoulder (the slope above
// 45°) to its foot — curled into a tube's mouth. From the lip's top the wall's points
// keep their place down a quarter of its height, then move back under the lip by up to
// D and return to the wall at its foot (sin² in the wall's height, so the mouth leaves
// and meets the envelope without a kink): a lip that faces down. D = ½ plunge × the
// wall's height (at the real ratio), plunge 0 … 1 from the curl (the paper's tube 1;
// collapsing and spilling crests 0), times the mouth's opening as the wall stands from
// 55° to 75°: below 55°, and wherever D is 0, the section is the envelope itself (the
// mouth is the wall's own points moved back, with samples between them), so nothing
// jumps in time as a wall stands up or sinks back. Returned as a polyline (x in
// wavelengths, z in units of 5H).
constexpr std::size_t kMouthSamples = 48;

double plunge_of(double curl) noexcept { return std::clamp((curl - 0.6) / 0.4, 0.0, 1.0); }

void curl_polyline(const std::vector<double>& top, double ratio, double plunge, std::vector<double>& px, std::vector<double>& pz) {
    const double dx = 1.0 / static_cast<double>(kColumns);
    const auto angle = [&](std::size_t j) { return std::atan2(-ratio * (top[j + 1] - top[j]), dx); };  // > 0 falling
    std::size_t steepest = 0;
    for (std::size_t j = 1; j < kColumns; ++j)
        if (angle(j) > angle(steepest)) steepest = j;
    px.clear();
    pz.clear();
    const double deg = std::numbers::pi / 180.0, side = 45.0 * deg;
    plunge *= detail::smoothstep(55.0 * deg, 75.0 * deg, angle(steepest));
    if (!(plunge > 0.0) || steepest == 0 || steepest + 1 == kColumns) {
        for (std::size_t j = 0; j <= kColumns; ++j) px.push_back(static_cast<double>(j) * dx), pz.push_back(top[j]);
        return;
    }
    std::size_t a = steepest, b = steepest + 1;  // the wall: columns a (its top) … b (its foot), falling all the way
    while (a > 1 && angle(a - 1) > side) --a;
    while (b + 1 < kColumns && angle(b) > side) ++b;
    for (std::size_t j = 0; j < a; ++j) px.push_back(static_cast<double>(j) * dx), pz.push_back(top[j]);
    const double za = top[a], zb = top[b], depth = 0.5 * plunge * ratio * (za - zb);
    constexpr double lip = 0.25;  // the lip's thickness: a quarter of the wall
    const auto curl_back = [&](double u) {
        const double w = std::clamp((u - lip) / (1.0 - lip), 0.0, 1.0), g = std::sin(std::numbers::pi * w);
        return depth * g * g;
    };
    // Down the wall by u = (za − z)/(za − zb): its columns and kMouthSamples steps in u,
    // each on the envelope (x where the falling wall has height z) moved back.
    std::size_t j = a, i = 0;
    while (j <= b) {
        const double uj = (za - top[j]) / (za - zb), ui = static_cast<double>(i) / static_cast<double>(kMouthSamples);
        if (i <= kMouthSamples && ui < uj - 1e-12) {
            const double z = za + (zb - za) * ui;
            std::size_t k = j - 1;  // top[k] > z > top[j]: j > a here (u at a is 0, the first step's)
            const double x = (static_cast<double>(k) + (top[k] - z) / (top[k] - top[j])) * dx;
            px.push_back(x - curl_back(ui)), pz.push_back(z);
            ++i;
            continue;
        }
        if (i <= kMouthSamples && std::abs(ui - uj) <= 1e-12) ++i;  // a step on a column: the column's point
        px.push_back(static_cast<double>(j) * dx - curl_back(uj)), pz.push_back(top[j]);
        ++j;
    }
    for (std::size_t c = b + 1; c <= kColumns; ++c) px.push_back(static_cast<double>(c) * dx), pz.push_back(top[c]);
}

// relabel over a polyline whose segments may run backwards (cos θ < 0: the lip's
// underside), where a point of a section moving at c moves at c √(1 − 2μ cos θ + μ²):
// μ = max(p, min(1/cos θ (cos θ > 0), cos θ + √(v² − sin² θ))) — on the underside
// the packing p, so the lip's jet runs at most (1 + p) c frozen.
void relabel_polyline(const std::vector<double>& px, const std::vector<double>& pz, double ratio, const BreakerSectionBounds& b,
                      std::size_t labels, std::vector<BreakerSectionPoint>& out) {
    const double v2 = b.frozen_speed * b.frozen_speed;
    const std::size_t m = px.size() - 1;
    std::vector<double> label(m + 1, 0.0);
    for (std::size_t j = 0; j < m; ++j) {
        const double ddx = px[j + 1] - px[j], dz = ratio * (pz[j + 1] - pz[j]), length = std::hypot(ddx, dz);
        if (!(length > 0.0)) {
            label[j + 1] = label[j];
            continue;
        }
        const double c = ddx / length, sin2 = 1.0 - c * c;
        const double rest = c > 0.0 ? 1.0 / c : std::numeric_limits<double>::infinity();
        const double mu = std::max(b.min_packing, std::min(rest, c + std::sqrt(v2 - sin2)));
        label[j + 1] = label[j] + length / mu;
    }
    const double kappa = label.back();
    out.resize(labels + 1);
    std::size_t j = 0;
    for (std::size_t q = 0; q <= labels; ++q) {
        const double s = kappa * static_cast<double>(q) / static_cast<double>(labels);
        while (j + 1 < m && label[j + 1] < s) ++j;
        const double span = label[j + 1] - label[j];
        const double w = span > 0.0 ? std::clamp((s - label[j]) / span, 0.0, 1.0) : 0.0;
        out[q] = {px[j] + w * (px[j + 1] - px[j]), pz[j] + w * (pz[j + 1] - pz[j])};
    }
    out.front() = {0.0, pz.front()};
    out.back() = {1.0, pz.back()};
}

void check_bounds(const BreakerSectionBounds& b) {
    if (!(b.min_packing >= 0.0 && b.min_packing < 1.0))
        throw InputError("breakers: min_packing must be in [0, 1), got " + std::to_string(b.min_packing));
    if (!(b.frozen_speed > 1.0 && b.frozen_speed <= 2.0))
        throw InputError("breakers: frozen_speed must be in (1, 2], got " + std::to_string(b.frozen_speed));
}

double ratio_at(const BreakerSections& t, std::size_t r) noexcept {
    return std::exp2(t.log2_ratio_first + t.log2_ratio_step * static_cast<double>(r));
}

// Index and weight of v on a grid of n samples first, first + step, … (clamped).
std::pair<std::size_t, double> cell(double v, double first, double step, std::size_t n) noexcept {
    if (n < 2) return {0, 0.0};
    const double f = std::clamp((v - first) / step, 0.0, static_cast<double>(n - 1));
    const std::size_t i = std::min(static_cast<std::size_t>(f), n - 2);
    return {i, f - static_cast<double>(i)};
}

}  // namespace

void outer_section(double life, double curl, double ratio, const BreakerSectionBounds& bounds, std::size_t labels,
                   std::vector<BreakerSectionPoint>& out) {
    check_bounds(bounds);
    if (labels == 0) throw InputError("outer section: no labels");
    if (!(ratio > 0.0) || !std::isfinite(ratio)) throw InputError("outer section: the height ratio 5H/W must be > 0 and finite");
    relabel(envelope(life, curl), ratio, bounds, labels, out);
}

void curl_section(double life, double curl, double ratio, const BreakerSectionBounds& bounds, std::size_t labels,
                  std::vector<BreakerSectionPoint>& out) {
    check_bounds(bounds);
    if (labels == 0) throw InputError("curl section: no labels");
    if (!(ratio > 0.0) || !std::isfinite(ratio)) throw InputError("curl section: the height ratio 5H/W must be > 0 and finite");
    std::vector<double> px, pz;
    curl_polyline(press_front(envelope(life, curl), ratio, life), ratio, plunge_of(curl), px, pz);
    relabel_polyline(px, pz, ratio, bounds, labels, out);
}

BreakerSections plan_breaker_sections(double curl_min, double curl_max, const BreakerSectionBounds& bounds, bool overturn) {
    check_bounds(bounds);
    if (!(curl_min >= 0.0 && curl_max <= 2.0 && curl_min <= curl_max))
        throw InputError("breakers: curls must lie in [0, 2], got " + std::to_string(curl_min) + " … " + std::to_string(curl_max));
    BreakerSections t;
    const auto first = std::floor(curl_min / t.curl_step), last = std::ceil(curl_max / t.curl_step);
    t.curl_first = first * t.curl_step;
    t.curls = static_cast<std::size_t>(last - first) + 1;
    t.lives = kLives;
    t.ratios = kRatios;
    t.log2_ratio_first = -5.0;
    t.labels = overturn ? 2 * kLabels : kLabels;  // the mouth holds a few labels more
    const std::size_t per_section = t.labels + 1, sections = t.lives * t.curls * t.ratios;
    t.x.resize(sections * per_section);
    t.z.resize(sections * per_section);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, t.lives * t.curls), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<BreakerSectionPoint> section;
        std::vector<double> px, pz;
        for (std::size_t lc = r.begin(); lc != r.end(); ++lc) {
            const std::size_t life_index = lc / t.curls;  // the table's life row (whole rows of curls)
            const double life = 2.0 * static_cast<double>(life_index) / static_cast<double>(t.lives - 1);
            const double curl = t.curl_first + t.curl_step * static_cast<double>(lc % t.curls);
            const std::vector<double> top = envelope(life, curl);
            for (std::size_t q = 0; q < t.ratios; ++q) {
                if (overturn) {
                    curl_polyline(press_front(top, ratio_at(t, q), life), ratio_at(t, q), plunge_of(curl), px, pz);
                    relabel_polyline(px, pz, ratio_at(t, q), bounds, t.labels, section);
                } else {
                    relabel(top, ratio_at(t, q), bounds, kLabels, section);
                }
                const std::size_t at = (lc * t.ratios + q) * per_section;
                for (std::size_t m = 0; m < per_section; ++m) {
                    t.x[at + m] = static_cast<float>(section[m].x);
                    t.z[at + m] = static_cast<float>(section[m].z);
                }
            }
        }
    });
    return t;
}

BreakerSectionPoint breaker_section(const BreakerSections& t, double life, double curl, double ratio, double s) noexcept {
    const auto [li, lw] = cell(life, 0.0, 2.0 / static_cast<double>(t.lives - 1), t.lives);
    const auto [ci, cw] = cell(curl, t.curl_first, t.curl_step, t.curls);
    const auto [ri, rw] = cell(std::log2(std::max(ratio, 1e-30)), t.log2_ratio_first, t.log2_ratio_step, t.ratios);
    const auto [si, sw] = cell(s * static_cast<double>(t.labels), 0.0, 1.0, t.labels + 1);
    BreakerSectionPoint p;
    for (std::size_t corner = 0; corner < 8; ++corner) {
        const std::size_t dl = corner & 1u, dc = (corner >> 1) & 1u, dr = (corner >> 2) & 1u;
        const double w = (dl ? lw : 1.0 - lw) * (dc ? cw : 1.0 - cw) * (dr ? rw : 1.0 - rw);
        if (w == 0.0) continue;
        const std::size_t l = std::min(li + dl, t.lives - 1), c = std::min(ci + dc, t.curls - 1), r = std::min(ri + dr, t.ratios - 1);
        const std::size_t at = ((l * t.curls + c) * t.ratios + r) * (t.labels + 1) + si;
        p.x += w * (t.x[at] + sw * (t.x[at + 1] - t.x[at]));
        p.z += w * (t.z[at] + sw * (t.z[at + 1] - t.z[at]));
    }
    return p;
}

}  // namespace wave
