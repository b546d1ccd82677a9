// Internal to the trace stage, shared by both tracers: input checks and where rays
// enter the domain.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/trace.h"

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

}  // namespace wave::detail
