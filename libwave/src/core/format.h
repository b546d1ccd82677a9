// Internal: numbers in error messages, with enough digits to find the value again.
#pragma once

#include <string>

namespace wave::detail {

/// Shortest decimal text (up to 15 significant digits) of v, e.g. "0.25", "1e-09", "nan".
std::string format_number(double v);

}  // namespace wave::detail
