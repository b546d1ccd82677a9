// Internal: the two guards every reader and planner of input-sized work shares.
//  * Nesting: JSON is parsed and printed by recursion (tinygltf's parser; printing a
//    value in an error message), so text nested deeper than kMaxJsonNesting is refused
//    by a flat scan before any parser sees it — scene files, contour files, glTF.
//  * Sizes: a count built from input values (grid nodes × samples, image pixels, frames
//    × vertices) is computed saturating at SIZE_MAX, so the limit check that follows it
//    is exact however large the values are: no wrap-around past a limit.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>

namespace wave::detail {

/// Deepest nesting of arrays and objects accepted in any JSON input (libwave's own
/// files nest 6 deep at most; a glTF's extras a little more).
inline constexpr int kMaxJsonNesting = 64;

/// Throws InputError("<origin>: JSON nested deeper than 64 arrays/objects at byte N")
/// if `text` opens more than kMaxJsonNesting brackets at once. Brackets inside strings
/// (with their escapes) do not count; the text need not be valid JSON otherwise.
void check_json_nesting(std::string_view text, const std::string& origin);

/// a · b, or SIZE_MAX if it does not fit.
constexpr std::size_t mul_sat(std::size_t a, std::size_t b) noexcept {
    if (a != 0 && b > std::numeric_limits<std::size_t>::max() / a) return std::numeric_limits<std::size_t>::max();
    return a * b;
}

/// a + b, or SIZE_MAX if it does not fit.
constexpr std::size_t add_sat(std::size_t a, std::size_t b) noexcept {
    return b > std::numeric_limits<std::size_t>::max() - a ? std::numeric_limits<std::size_t>::max() : a + b;
}

/// "12345678", or "more than 2^64" for SIZE_MAX (a saturated count) — for limit messages.
std::string format_count(std::size_t n);

}  // namespace wave::detail
