// GDAL loaded on first use (gdal_library.h).
#include "gdal_library.h"

#include "libwave/errors.h"

#include <dlfcn.h>

#include <string>
#include <type_traits>

namespace wave::detail {
namespace {

// The library and its functions; the reason it could not be loaded, if it could not.
struct Loaded {
    GdalLibrary api;
    std::string failure;
};

Loaded load() {
    Loaded out;
    // RTLD_LOCAL: GDAL's ~110 libraries stay out of the process's global symbol scope.
    void* handle = dlopen(LIBWAVE_GDAL_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = dlerror();
        out.failure = std::string("GDAL (" LIBWAVE_GDAL_SONAME ") could not be loaded: ") + (why ? why : "no reason given");
        return out;
    }
    const auto take = [&](auto& function, const char* name) {
        function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(handle, name));
        if (!function && out.failure.empty())
            out.failure = std::string("GDAL (" LIBWAVE_GDAL_SONAME ") has no function ") + name;
    };
#define LIBWAVE_GDAL_TAKE(name) take(out.api.name, #name);
    LIBWAVE_GDAL_FUNCTIONS(LIBWAVE_GDAL_TAKE)
#undef LIBWAVE_GDAL_TAKE
    if (out.failure.empty()) out.api.GDALAllRegister();
    return out;  // the handle stays open for the process's life
}

}  // namespace

const GdalLibrary& gdal(const std::string& purpose) {
    static const Loaded loaded = load();  // once, thread-safe
    if (!loaded.failure.empty()) throw Error(purpose + ": " + loaded.failure);
    return loaded.api;
}

}  // namespace wave::detail
