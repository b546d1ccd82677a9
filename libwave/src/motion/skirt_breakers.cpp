// Jeschke's breakers carried beyond the domain onto the far field's skirt
// (libwave/motion.h, docs/far-field.md "Breakers beyond the border").
#include "core/format.h"
#include "core/smoothstep.h"
#include "libwave/bathymetry.h"
#include "libwave/errors.h"
#include "libwave/motion.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace wave {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

// Whether vertex v of the breakers sees breaking crests: traced, from a quarter
// wavelength before its earliest varied break to where its crests die.
bool in_surf_zone(const JeschkeMotionPlan& p, std::size_t v) noexcept {
    return p.width[v] > 0.0f && std::isfinite(p.break_phase[v]) &&
           p.phase[v] >= static_cast<double>(p.break_phase[v]) - two_pi * (0.25 + p.variation) &&
           p.phase[v] <= static_cast<double>(p.end_phase[v]);
}

// The bands held beyond the breakers' bounding rectangle: per side (0 bottom, 1 right,
// 2 top, 3 left), boxes reaching `band` m out from the side over the stretch of it
// nearest to one border vertex, sorted along the side (only bands > 0).
struct BandBox {
    double lo, hi, band;
};

struct BorderBands {
    double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
    std::array<std::vector<BandBox>, 4> sides;

    // The distance from (px, py) to the nearest held band, or `d` (its distance to the
    // rectangle) when that is nearer. The boxes of a side are disjoint and sorted, and a
    // box is no nearer than its gap along the side: the scan stops at the first gap
    // past the best.
    double distance(double px, double py, double d) const {
        double best = d;
        for (std::size_t side = 0; side < 4; ++side) {
            const std::vector<BandBox>& boxes = sides[side];
            const double along = side % 2 == 0 ? px : py;
            const double out = side == 0 ? y0 - py : side == 1 ? px - x1 : side == 2 ? py - y1 : x0 - px;
            const auto to = [&](const BandBox& b) {
                return std::hypot(std::max({0.0, b.lo - along, along - b.hi}), std::max({0.0, out - b.band, -out}));
            };
            const auto first = std::lower_bound(boxes.begin(), boxes.end(), along, [](const BandBox& b, double v) { return b.hi < v; });
            for (auto it = first; it != boxes.end() && it->lo - along < best; ++it) best = std::min(best, to(*it));
            for (auto it = first; it != boxes.begin() && along - std::prev(it)->hi < best; --it) best = std::min(best, to(*std::prev(it)));
        }
        return best;
    }
};

BorderBands border_bands(const JeschkeMotionPlan& p, const ElevationGrid& seafloor, double band_wavelengths) {
    BorderBands b;
    if (p.vertex_count() == 0) return b;
    const auto [xlo, xhi] = std::minmax_element(p.x.begin(), p.x.end());
    const auto [ylo, yhi] = std::minmax_element(p.y.begin(), p.y.end());
    b.x0 = *xlo, b.x1 = *xhi, b.y0 = *ylo, b.y1 = *yhi;
    const double tolerance = 1e-9 * std::max({1.0, b.x1 - b.x0, b.y1 - b.y0});
    constexpr double kOut = 0.01;  // m: where the water beyond the border is looked for
    constexpr std::array<std::array<double, 2>, 4> kNormal{{{0.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}}};
    std::array<std::vector<std::pair<double, double>>, 4> held;  // per side: (coordinate along it, band)
    for (std::size_t v = 0; v < p.vertex_count(); ++v) {
        const std::array<bool, 4> on{std::abs(p.y[v] - b.y0) <= tolerance, std::abs(p.x[v] - b.x1) <= tolerance,
                                     std::abs(p.y[v] - b.y1) <= tolerance, std::abs(p.x[v] - b.x0) <= tolerance};
        for (std::size_t side = 0; side < 4; ++side) {
            if (!on[side]) continue;
            const bool wet_beyond = depth_at(seafloor, p.x[v] + kOut * kNormal[side][0], p.y[v] + kOut * kNormal[side][1]) > 0.0;
            const double band = in_surf_zone(p, v) && wet_beyond ? std::max(0.0, band_wavelengths - 1.0) * p.width[v] : 0.0;
            held[side].emplace_back(side % 2 == 0 ? p.x[v] : p.y[v], band);
        }
    }
    // Each vertex holds the side from half way to its neighbour before to half way to the next.
    for (std::size_t side = 0; side < 4; ++side) {
        std::vector<std::pair<double, double>>& h = held[side];
        std::sort(h.begin(), h.end());
        const double start = side % 2 == 0 ? b.x0 : b.y0, end = side % 2 == 0 ? b.x1 : b.y1;
        for (std::size_t i = 0; i < h.size(); ++i)
            if (h[i].second > 0.0)
                b.sides[side].push_back({i == 0 ? start : 0.5 * (h[i - 1].first + h[i].first),
                                         i + 1 == h.size() ? end : 0.5 * (h[i].first + h[i + 1].first), h[i].second});
    }
    return b;
}

void check_band(double band_wavelengths) {
    if (!(band_wavelengths >= 0.0 && band_wavelengths <= 100.0))
        throw InputError("skirt breakers: band_wavelengths must be in [0, 100], got " + detail::format_number(band_wavelengths));
}

