// Hermite smoothstep: 0 below e0, 1 above e1, 3t² − 2t³ between (t = (v − e0)/(e1 − e0)).
// Internal: the far field's residual band, the untangling's foam weight, the lip's foam.
#pragma once

#include <algorithm>

namespace wave::detail {

inline double smoothstep(double e0, double e1, double v) noexcept {
    const double t = std::clamp((v - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace wave::detail
