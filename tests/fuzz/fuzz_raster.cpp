// Raster grids through our GDAL wrapper (ESRI ASCII grid, the format surveys arrive in):
// header parsing, NODATA, NaN/Inf values, orientation. Seeds: data/bathymetry/*.asc.
#include "fuzz_input.h"
#include "libwave/bathymetry.h"

#include <gdal.h>
#include <cpl_error.h>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    CPLSetErrorHandler(CPLQuietErrorHandler);  // GDAL's own warnings are not findings
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    wave::ReadOptions o;
    o.max_nodes = wave::fuzz::kMaxNodes;
    const wave::fuzz::InputFile file(data, size, ".asc");
    const std::string& path = file.path;
    wave::fuzz::expect_input_error_only([&] { wave::read_raster_gdal(path, o); });
    return 0;
}
