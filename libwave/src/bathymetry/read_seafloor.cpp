// Chooses a reader by the file's extension.
#include "libwave/bathymetry.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace wave {

Seafloor read_seafloor(const std::string& path, const ReadOptions& options) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".bot") return read_swan_bot(path, options);
    if (ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl")
        return read_mesh_file(path, options);
    if (ext == ".json") return read_contour_file(path, options);
    return read_raster_gdal(path, options);
}

}  // namespace wave
