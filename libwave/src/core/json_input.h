// Internal: JSON read from a user's file (scene, contours, glTF, a frame index), and
// JSON values shown in error messages.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace wave::detail {

/// Parses `text` after check_json_nesting (core/limits.h); InputError naming `origin`
/// and the byte for malformed JSON and for numbers past a double's range.
nlohmann::json parse_json_input(std::string_view text, const std::string& origin);

/// `value` as JSON text cut to about 60 characters ("[[[[…" rather than a megabyte):
/// what an error message echoes of a value the user gave.
std::string brief_json(const nlohmann::json& value);

}  // namespace wave::detail
