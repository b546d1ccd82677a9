#include "core/limits.h"

#include "libwave/errors.h"

namespace wave::detail {

void check_json_nesting(std::string_view text, const std::string& origin) {
    int depth = 0;
    bool in_string = false, escaped = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonNesting)
                throw InputError(origin + ": JSON nested deeper than " + std::to_string(kMaxJsonNesting) +
                                 " arrays/objects at byte " + std::to_string(i) + " (no libwave file nests so deep)");
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
}

std::string format_count(std::size_t n) {
    return n == std::numeric_limits<std::size_t>::max() ? std::string("more than 2^64") : std::to_string(n);
}

}  // namespace wave::detail
