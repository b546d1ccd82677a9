// GDAL, loaded on first use. Linked at start-up, libgdal and the ~110 libraries it
// brings cost every process ~135 ms of relocations before main() (docs/build-notes.md,
// "GDAL loaded on first use"): `wave validate` or a conversion that reads no raster paid
// it too. Its C API, taken by name from its soname (the one we built against) the
// first time a raster is read or a GeoTIFF written; GDAL's headers give the types.
#pragma once

#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <memory>
#include <string>
#include <type_traits>

namespace wave::detail {

// Every GDAL function libwave calls, listed once.
#define LIBWAVE_GDAL_FUNCTIONS(X)                                                                                      \
    X(GDALAllRegister)                                                                                                 \
    X(CPLPushErrorHandler) X(CPLPopErrorHandler) X(CPLQuietErrorHandler) X(CPLErrorReset) X(CPLGetLastErrorMsg)        \
    X(VSIFree) X(CSLAddString) X(CSLDestroy) X(VSIGetMemFileBuffer)                                                    \
    X(GDALOpenEx) X(GDALClose) X(GDALGetRasterCount) X(GDALGetMetadata) X(GDALGetGeoTransform)                        \
    X(GDALGetRasterXSize) X(GDALGetRasterYSize) X(GDALGetSpatialRef) X(GDALGetRasterBand) X(GDALGetDatasetDriver)      \
    X(GDALGetDriverShortName) X(GDALRasterIO) X(GDALGetRasterNoDataValue)                                              \
    X(GDALWarpAppOptionsNew) X(GDALWarpAppOptionsFree) X(GDALWarp)                                                     \
    X(GDALGetDriverByName) X(GDALCreate) X(GDALSetGeoTransform) X(GDALSetMetadataItem) X(GDALSetDescription)          \
    X(GDALSetRasterNoDataValue)                                                                                        \
    X(OSRNewSpatialReference) X(OSRClone) X(OSRDestroySpatialReference) X(OSRSetAxisMappingStrategy)                  \
    X(OSRSetWellKnownGeogCS) X(OSRCopyGeogCSFrom) X(OSRSetAE) X(OSRExportToWkt) X(OSRIsGeographic) X(OSRIsProjected)  \
    X(OSRGetName) X(OCTNewCoordinateTransformation) X(OCTTransform) X(OCTDestroyCoordinateTransformation)

/// GDAL's C API as function pointers (the members are named as GDAL names them).
struct GdalLibrary {
#define LIBWAVE_GDAL_MEMBER(name) decltype(&::name) name = nullptr;
    LIBWAVE_GDAL_FUNCTIONS(LIBWAVE_GDAL_MEMBER)
#undef LIBWAVE_GDAL_MEMBER
};

/// A GDAL handle (a pointer type) that `Close`, the library's function for it, closes
/// or destroys at the end of its scope.
template <typename Handle, typename Close>
using GdalOwned = std::unique_ptr<std::remove_pointer_t<Handle>, Close>;

/// GDAL, loaded and its drivers registered the first time (thread-safe). Throws Error
/// when it cannot be loaded, saying what it was needed for (`purpose`, e.g. a file).
const GdalLibrary& gdal(const std::string& purpose);

}  // namespace wave::detail
