#include "libwave/version.h"

namespace wave {
const char* version() noexcept { return LIBWAVE_VERSION_STRING; }
}  // namespace wave
