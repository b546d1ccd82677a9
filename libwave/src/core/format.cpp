#include "core/format.h"

#include <sstream>

namespace wave::detail {

std::string format_number(double v) {
    std::ostringstream s;
    s.precision(15);
    s << v;
    return s.str();
}

}  // namespace wave::detail
