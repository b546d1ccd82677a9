// Internal to the trace stage, shared by both tracers: input checks and where rays
// enter the domain.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/isobath.h"
#include "libwave/trace.h"

#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace wave::detail {

/// Throws InputError, message starting with `where`, unless the train has a finite
/// period > 0 s, amplitude > 0 m and a finite non-zero direction.
void validate_wave_train(const WaveTrain& train, const std::string& where);

struct Box {
    double x0, y0, x1, y1;
};

inline Box domain_box(const ElevationGrid& g) { return {g.x0, g.y0, g.x_max(), g.y_max()}; }

/// The greatest depth over the grid's nodes (m), seafloor_stats' depth_max without the
/// rest of its statistics; 0 for an empty grid.
inline double deepest(const ElevationGrid& g) {
    return g.z.empty() ? 0.0 : -*std::min_element(g.z.begin(), g.z.end());
}

/// Slab clipping of the line p + t d against the box: the parameter interval inside.
bool clip(const Box& b, double px, double py, double dx, double dy, double& t0, double& t1);

/// Where and how the rays of a train enter the domain: `spacing` apart across the unit
/// direction (dx, dy), where each ray's line meets the box. The train is a plane wave
/// of direction (dx, dy) where the up-wave sides (those it enters across) are deepest —
/// on every shipped scene the up-wave corner, the corner it reaches first. Beyond each
/// side the seafloor is the side's own, continued along its outward normal n (the apron
/// the far field assumes too). Over the apron the depth varies only along the side, so
/// k·n keeps the reference's value (Snell) and the wave at an entry is the reference
/// wave refracted: direction (k_n n ± k_t t) / k with k_t = √(k² − k_n²), running along
/// the side away from the corner (or, with a dry corner or a train along the side's
/// normal, away from the side's deepest point), and phase ∫ k_t dt from there. On a side
/// of constant depth this is the plane wave k (x·d − corner·d) itself.
/// docs/conventions.md ("Where rays enter").
struct EntryPoint {
    double x = 0.0, y = 0.0;
    double s = 0.0;                // position across the train (m)
    double depth = 0.0;            // m; <= 0 on land (no ray starts there)
    double dx = 0.0, dy = 0.0;     // unit direction of travel on entry
    double phase = 0.0;            // rad, 0 at the up-wave corner
    /// The tube's width in the reference plane wave over its width across the train here
    /// (k_t of the reference over k_t here): b0 per metre of `s`, for K_r = √(b0 / b). 1
    /// on a side of constant depth.
    double tube = 1.0;
    /// Where the wave already broke over the apron (2 A∞ K_s K_r >= γ h there, as the
    /// tracers cap it): the phase the entering ray had at that point, phase − ∫ k ds along
    /// its path over the apron; NaN where the wave enters unbroken.
    double break_phase = std::numeric_limits<double>::quiet_NaN();
};
/// The train as it enters: ω, its deep-water amplitude A∞ and the breaker index γ the
/// tracers cap amplitudes with.
struct EntryWave {
    double omega = 0.0, deep_amplitude = 0.0, breaker_index = 0.0;
    DispersionOptions dispersion;
};
/// Throws LimitError (before allocating) when more than max_rays would enter.
std::vector<EntryPoint> entry_points(const ElevationGrid& grid, double dx, double dy, const EntryWave& train, double spacing,
                                     std::size_t max_rays);

/// The isobath segments a ray standing on its last crossing must not cross again: the
/// crossed segment, and its neighbours when the crossing was at a shared vertex.
struct CrossingSkip {
    static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
    std::size_t segment = none, previous = none, next = none;
};

/// The nearest isobath crossing ahead of (px, py) along the unit (dx, dy) within
/// `max_distance`, not re-crossing `skip`. `scale` is the domain size (tolerances).
/// Searches a short reach first and widens it: the next isobath is usually near, and a
/// query to the far side of the domain visits every tree box on the way.
std::optional<IsobathCrossing> next_crossing(const IsobathIndex& index, double px, double py, double dx, double dy,
                                             double max_distance, double scale, const CrossingSkip& skip);

/// What a ray standing on `hit` skips next.
CrossingSkip skip_after(const IsobathIndex& index, const IsobathCrossing& hit);

/// Snell's law at a crossed contour, sin i / C_before = sin r / C_after, with i and r
/// measured from the contour normal oriented along the ray; turns (dx, dy). Returns
/// false, having mirrored (dx, dy) across the contour, when sin r > 1 (total reflection).
bool refract_at_contour(const IsobathCrossing& hit, double celerity_before, double celerity_after, double& dx,
                        double& dy);

/// k, C and K_s of one frequency, tabulated over depth for the tracers' inner loops
/// (a dispersion solve per query was 40 % of the adaptive tracer's time). In s = √h
/// the products k√h, C/√h and K_s h^{1/4} are smooth down to h → 0 (their shallow-water
/// limits are finite), so linear interpolation in s is accurate to ~1e-9 relative with
/// the default nodes. C is interpolated too, not ω/k: a lookup costs two square roots
/// and one division (the three of ω/k and K_s's root were a tenth of a trace). Depths
/// below the first node or above the range, and capillary waves, go to the exact solver.
class WaveTable {
public:
    struct Entry {
        double k = 0.0, celerity = 0.0, shoaling = 0.0;
    };
    WaveTable(double omega, double max_depth, const DispersionOptions& options, std::size_t nodes = 4096);
    Entry at(double depth) const;
    /// at(depth).celerity alone (one square root): Snell's ratios ahead of a ray.
    double celerity(double depth) const;
    double omega() const noexcept { return omega_; }  ///< the frequency tabulated (rad/s)

private:
    Entry exact(double depth) const;
    /// Whether s = √depth lies between the first node and the last (else the exact solver).
    bool tabulated(double s) const noexcept { return !k_root_h_.empty() && s >= ds_ && s < s_max_; }
    double omega_;
    DispersionOptions options_;
    double ds_ = 0.0, inverse_ds_ = 0.0, s_max_ = 0.0;
    // k √h, C / √h and K_s h^{1/4} at s = i ds
    std::vector<double> k_root_h_, celerity_per_root_h_, shoaling_quarter_h_;
};

}  // namespace wave::detail
