// The wave field as a GeoTIFF (GDAL): the io component.
#include "libwave/field.h"

#include "core/format.h"
#include "libwave/errors.h"

#include <cpl_vsi.h>
#include <gdal_priv.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <memory>
#include <mutex>

namespace wave {

std::string field_geotiff(const FieldRaster& r, const Seafloor& seafloor) {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    if (!driver) throw Error("wave field: GDAL has no GTiff driver");
    static std::atomic<unsigned> serial{0};
    const std::string path = "/vsimem/libwave-field-" + std::to_string(serial++) + ".tif";
    {
        std::unique_ptr<GDALDataset, void (*)(GDALDataset*)> ds(
            driver->Create(path.c_str(), static_cast<int>(r.nx), static_cast<int>(r.ny), 3, GDT_Float32, nullptr),
            [](GDALDataset* d) { GDALClose(d); });
        if (!ds) throw Error("wave field: GDAL could not create the GeoTIFF");
        // Row 0 of a GeoTIFF is the top (north): the raster's last row.
        double transform[6] = {r.x0 - 0.5 * r.spacing, r.spacing, 0.0,
                               r.y0 + (static_cast<double>(r.ny) - 0.5) * r.spacing, 0.0, -r.spacing};
        ds->SetGeoTransform(transform);
        ds->SetMetadataItem("LIBWAVE_FRAME", seafloor.frame.c_str());
        ds->SetMetadataItem("LIBWAVE_SEAFLOOR", seafloor.source.c_str());
        ds->SetMetadataItem("LIBWAVE_H0_M", detail::format_number(r.incident_height).c_str());
        const std::array<const std::vector<float>*, 3> bands{&r.height_ratio, &r.phase, &r.direction_deg};
        const std::array<const char*, 3> names{"H/H0", "phase (rad)", "direction (degrees from +x)"};
        std::vector<float> row(r.nx);
        for (int b = 0; b < 3; ++b) {
            GDALRasterBand* band = ds->GetRasterBand(b + 1);
            band->SetDescription(names[static_cast<std::size_t>(b)]);
            band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
            for (std::size_t j = 0; j < r.ny; ++j) {
                const float* src = &(*bands[static_cast<std::size_t>(b)])[(r.ny - 1 - j) * r.nx];
                std::copy(src, src + r.nx, row.begin());
                if (band->RasterIO(GF_Write, 0, static_cast<int>(j), static_cast<int>(r.nx), 1, row.data(),
                                   static_cast<int>(r.nx), 1, GDT_Float32, 0, 0) != CE_None)
                    throw Error("wave field: GDAL could not write the GeoTIFF");
            }
        }
    }
    vsi_l_offset size = 0;
    GByte* data = VSIGetMemFileBuffer(path.c_str(), &size, TRUE);
    std::string bytes(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size));
    CPLFree(data);
    return bytes;
}

}  // namespace wave
