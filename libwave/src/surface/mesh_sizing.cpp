// The water mesh's sizing by the local wavelength of a wave train (surface.h).
#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/physics.h"
#include "libwave/surface.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wave {

EdgeSize wavelength_edge_size(const Seafloor& seafloor, const WaveTrain& train, double per_wavelength,
                              double breaker_index) {
    if (!(per_wavelength > 0.0) || !std::isfinite(per_wavelength))
        throw InputError("water mesh: per_wavelength must be > 0, got " + detail::format_number(per_wavelength));
    if (!(breaker_index > 0.0) || !std::isfinite(breaker_index))
        throw InputError("water mesh: breaker_index must be > 0, got " + detail::format_number(breaker_index));
    if (!(train.period > 0.0) || !(train.amplitude > 0.0) || !std::isfinite(train.period) || !std::isfinite(train.amplitude))
        throw InputError("water mesh: the wave train needs a period and an amplitude > 0");
    const double omega = 2.0 * std::numbers::pi / train.period;
    const double floor_depth = std::max(2.0 * train.amplitude / breaker_index, 1e-3);
    const ElevationGrid* grid = &seafloor.grid;
    return [grid, omega, floor_depth, per_wavelength](double x, double y) {
        return linear_wave(omega, std::max(depth_at(*grid, x, y), floor_depth)).wavelength / per_wavelength;
    };
}

SkirtSize swell_skirt_size(const Seafloor& seafloor, double shortest_period, double swell_wavelengths, double min_depth) {
    if (!(shortest_period > 0.0) || !std::isfinite(shortest_period))
        throw InputError("sea skirt: the shortest period must be > 0 s, got " + detail::format_number(shortest_period));
    if (!(swell_wavelengths > 0.0) || !std::isfinite(swell_wavelengths))
        throw InputError("sea skirt: swell_wavelengths must be > 0, got " + detail::format_number(swell_wavelengths));
    if (!(min_depth > 0.0) || !std::isfinite(min_depth))
        throw InputError("sea skirt: min_depth must be > 0 m, got " + detail::format_number(min_depth));
    const ElevationGrid* grid = &seafloor.grid;
    return [grid, shortest_period, swell_wavelengths, min_depth](const SkirtSite& site) {
        const double depth = std::max(depth_at(*grid, site.bx, site.by), min_depth), d = site.d, edge = site.border_edge;
        const double wavelength = 2.0 * std::numbers::pi / wavenumber_for_period(shortest_period, depth);
        const double base = std::max(edge, wavelength / 6.0), band = swell_wavelengths * wavelength;
        if (d <= band) return std::min(edge + 0.3 * d, base);
        const double out = d - band;
        return base + 0.08 * out + 0.3 * out * out / (out + 2.0 * wavelength);
    };
}

}  // namespace wave
