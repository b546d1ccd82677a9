// Raster grids through our GDAL wrapper (ESRI ASCII grid, the format surveys arrive in):
// header parsing, NODATA, NaN/Inf values, orientation. Seeds: data/bathymetry/*.asc.
#include "fuzz_input.h"
#include "libwave/bathymetry.h"

#include <gdal.h>
#include <cpl_conv.h>
#include <cpl_error.h>

#include <string>

// GDAL is left with its drivers of text grids: probing ~200 drivers per input took most
// of the time, and GDAL's other drivers are fuzzed by GDAL itself (OSS-Fuzz).
// libwave's GDALAllRegister then registers them again and drops them (GDAL_SKIP).
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    CPLSetErrorHandler(CPLQuietErrorHandler);  // GDAL's own warnings are not findings
    GDALAllRegister();
    std::string skip;
    for (int i = 0; i < GDALGetDriverCount(); ++i) {
        const std::string name = GDALGetDriverShortName(GDALGetDriver(i));
        if (name != "AAIGrid" && name != "GRASSASCIIGrid" && name != "XYZ" && name != "ISG") skip += name + " ";
    }
    CPLSetConfigOption("GDAL_SKIP", skip.c_str());
    GDALAllRegister();
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
