// Texture coordinates over the seafloor's rectangle (surface.h).
#include "libwave/errors.h"
#include "libwave/surface.h"

namespace wave {

void domain_texcoords(const ElevationGrid& grid, std::span<const double> x, std::span<const double> y,
                      std::span<float> texcoords) {
    if (x.size() != y.size() || texcoords.size() != 2 * x.size())
        throw InputError("domain_texcoords: expected as many x as y and 2 texcoords per point");
    const double width = grid.x_max() - grid.x0, height = grid.y_max() - grid.y0;
    for (std::size_t v = 0; v < x.size(); ++v) {
        texcoords[2 * v] = static_cast<float>((x[v] - grid.x0) / width);
        texcoords[2 * v + 1] = static_cast<float>(1.0 - (y[v] - grid.y0) / height);
    }
}

}  // namespace wave
