// glTF's normalised integers (KHR_mesh_quantization) as the writer and the reader both
// decode them: one rule, so that a float written to equal a decoded integer does.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace wave::detail {

// The integer nearest x (x = a value times the type's scale, e.g. 32767), clamped to
// the type's range: how every normalised integer is written.
template <class Int>
Int nearest(double x) noexcept {
    return static_cast<Int>(std::clamp(std::round(x), double{std::numeric_limits<Int>::min()}, double{std::numeric_limits<Int>::max()}));
}

// A normalised int16 as glTF decodes it: max(q / 32767, −1). In double; cast to float,
// it is also the correctly rounded float quotient (q / 32767 lies nowhere near a float's
// rounding midpoint, so rounding twice changes nothing).
constexpr double snorm16(std::int16_t q) noexcept { return std::max(q / 32767.0, -1.0); }

}  // namespace wave::detail