// The carried vertices' sizes agree and their indices (ascending) lie below `count`:
// one look at the last, not a pass a frame.
void check_targets(const SkirtBreakers& b, std::size_t count, const char* what) {
    const std::size_t n = b.vertex_count();
    if (b.weight.size() != n || b.plan.vertex_count() != n)
        throw InputError("skirt breakers: " + std::to_string(n) + " vertices, " + std::to_string(b.weight.size()) + " weights, " +
                         std::to_string(b.plan.vertex_count()) + " planned");
    if (n > 0 && b.vertex.back() >= count)
        throw InputError("skirt breakers: vertex " + std::to_string(b.vertex.back()) + " beyond the " + std::to_string(count) + " " + what);
}

}  // namespace

SkirtBreakers continue_jeschke_breakers(const JeschkeMotionPlan& p, const SeaSkirt& skirt, const ElevationGrid& seafloor,
                                        double band_wavelengths) {
    check_band(band_wavelengths);
    if (p.vertex_count() != skirt.surface_vertices)
        throw InputError("skirt breakers: the breakers hold " + std::to_string(p.vertex_count()) + " vertices, the skirt's surface " +
                         std::to_string(skirt.surface_vertices));
    SkirtBreakers out;
    if (band_wavelengths == 0.0) return out;
    JeschkeMotionPlan& q = out.plan;
    q.omega = p.omega;
    q.foam_fade_time = p.foam_fade_time;
    q.foam_onset = p.foam_onset;
    q.crest_draws = p.crest_draws;
    q.variation = p.variation;
    q.sections = p.sections;
    for (std::size_t v = 0; v < skirt.vertex_count(); ++v) {
        const std::uint32_t a = skirt.anchor_weight[v] >= 0.5f ? skirt.anchor[2 * v] : skirt.anchor[2 * v + 1];
        const double width = p.width[a];
        if (width == 0.0 || !(depth_at(seafloor, skirt.x[v], skirt.y[v]) > 0.0)) continue;  // untraced, or over land: the fit alone
        const double weight = 1.0 - detail::smoothstep(std::max(0.0, band_wavelengths - 1.0) * width, band_wavelengths * width, skirt.distance[v]);
        if (weight <= 0.0) continue;
        out.vertex.push_back(static_cast<std::uint32_t>(skirt.surface_vertices + v));
        out.weight.push_back(static_cast<float>(weight));
        q.x.push_back(skirt.x[v]);
        q.y.push_back(skirt.y[v]);
        q.dir_x.push_back(p.dir_x[a]);
        q.dir_y.push_back(p.dir_y[a]);
        q.phase.push_back(p.phase[a]);
        // The anchor's plane wave carried to the vertex: its crests arrive k D·(p − p_a) later.
        q.lag.push_back(two_pi / width * (p.dir_x[a] * (skirt.x[v] - p.x[a]) + p.dir_y[a] * (skirt.y[v] - p.y[a])));
        for (auto [to, from] : {std::pair{&q.width, &p.width}, {&q.scale, &p.scale}, {&q.mean_level, &p.mean_level},
                                {&q.break_phase, &p.break_phase}, {&q.end_phase, &p.end_phase}, {&q.rise, &p.rise},
                                {&q.breaking_length, &p.breaking_length}, {&q.curl, &p.curl}, {&q.foam_yield, &p.foam_yield}})
            to->push_back((*from)[a]);
        if (!p.life_start.empty()) q.life_start.push_back(p.life_start[a]);
    }
    return out;
}

SkirtSize breaker_skirt_size(SkirtSize size, const JeschkeMotionPlan& plan, const ElevationGrid& seafloor, double band_wavelengths) {
    check_band(band_wavelengths);
    if (!size) throw InputError("skirt breakers: no size function");
    if (band_wavelengths == 0.0) return size;
    return [size = std::move(size), bands = border_bands(plan, seafloor, band_wavelengths)](const SkirtSite& site) {
        SkirtSite past = site;
        past.d = bands.distance(site.x, site.y, site.d);
        return size(past);
    };
}

void evaluate_skirt_breakers(const SkirtBreakers& b, double t, std::span<float> positions, std::vector<float>& scratch) {
    const std::size_t n = b.vertex_count();
    check_targets(b, positions.size() / 3, "positions");
    scratch.resize(3 * n);
    evaluate_jeschke_breakers(b.plan, t, scratch);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const float w = b.weight[i];
            float* p = &positions[3 * static_cast<std::size_t>(b.vertex[i])];
            for (std::size_t c = 0; c < 3; ++c) p[c] = w * scratch[3 * i + c] + (1.0f - w) * p[c];
        }
    });
}

void skirt_breaker_foam(const SkirtBreakers& b, double t, std::span<float> foam, std::vector<float>& scratch) {
    const std::size_t n = b.vertex_count();
    check_targets(b, foam.size(), "foam values");
    scratch.resize(n);
    jeschke_foam(b.plan, t, scratch);
    for (std::size_t i = 0; i < n; ++i) foam[b.vertex[i]] = std::max(foam[b.vertex[i]], b.weight[i] * scratch[i]);
}

}  // namespace wave
