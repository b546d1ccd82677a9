// The terrain beyond a grid's rectangle: the land and sea bottom of the exported
// seafloor's apron (docs/far-field.md#the-terrain-beyond-the-data).
#include "libwave/bathymetry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace wave {
namespace {

// splitmix64: the hills' directions and phases from the seed.
double uniform(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
}

double smoothstep(double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// The node before s (s in [0, perimeter)) and the fraction towards the next.
std::pair<std::size_t, double> segment(const TerrainBeyond& t, double s) {
    const std::size_t n = t.s.size();
    std::size_t k = static_cast<std::size_t>(std::upper_bound(t.s.begin(), t.s.end(), s) - t.s.begin());
    k = k == 0 ? 0 : k - 1;
    const double next = k + 1 < n ? t.s[k + 1] : t.perimeter;
    return {k, next > t.s[k] ? std::clamp((s - t.s[k]) / (next - t.s[k]), 0.0, 1.0) : 0.0};
}

double wrap(double s, double p) {
    const double w = std::fmod(s, p);
    return w < 0.0 ? w + p : w;
}

// ∫ f ds from 0 to s (any s: whole loops add the loop's integral), `cum` the integral
// at the nodes and `f` the integrand at node k (linear between nodes).
template <class F>
double integral(const TerrainBeyond& t, const std::vector<double>& cum, F&& f, double s) {
    const double loops = std::floor(s / t.perimeter);
    const double r = s - loops * t.perimeter;
    const auto [k, u] = segment(t, r);
    const std::size_t n = t.s.size();
    const double f0 = f(k), f1 = f((k + 1) % n);
    const double next = k + 1 < n ? t.s[k + 1] : t.perimeter;
    const double len = (next - t.s[k]) * u;
    return loops * cum[n] + cum[k] + len * (f0 + 0.5 * (f1 - f0) * u);
}

// Band-limited hills in [−1, 1]: 8 octaves of 3 sines each, an octave's weight
// growing as √wavelength, faded out where `resolution` exceeds an eighth of its
// wavelength (gone at a quarter).
double hills(const TerrainBeyond& t, double x, double y, double resolution) {
    double sum = 0.0, norm = 0.0;
    for (int k = 0; k < 8; ++k) {
        const double wavelength = t.options.hill_wavelength * std::ldexp(1.0, k);
        const double weight = std::sqrt(std::ldexp(1.0, k));
        norm += weight;
        const double keep = std::clamp(2.0 - 8.0 * resolution / wavelength, 0.0, 1.0);
        if (keep == 0.0) continue;
        double octave = 0.0;
        for (int j = 0; j < 3; ++j) octave += std::sin(t.hill_kx[k][j] * x + t.hill_ky[k][j] * y + t.hill_phase[k][j]);
        sum += weight * keep * octave / 3.0;
    }
    return sum / norm;
}

// The far ranges' profile in [0, 1] along the azimuth θ about the grid's centre: 12
// harmonics of θ (3, 4, 5, 7, … 71 turns a circle), weights falling as 1/√f, ridged
// (1 − |sum|: sharp crests, broad valleys); a harmonic fades out where the mesh's edges
// at distance d exceed a quarter of its wavelength 2πd/f (gone at a half: a skyline
// needs four vertices a crest, not the hills' eight), and the profile with it towards
// its mean (0.5) by the share of the weight left out: a mesh too coarse for the ranges
// gets their mean height, not their crests'.
double ranges(const TerrainBeyond& t, double theta, double d, double resolution) {
    static constexpr double kTurns[12] = {3, 4, 5, 7, 9, 12, 16, 21, 28, 38, 52, 71};
    double sum = 0.0, norm = 0.0, kept = 0.0;
    for (int k = 0; k < 12; ++k) {
        const double weight = 1.0 / std::sqrt(kTurns[k]);
        norm += weight;
        const double wavelength = 2.0 * std::numbers::pi * d / kTurns[k];
        const double keep = std::clamp(2.0 - 4.0 * resolution / wavelength, 0.0, 1.0);
        kept += weight * keep;
        sum += weight * keep * std::sin(kTurns[k] * theta + t.range_phase[k]);
    }
    if (kept <= 0.0) return 0.5;
    return 0.5 + (kept / norm) * (0.5 - std::abs(sum / kept));
}

// The distance (m) from (x, y) to the nearest of the far field's cuts: the lines out
// from where the shoreline meets the border, along that side's outward normal (the
// skirt's water ends on them); infinite without a shoreline on the border.
double cut_distance(const TerrainBeyond& t, double x, double y) {
    const double w = t.x1 - t.x0, h = t.y1 - t.y0;
    double nearest = std::numeric_limits<double>::infinity();
    for (const double c : t.shore) {
        double px, py, nx, ny;
        if (c < w) px = t.x0 + c, py = t.y0, nx = 0.0, ny = -1.0;
        else if (c < w + h) px = t.x1, py = t.y0 + (c - w), nx = 1.0, ny = 0.0;
        else if (c < 2.0 * w + h) px = t.x1 - (c - w - h), py = t.y1, nx = 0.0, ny = 1.0;
        else px = t.x0, py = t.y1 - (c - 2.0 * w - h), nx = -1.0, ny = 0.0;
        const double along = (x - px) * nx + (y - py) * ny;
        const double across = (x - px) * -ny + (y - py) * nx;
        nearest = std::min(nearest, along > 0.0 ? std::abs(across) : std::hypot(x - px, y - py));
    }
    return nearest;
}

}  // namespace

TerrainBeyond plan_terrain_beyond(const ElevationGrid& g, const TerrainBeyondOptions& options) {
    TerrainBeyond t;
    t.x0 = g.x0;
    t.y0 = g.y0;
    t.x1 = g.x_max();
    t.y1 = g.y_max();
    const double w = t.x1 - t.x0, h = t.y1 - t.y0;
    t.perimeter = 2.0 * (w + h);
    // The border nodes counter-clockwise from (x0, y0), each corner once.
    const auto push = [&](std::size_t i, std::size_t j, double s) {
        t.s.push_back(s);
        t.z.push_back(g.at(i, j));
    };
    for (std::size_t i = 0; i + 1 < g.nx; ++i) push(i, 0, static_cast<double>(i) * g.dx);
    for (std::size_t j = 0; j + 1 < g.ny; ++j) push(g.nx - 1, j, w + static_cast<double>(j) * g.dy);
    for (std::size_t i = g.nx - 1; i > 0; --i) push(i, g.ny - 1, w + h + static_cast<double>(g.nx - 1 - i) * g.dx);
    for (std::size_t j = g.ny - 1; j > 0; --j) push(0, j, 2.0 * w + h + static_cast<double>(g.ny - 1 - j) * g.dy);
    const std::size_t n = t.s.size();
    t.land.assign(n + 1, 0.0);
    t.land_len.assign(n + 1, 0.0);
    t.sea.assign(n + 1, 0.0);
    t.sea_len.assign(n + 1, 0.0);
    double highest = 0.0;
    for (double z : g.z) highest = std::max(highest, z);
    for (std::size_t k = 0; k < n; ++k) {
        const double z0 = t.z[k], z1 = t.z[(k + 1) % n];
        const double len = (k + 1 < n ? t.s[k + 1] : t.perimeter) - t.s[k];
        t.land[k + 1] = t.land[k] + 0.5 * len * (std::max(z0, 0.0) + std::max(z1, 0.0));
        t.land_len[k + 1] = t.land_len[k] + 0.5 * len * ((z0 >= 0.0 ? 1.0 : 0.0) + (z1 >= 0.0 ? 1.0 : 0.0));
        t.sea[k + 1] = t.sea[k] + 0.5 * len * (std::min(z0, 0.0) + std::min(z1, 0.0));
        t.sea_len[k + 1] = t.sea_len[k] + 0.5 * len * ((z0 >= 0.0 ? 0.0 : 1.0) + (z1 >= 0.0 ? 0.0 : 1.0));
        if ((z0 >= 0.0) != (z1 >= 0.0)) t.shore.push_back(t.s[k] + len * z0 / (z0 - z1));  // where z crosses 0
    }
    const double size = std::max(w, h);
    t.options = options;
    if (!(t.options.relief > 0.0)) t.options.relief = std::max(0.05 * size, 0.5 * highest);
    if (!(t.options.rise_distance > 0.0)) t.options.rise_distance = 0.5 * size;
    if (!(t.options.hill_wavelength > 0.0)) t.options.hill_wavelength = 0.25 * size;
    std::uint64_t state = options.seed;
    for (int k = 0; k < 8; ++k)
        for (int j = 0; j < 3; ++j) {
            const double wavelength = t.options.hill_wavelength * std::ldexp(1.0, k) * (0.85 + 0.3 * uniform(state));
            const double angle = 2.0 * std::numbers::pi * uniform(state);
            t.hill_kx[k][j] = 2.0 * std::numbers::pi / wavelength * std::cos(angle);
            t.hill_ky[k][j] = 2.0 * std::numbers::pi / wavelength * std::sin(angle);
            t.hill_phase[k][j] = 2.0 * std::numbers::pi * uniform(state);
        }
    for (double& phase : t.range_phase) phase = 2.0 * std::numbers::pi * uniform(state);
    return t;
}

double terrain_elevation(const TerrainBeyond& t, double x, double y, double resolution) noexcept {
    if (t.s.empty()) return 0.0;
    const double cx = std::clamp(x, t.x0, t.x1), cy = std::clamp(y, t.y0, t.y1);
    const double d = std::hypot(x - cx, y - cy);
    const double w = t.x1 - t.x0, h = t.y1 - t.y0;
    double s;  // the foot's perimeter coordinate, counter-clockwise from (x0, y0)
    if (y < t.y0) s = cx - t.x0;
    else if (x > t.x1) s = w + (cy - t.y0);
    else if (y > t.y1) s = w + h + (t.x1 - cx);
    else if (x < t.x0) s = 2.0 * w + h + (t.y1 - cy);
    else s = 0.0;  // inside: not the terrain beyond's; the nearest side's value below
    if (x >= t.x0 && x <= t.x1 && y >= t.y0 && y <= t.y1) {
        const double to[4] = {y - t.y0, t.x1 - x, t.y1 - y, x - t.x0};
        const int side = static_cast<int>(std::min_element(to, to + 4) - to);
        s = side == 0 ? x - t.x0 : side == 1 ? w + (y - t.y0) : side == 2 ? w + h + (t.x1 - x) : 2.0 * w + h + (t.y1 - y);
    }
    s = wrap(s, t.perimeter);
    const auto [k, u] = segment(t, s);
    const double z_foot = t.z[k] + (t.z[(k + 1) % t.z.size()] - t.z[k]) * u;
    if (d <= 0.0) return z_foot;

    // The land's and the sea's means over the window ±d/2 along the border.
    const double half = 0.5 * d;
    const auto mean = [&](const std::vector<double>& value, const std::vector<double>& length, auto&& f, auto&& in) {
        const double v = integral(t, value, f, s + half) - integral(t, value, f, s - half);
        const double l = integral(t, length, in, s + half) - integral(t, length, in, s - half);
        return l > 1e-9 * d ? v / l : 0.0;
    };
    const double land_mean = mean(t.land, t.land_len, [&](std::size_t i) { return std::max(t.z[i], 0.0); },
                                  [&](std::size_t i) { return t.z[i] >= 0.0 ? 1.0 : 0.0; });
    const TerrainBeyondOptions& o = t.options;
    const double size = std::max(t.x1 - t.x0, t.y1 - t.y0);
    // The distance along the border to where the shoreline meets it (the far field's
    // skirt ends on a straight cut there, perpendicular to the side).
    double shore = std::numeric_limits<double>::infinity();
    for (double c : t.shore) {
        const double a = std::abs(s - c);
        shore = std::min(shore, std::min(a, t.perimeter - a));
    }
    const double n = hills(t, x, y, resolution);
    const double rise = smoothstep(d / o.rise_distance);
    const double dune_at = (d - 0.3 * o.rise_distance) / (0.12 * o.rise_distance);
    const double dune = 0.5 * std::exp(-dune_at * dune_at) * (1.0 + 0.5 * n) * smoothstep(d / (0.15 * o.rise_distance));
    const double inland = land_mean + o.relief * (rise * (1.0 + 0.6 * n) + dune);  // > 0 for d > 0
    // Near that cut the land comes down to a low coast (a twentieth of the relief, with
    // low hills), over a width growing with d: the inland's height there, 130 m over
    // Okushiri's, stood as a wall along the cut to the horizon, and a slope of a quarter
    // of the grid still did, seen end-on from 20 km.
    const double coastal = std::max(z_foot, 0.0) + o.relief * rise * (0.05 + 0.1 * (1.0 + n));
    const double taper = smoothstep(shore / std::max(0.25 * size, 0.5 * d));
    // The far ranges: from twice the grid's size out the land climbs on, 0.6–4.6 % of the
    // distance (a constant angle seen from the grid: the rolling land's top, a few
    // metres high to the horizon, read as a ruled line across the frame), its crests
    // along the azimuth; away from the skirt's cuts only (a range beside a cut would
    // stand as a wall along the water's straight edge), by the distance to the nearest
    // cut's line out over d (the angle seen from the cut's foot).
    const double theta = std::atan2(y - 0.5 * (t.y0 + t.y1), x - 0.5 * (t.x0 + t.x1));
    const double clear = smoothstep(cut_distance(t, x, y) / (0.4 * d) - 0.25);
    const double far = clear * d * smoothstep((d - 2.0 * size) / (10.0 * size)) * (0.006 + 0.04 * ranges(t, theta, d, resolution));
    const double land = coastal + (inland - coastal) * taper + far;
    if (z_foot >= 0.0) return land;  // land is h <= 0 (docs/conventions.md)

    const double sea_mean = mean(t.sea, t.sea_len, [&](std::size_t i) { return std::min(t.z[i], 0.0); },
                                 [&](std::size_t i) { return t.z[i] >= 0.0 ? 0.0 : 1.0; });
    // Beside land: the coast runs on over the sea, falling to the sea's depth over a width
    // that grows with d and wobbles with the hills, so the coast leaves the skirt's
    // straight cut. The width is at most a tenth of the grid (a corner's quadrant beyond
    // holds one foot, the corner, so a width growing on with d would turn it all to
    // land), and where the mesh allows, no narrower than two of its edges.
    const double width = std::min(std::max(0.25 * d, 2.0 * resolution), 0.1 * size) *
                         (1.0 + 0.6 * hills(t, -y + 0.37 * o.hill_wavelength, x, resolution));
    if (!std::isfinite(shore) || !(width > 0.0)) return sea_mean;
    return std::max(sea_mean, land - (land - sea_mean) * 2.0 * shore / width);  // the sea's own at shore = width / 2
}

}  // namespace wave
