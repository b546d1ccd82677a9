#include "core/json_input.h"

#include "core/limits.h"
#include "libwave/errors.h"

namespace wave::detail {

nlohmann::json parse_json_input(std::string_view text, const std::string& origin) {
    check_json_nesting(text, origin);
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw InputError(origin + ": not valid JSON (byte " + std::to_string(e.byte) + "): " + e.what());
    } catch (const nlohmann::json::exception& e) {  // out_of_range: a number too large for a double
        throw InputError(origin + ": not valid JSON: " + e.what());
    }
}

std::string brief_json(const nlohmann::json& value) {
    constexpr std::size_t kShown = 60;
    // Containers are cut before printing (nesting is bounded, but a 1 MB array would be
    // printed whole only to be cut): their first few items stand for them.
    nlohmann::json shown = value;
    bool cut = false;
    if (value.is_array() && value.size() > 8) {
        shown = nlohmann::json::array();
        for (std::size_t i = 0; i < 8; ++i) shown.push_back(value[i]);
        cut = true;
    }
    std::string text = shown.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (text.size() > kShown) {
        std::size_t end = kShown;
        while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;  // whole UTF-8 characters
        text.resize(end);
        cut = true;
    }
    return cut ? text + "…" : text;
}

}  // namespace wave::detail
