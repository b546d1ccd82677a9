// The wave field as a GeoTIFF (GDAL): the io component.
#include "libwave/field.h"

#include "bathymetry/gdal_library.h"
#include "core/format.h"
#include "libwave/errors.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <memory>

namespace wave {

std::string field_geotiff(const FieldRaster& r, const Seafloor& seafloor) {
    const detail::GdalLibrary& g = detail::gdal("wave field (GeoTIFF)");
    GDALDriverH driver = g.GDALGetDriverByName("GTiff");
    if (!driver) throw Error("wave field: GDAL has no GTiff driver");
    static std::atomic<unsigned> serial{0};
    const std::string path = "/vsimem/libwave-field-" + std::to_string(serial++) + ".tif";
    {
        const detail::GdalOwned<GDALDatasetH, decltype(&GDALClose)> ds(
            g.GDALCreate(driver, path.c_str(), static_cast<int>(r.nx), static_cast<int>(r.ny), 3, GDT_Float32, nullptr),
            g.GDALClose);
        if (!ds) throw Error("wave field: GDAL could not create the GeoTIFF");
        // Row 0 of a GeoTIFF is the top (north): the raster's last row.
        double transform[6] = {r.x0 - 0.5 * r.spacing, r.spacing, 0.0,
                               r.y0 + (static_cast<double>(r.ny) - 0.5) * r.spacing, 0.0, -r.spacing};
        g.GDALSetGeoTransform(ds.get(), transform);
        g.GDALSetMetadataItem(ds.get(), "LIBWAVE_FRAME", seafloor.frame.c_str(), nullptr);
        g.GDALSetMetadataItem(ds.get(), "LIBWAVE_SEAFLOOR", seafloor.source.c_str(), nullptr);
        g.GDALSetMetadataItem(ds.get(), "LIBWAVE_H0_M", detail::format_number(r.incident_height).c_str(), nullptr);
        const std::array<const std::vector<float>*, 3> bands{&r.height_ratio, &r.phase, &r.direction_deg};
        const std::array<const char*, 3> names{"H/H0", "phase (rad)", "direction (degrees from +x)"};
        std::vector<float> row(r.nx);
        for (int b = 0; b < 3; ++b) {
            GDALRasterBandH band = g.GDALGetRasterBand(ds.get(), b + 1);
            g.GDALSetDescription(band, names[static_cast<std::size_t>(b)]);
            g.GDALSetRasterNoDataValue(band, std::numeric_limits<double>::quiet_NaN());
            for (std::size_t j = 0; j < r.ny; ++j) {
                const float* src = &(*bands[static_cast<std::size_t>(b)])[(r.ny - 1 - j) * r.nx];
                std::copy(src, src + r.nx, row.begin());
                if (g.GDALRasterIO(band, GF_Write, 0, static_cast<int>(j), static_cast<int>(r.nx), 1, row.data(),
                                   static_cast<int>(r.nx), 1, GDT_Float32, 0, 0) != CE_None)
                    throw Error("wave field: GDAL could not write the GeoTIFF");
            }
        }
    }
    vsi_l_offset size = 0;
    GByte* data = g.VSIGetMemFileBuffer(path.c_str(), &size, TRUE);
    std::string bytes(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size));
    g.VSIFree(data);
    return bytes;
}

}  // namespace wave
