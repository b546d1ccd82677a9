// Internal to the trace stage, shared by both tracers: input checks and where rays
// enter the domain.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/isobath.h"
#include "libwave/trace.h"

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

/// Slab clipping of the line p + t d against the box: the parameter interval inside.
bool clip(const Box& b, double px, double py, double dx, double dy, double& t0, double& t1);

/// Entry points of rays travelling along the unit direction (dx, dy), `spacing` apart
/// across it, where each ray's line enters the box; `s` is the position across the
/// train (m), and `phase_origin` the position along (dx, dy) of the up-wave corner,
/// from which the plane-wave start phase k ((x, y)·d − phase_origin) is counted.
struct EntryPoint {
    double x, y, s;
};
/// Throws LimitError (before allocating) when more than max_rays would enter.
std::vector<EntryPoint> entry_points(const Box& box, double dx, double dy, double spacing, std::size_t max_rays,
                                     double& phase_origin);

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
/// the products k√h and K_s h^{1/4} are smooth down to h → 0 (their shallow-water
/// limits are finite), so linear interpolation in s is accurate to ~1e-9 relative with
/// the default nodes. Depths below the first node or above the range, and capillary
/// waves, go to the exact solver.
class WaveTable {
public:
    struct Entry {
        double k = 0.0, celerity = 0.0, shoaling = 0.0;
    };
    WaveTable(double omega, double max_depth, const DispersionOptions& options, std::size_t nodes = 4096);
    Entry at(double depth) const;

private:
    Entry exact(double depth) const;
    double omega_;
    DispersionOptions options_;
    double ds_ = 0.0, s_max_ = 0.0;
    std::vector<double> k_root_h_, shoaling_quarter_h_;  // k √h and K_s h^{1/4} at s = i ds
};

}  // namespace wave::detail
