// Raster seafloors through GDAL: ESRI ASCII, GeoTIFF, NetCDF and every other raster
// format GDAL reads. Geographic (lon/lat) rasters are reprojected by GDAL's warper to
// a local metric frame; no hand-written format code here. GDAL's C API, loaded on the
// first read (gdal_library.h).
#include "gdal_library.h"
#include "grid_fill.h"
#include "libwave/bathymetry.h"
#include "libwave/errors.h"
#include "libwave/io.h"
#include "core/files.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <utility>
#include <numbers>
#include <string_view>
#include <string>
#include <vector>

namespace wave {
namespace {

using detail::GdalLibrary;

// Silences GDAL's stderr output for the scope; the last message goes into our errors.
class QuietGdalErrors {
public:
    explicit QuietGdalErrors(const GdalLibrary& g) : g_(g) {
        g_.CPLPushErrorHandler(g_.CPLQuietErrorHandler);
        g_.CPLErrorReset();
    }
    ~QuietGdalErrors() { g_.CPLPopErrorHandler(); }
    QuietGdalErrors(const QuietGdalErrors&) = delete;
    QuietGdalErrors& operator=(const QuietGdalErrors&) = delete;
    std::string last() const {
        const char* m = g_.CPLGetLastErrorMsg();
        return (m && *m) ? std::string(m) : std::string("no further detail from GDAL");
    }

private:
    const GdalLibrary& g_;
};

using Dataset = detail::GdalOwned<GDALDatasetH, decltype(&GDALClose)>;
using SpatialRef = detail::GdalOwned<OGRSpatialReferenceH, decltype(&OSRDestroySpatialReference)>;
Dataset adopt(const GdalLibrary& g, GDALDatasetH h) { return Dataset(h, g.GDALClose); }
SpatialRef new_srs(const GdalLibrary& g, OGRSpatialReferenceH h) { return SpatialRef(h, g.OSRDestroySpatialReference); }

// A string GDAL allocated, copied and freed.
std::string take_string(const GdalLibrary& g, char* s) {
    std::string out = s ? s : "";
    g.VSIFree(s);
    return out;
}

// GDAL's ESRI ASCII reader turns a token it cannot read ("abc", "nan") into 0 or −0
// without a word, which raised crests from 0.32 m to 1.99 m: every value token must be
// a whole finite number (or the header's NODATA text) before GDAL reads the values.
void check_ascii_grid_tokens(const std::string& path, std::size_t nx, std::size_t ny) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return;  // GDAL read it; a later RasterIO reports what is wrong
    static const std::vector<std::string> keys = {"ncols", "nrows", "xllcorner", "yllcorner", "xllcenter", "yllcenter",
                                                  "cellsize", "dx", "dy", "nodata_value"};
    const auto lower = [](std::string s) {
        for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return s;
    };
    std::string token, nodata_text;
    std::size_t n = 0;
    bool header = true;
    while (in >> token) {
        if (header && std::find(keys.begin(), keys.end(), lower(token)) != keys.end()) {
            const std::string key = lower(token);
            if (!(in >> token)) break;
            if (key == "nodata_value") nodata_text = token;
            continue;
        }
        header = false;
        if (n >= nx * ny) return;  // trailing text: GDAL's business
        const std::size_t row = n / nx + 1, column = n % nx + 1;
        ++n;
        if (token == nodata_text) continue;
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(token.c_str(), &end);
        const std::string where = path + ": row " + std::to_string(row) + ", column " + std::to_string(column) + " holds '" +
                                  (token.size() > 24 ? token.substr(0, 24) + "…" : token) + "'";
        if (end != token.c_str() + token.size() || !std::isfinite(v) || errno == ERANGE)
            throw InputError(where + ", not a finite number; mark missing values with the NODATA_value");
        if (std::abs(v) > std::numeric_limits<float>::max())  // GDAL would store the float's largest value
            throw InputError(where + ", beyond the 32-bit floats GDAL reads ESRI grids as; mark missing values with the NODATA_value");
    }
}

Dataset open_raster(const GdalLibrary& g, const QuietGdalErrors& quiet, const std::string& name, const std::string& path) {
    GDALDatasetH h = g.GDALOpenEx(name.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
    if (!h) throw InputError(path + ": GDAL cannot read it as a raster grid (" + quiet.last() + ")");
    return adopt(g, h);
}

// NetCDF and HDF files hold several variables as subdatasets: take the elevation
// variable ("z", "elevation", "Band1", "depth") or else the first one.
Dataset open_first_grid(const GdalLibrary& g, const QuietGdalErrors& quiet, Dataset ds, const std::string& path) {
    if (g.GDALGetRasterCount(ds.get()) > 0) return ds;
    char** sub = g.GDALGetMetadata(ds.get(), "SUBDATASETS");
    std::vector<std::string> names;
    for (int n = 0; sub && sub[n]; ++n) {
        const std::string entry = sub[n];
        const auto eq = entry.find('=');
        if (entry.find("_NAME=") != std::string::npos) names.push_back(entry.substr(eq + 1));
    }
    if (names.empty()) throw InputError(path + ": the file holds no raster band");
    std::string pick = names.front();
    const auto ends_with = [](const std::string& s, std::string_view tail) {
        return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
    };
    for (std::string_view var : {":z", ":elevation", ":Band1", ":depth"}) {
        const auto hit = std::find_if(names.begin(), names.end(),
                                      [&](const std::string& n) { return ends_with(n, var); });
        if (hit != names.end()) {
            pick = *hit;
            break;
        }
    }
    return open_raster(g, quiet, pick, path);
}

// A local azimuthal equidistant frame centred on the raster, and the largest
// axis-aligned rectangle of it that lies inside the raster's lon/lat box (so that
// the reprojected grid has no cells outside the data).
struct LocalFrame {
    std::string wkt;
    std::string source_wkt;
    double x_min, y_min, x_max, y_max, spacing;
    double lon0, lat0;
};

LocalFrame local_frame_for(const GdalLibrary& g, const QuietGdalErrors& quiet, GDALDatasetH ds,
                           OGRSpatialReferenceH geographic, const std::string& path) {
    double gt[6];
    g.GDALGetGeoTransform(ds, gt);
    const double w = g.GDALGetRasterXSize(ds), h = g.GDALGetRasterYSize(ds);
    const double lon_a = gt[0], lon_b = gt[0] + w * gt[1];
    const double lat_a = gt[3], lat_b = gt[3] + h * gt[5];
    LocalFrame f{};
    f.lon0 = 0.5 * (lon_a + lon_b);
    f.lat0 = 0.5 * (lat_a + lat_b);

    const SpatialRef src = new_srs(g, g.OSRClone(geographic));
    g.OSRSetAxisMappingStrategy(src.get(), OAMS_TRADITIONAL_GIS_ORDER);
    const SpatialRef dst = new_srs(g, g.OSRNewSpatialReference(nullptr));
    g.OSRCopyGeogCSFrom(dst.get(), src.get());
    g.OSRSetAE(dst.get(), f.lat0, f.lon0, 0.0, 0.0);
    g.OSRSetAxisMappingStrategy(dst.get(), OAMS_TRADITIONAL_GIS_ORDER);
    const detail::GdalOwned<OGRCoordinateTransformationH, decltype(&OCTDestroyCoordinateTransformation)> ct(
        g.OCTNewCoordinateTransformation(src.get(), dst.get()), g.OCTDestroyCoordinateTransformation);
    if (!ct.get()) throw InputError(path + ": cannot build a local metric frame (" + quiet.last() + ")");

    const double west = std::min(lon_a, lon_b), east = std::max(lon_a, lon_b);
    const double south = std::min(lat_a, lat_b), north = std::max(lat_a, lat_b);
    constexpr int kSamples = 64;
    double x_west = -HUGE_VAL, x_east = HUGE_VAL, y_south = -HUGE_VAL, y_north = HUGE_VAL;
    for (int n = 0; n <= kSamples; ++n) {
        const double s = static_cast<double>(n) / kSamples;
        double lx[4] = {west, east, west + s * (east - west), west + s * (east - west)};
        double ly[4] = {south + s * (north - south), south + s * (north - south), south, north};
        if (!g.OCTTransform(ct.get(), 4, lx, ly, nullptr))
            throw InputError(path + ": GDAL could not project the raster's edges");
        x_west = std::max(x_west, lx[0]);
        x_east = std::min(x_east, lx[1]);
        y_south = std::max(y_south, ly[2]);
        y_north = std::min(y_north, ly[3]);
    }
    f.x_min = x_west;
    f.x_max = x_east;
    f.y_min = y_south;
    f.y_max = y_north;
    // Keep the finer of the two source spacings, measured at the centre.
    const double deg = 6371008.8 * std::numbers::pi / 180.0;
    f.spacing = std::min(std::abs(gt[1]) * deg * std::cos(f.lat0 * std::numbers::pi / 180.0),
                         std::abs(gt[5]) * deg);
    char* wkt = nullptr;
    g.OSRExportToWkt(dst.get(), &wkt);
    f.wkt = take_string(g, wkt);
    wkt = nullptr;
    g.OSRExportToWkt(src.get(), &wkt);
    f.source_wkt = take_string(g, wkt);
    return f;
}

Dataset reproject_to_local(const GdalLibrary& g, const QuietGdalErrors& quiet, GDALDatasetH ds, const LocalFrame& f,
                           const std::string& path) {
    const std::string te[4] = {detail::format_number(f.x_min), detail::format_number(f.y_min),
                               detail::format_number(f.x_max), detail::format_number(f.y_max)};
    const std::string tr = detail::format_number(f.spacing);
    std::vector<std::string> words = {"-of", "MEM", "-r", "cubic", "-ot", "Float64", "-s_srs", f.source_wkt,
                                      "-t_srs", f.wkt, "-te", te[0], te[1], te[2], te[3], "-tr", tr, tr};
    char** args = nullptr;
    for (const std::string& w : words) args = g.CSLAddString(args, w.c_str());
    GDALWarpAppOptions* opts = g.GDALWarpAppOptionsNew(args, nullptr);
    g.CSLDestroy(args);
    GDALDatasetH src = ds;
    int usage_error = 0;
    GDALDatasetH out = g.GDALWarp("", nullptr, 1, &src, opts, &usage_error);
    g.GDALWarpAppOptionsFree(opts);
    if (!out) throw InputError(path + ": GDAL could not reproject the grid (" + quiet.last() + ")");
    return adopt(g, out);
}

// CF / COARDS files (GMT, many NetCDF grids) carry no CRS but say "degrees_east" in
// the units of their x variable: such grids are lon/lat on WGS84.
bool says_degrees_east(const GdalLibrary& g, GDALDatasetH ds) {
    char** md = g.GDALGetMetadata(ds, nullptr);
    for (int n = 0; md && md[n]; ++n) {
        const std::string entry = md[n];
        const auto eq = entry.find('=');
        if (eq == std::string::npos || eq < 6 || entry.compare(eq - 6, 6, "#units") != 0) continue;
        const std::string value = entry.substr(eq + 1);
        if (value.rfind("degrees_east", 0) == 0 || value.rfind("degree_east", 0) == 0) return true;
    }
    return false;
}

}  // namespace

Seafloor read_raster_gdal(const std::string& path, const ReadOptions& options) {
    // A folder may be a raster (an ArcInfo binary grid); a FIFO or a device is not, and
    // GDAL's open would block on it.
    std::error_code ec;
    if (!std::filesystem::is_directory(path, ec)) require_input_file(path);
    const GdalLibrary& g = detail::gdal(path);
    const QuietGdalErrors quiet(g);
    Dataset ds = open_first_grid(g, quiet, open_raster(g, quiet, path, path), path);

    Seafloor out;
    out.source = path;
    out.frame = "local metres (the file's own x/y)";
    double gt[6] = {0.0, 1.0, 0.0, 0.0, 0.0, -1.0};
    const bool georeferenced = g.GDALGetGeoTransform(ds.get(), gt) == CE_None;
    if (!georeferenced) out.frame = "pixel units as metres (the file has no georeferencing)";
    if (gt[2] != 0.0 || gt[4] != 0.0)
        throw InputError(path + ": rotated or sheared rasters are not supported; warp it to a "
                                "north-up grid first (gdalwarp)");

    OGRSpatialReferenceH srs = g.GDALGetSpatialRef(ds.get());  // the dataset's own
    const SpatialRef wgs84 = new_srs(g, g.OSRNewSpatialReference(nullptr));
    g.OSRSetWellKnownGeogCS(wgs84.get(), "WGS84");
    const bool cf_degrees = !srs && georeferenced && says_degrees_east(g, ds.get());
    if ((srs && g.OSRIsGeographic(srs)) || cf_degrees) {
        const LocalFrame f = local_frame_for(g, quiet, ds.get(), cf_degrees ? wgs84.get() : srs, path);
        ds = reproject_to_local(g, quiet, ds.get(), f, path);
        g.GDALGetGeoTransform(ds.get(), gt);
        out.frame = "azimuthal equidistant about lon " + detail::format_number(f.lon0) +
                    ", lat " + detail::format_number(f.lat0) +
                    " (metres; reprojected from geographic lon/lat" +
                    (cf_degrees ? " (CF units degrees_east, WGS84 assumed)" : "") +
                    " by GDAL, cubic)";
    } else if (srs && g.OSRIsProjected(srs)) {
        const char* name = g.OSRGetName(srs);
        out.frame = std::string("projected CRS '") + (name ? name : "?") + "' (metres)";
    }

    const std::size_t nx = static_cast<std::size_t>(g.GDALGetRasterXSize(ds.get()));
    const std::size_t ny = static_cast<std::size_t>(g.GDALGetRasterYSize(ds.get()));
    detail::check_grid_size(path, nx, ny, options);

    GDALRasterBandH band = g.GDALGetRasterBand(ds.get(), 1);
    GDALDriverH driver = g.GDALGetDatasetDriver(ds.get());
    const char* driver_name = driver ? g.GDALGetDriverShortName(driver) : nullptr;
    if (driver_name && std::string_view(driver_name) == "AAIGrid") check_ascii_grid_tokens(path, nx, ny);
    std::vector<double> rows(nx * ny);
    if (g.GDALRasterIO(band, GF_Read, 0, 0, static_cast<int>(nx), static_cast<int>(ny), rows.data(), static_cast<int>(nx),
                       static_cast<int>(ny), GDT_Float64, 0, 0) != CE_None)
        throw InputError(path + ": reading the grid values failed, the file may be truncated (" + quiet.last() + ")");

    // GDAL rows run north to south when dy < 0: flip to j = 0 south.
    const bool north_first = gt[5] < 0.0;
    std::vector<double> values(nx * ny);
    for (std::size_t r = 0; r < ny; ++r) {
        const std::size_t j = north_first ? ny - 1 - r : r;
        std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(r * nx), nx,
                    values.begin() + static_cast<std::ptrdiff_t>(j * nx));
    }
    std::optional<double> nodata = options.nodata_value;
    int has_nodata = 0;
    const double file_nodata = g.GDALGetRasterNoDataValue(band, &has_nodata);
    if (!nodata && has_nodata) nodata = file_nodata;
    const auto where = [&](std::size_t i, std::size_t j) {
        const std::size_t r = north_first ? ny - 1 - j : j;
        return "row " + std::to_string(r + 1) + ", column " + std::to_string(i + 1);
    };
    out.nodata_count = detail::convert_to_elevation(values, nodata, {}, ValueSign::elevation,
                                                    options, path, where, nx);

    ElevationGrid& grid = out.grid;
    const double hs = options.horizontal_scale;
    grid.nx = nx;
    grid.ny = ny;
    grid.dx = std::abs(gt[1]) * hs;
    grid.dy = std::abs(gt[5]) * hs;
    // Node-registered: GDAL's geotransform addresses cell corners, nodes are centres.
    grid.x0 = (gt[0] + 0.5 * gt[1]) * hs;
    grid.y0 = (north_first ? gt[3] + (static_cast<double>(ny) - 0.5) * gt[5] : gt[3] + 0.5 * gt[5]) * hs;
    grid.z = std::move(values);
    return out;
}

}  // namespace wave
