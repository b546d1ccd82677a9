// Depth-limited breaking and breaker classification by the Iribarren number.
#include "libwave/physics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wave {

bool is_depth_limited_breaking(double wave_height, double depth, double breaker_index) noexcept {
    if (depth <= 0.0) return true;
    return wave_height >= breaker_index * depth;
}

double iribarren_number(double slope, double deep_height, double deep_wavelength) noexcept {
    // ξ0 = tan β / sqrt(H0/L0) (Battjes 1974); a flat bottom gives 0 (spilling).
    return slope / std::sqrt(deep_height / deep_wavelength);
}

BreakerType classify_breaker(double iribarren, const BreakerThresholds& t) noexcept {
    if (iribarren < t.spilling_to_plunging) return BreakerType::spilling;
    if (iribarren < t.plunging_to_collapsing) return BreakerType::plunging;
    if (iribarren < t.collapsing_to_surging) return BreakerType::collapsing;
    return BreakerType::surging;
}

const char* to_string(BreakerType type) noexcept {
    switch (type) {
        case BreakerType::spilling: return "spilling";
        case BreakerType::plunging: return "plunging";
        case BreakerType::collapsing: return "collapsing";
        case BreakerType::surging: return "surging";
    }
    return "unknown";
}

}  // namespace wave

namespace wave {

ShoalingProfile shoal_profile(double omega, double deep_height, std::span<const double> depth,
                              double spacing, double breaker_index,
                              const BreakerThresholds& thresholds) {
    ShoalingProfile p;
    p.height.assign(depth.size(), 0.0);
    for (std::size_t n = 0; n < depth.size(); ++n) {
        const LinearWave w = linear_wave(omega, depth[n]);
        p.height[n] = deep_height * w.shoaling;  // energy flux conserved: H = H∞ K_s
        if (p.break_index < 0 && is_depth_limited_breaking(p.height[n], depth[n], breaker_index)) {
            p.break_index = static_cast<std::ptrdiff_t>(n);
            p.break_depth = depth[n];
            p.break_height = p.height[n];
            // Battjes' ξ0 uses the beach slope the wave feels: the mean over one local
            // wavelength seaward of the break point.
            const double wavelength = w.dry ? spacing : w.wavelength;
            const auto back = std::min<std::size_t>(
                n, static_cast<std::size_t>(std::ceil(wavelength / spacing)));
            const double slope =
                back > 0 ? std::abs(depth[n - back] - depth[n]) / (static_cast<double>(back) * spacing) : 0.0;
            const double deep_wavelength = 2.0 * std::numbers::pi / deep_water_wavenumber(omega);
            p.iribarren = iribarren_number(slope, deep_height, deep_wavelength);
            p.type = classify_breaker(p.iribarren, thresholds);
        }
        if (w.dry) p.height[n] = 0.0;
    }
    return p;
}

}  // namespace wave
