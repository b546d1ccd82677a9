// Internal: SplitMix64 (Steele, Lea & Flood 2014), the counter-based hash behind every
// seeded draw (the ocean's amplitudes, the breakers' per-wave variation): a value
// depends on its key only — not on traversal order, thread count or grid size.
#pragma once

#include <cstdint>

namespace wave::detail {

constexpr std::uint64_t splitmix64(std::uint64_t x) noexcept {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

}  // namespace wave::detail
