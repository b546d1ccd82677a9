// Sunlight in the water: a caustic map per level of a voxel box (libwave/underwater.h,
// docs/underwater.md).
#include "libwave/underwater.h"

#include "core/format.h"
#include "libwave/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wave {

namespace {

constexpr std::size_t kMaxVolumeSide = 4096;

void check_options(const SunVolumeOptions& o) {
    for (const auto& [side, name] : {std::pair{o.nx, "nx"}, std::pair{o.ny, "ny"}, std::pair{o.nz, "nz"}})
        if (side == 0 || side > kMaxVolumeSide)
            throw InputError("sun volume: " + std::string(name) + " = " + std::to_string(side) + " voxels is not 1 … " +
                             std::to_string(kMaxVolumeSide));
    if (!(o.darkest > 0.0 && o.darkest < 1.0))
        throw InputError("sun volume: darkest " + detail::format_number(o.darkest) + " is not in (0, 1)");
}

// The depth below which flat water's beam has fallen under `darkest` of I₀ (infinite
// in water that does not dim light).
double darkest_depth(const CausticPlan& caustics, double darkest) noexcept {
    const CausticOptions& o = caustics.options;
    if (!(o.attenuation > 0.0)) return std::numeric_limits<double>::infinity();
    const double cos_t = -refracted_beam(caustics.sun, o.water_index)[2];  // the refracted beam's slant
    return std::log(1.0 / darkest) * cos_t / o.attenuation;
}

}  // namespace

std::array<double, 3> refracted_beam(const std::array<double, 3>& sun, double water_index) noexcept {
    // Snell with the normal (0, 0, 1): t = −η l + (η cos i − cos t) n, η = 1 / n.
    const double len = std::hypot(sun[0], sun[1], sun[2]), eta = 1.0 / water_index, cos_i = sun[2] / len;
    const double cos_t = std::sqrt(1.0 - eta * eta * (1.0 - cos_i * cos_i));
    return {-eta * sun[0] / len, -eta * sun[1] / len, -cos_t};
}

SunVolumePlan plan_sun_volume(const CausticPlan& caustics, const SunVolumeOptions& options) {
    check_options(options);
    const ElevationGrid& g = caustics.floor;
    const double depth = std::min(caustics.max_depth, darkest_depth(caustics, options.darkest));
    if (!(depth > 0.0)) throw InputError("sun volume: the seafloor is nowhere below the still water");
    SunVolumePlan plan;
    plan.nx = options.nx;
    plan.ny = options.ny;
    plan.nz = options.nz;
    plan.x0 = g.x0;
    plan.y0 = g.y0;
    plan.z0 = -depth;
    plan.dx = (g.x_max() - g.x0) / static_cast<double>(options.nx);
    plan.dy = (g.y_max() - g.y0) / static_cast<double>(options.ny);
    plan.dz = depth / static_cast<double>(options.nz);
    CausticOptions level_options = caustics.options;
    level_options.width = options.nx;
    level_options.height = options.ny;
    ElevationGrid level{2, 2, g.x0, g.y0, g.x_max() - g.x0, g.y_max() - g.y0, {}};
    plan.levels.reserve(options.nz);
    for (std::size_t k = 0; k < options.nz; ++k) {
        level.z.assign(4, plan.z0 + (static_cast<double>(k) + 0.5) * plan.dz);
        plan.levels.push_back(plan_caustics(level, level_options));
        plan.levels.back().level_in_water = true;
    }
    plan.first_wet.resize(options.nx * options.ny);
    for (std::size_t j = 0; j < options.ny; ++j)
        for (std::size_t i = 0; i < options.nx; ++i) {
            const double ground = -depth_at(g, plan.x0 + (static_cast<double>(i) + 0.5) * plan.dx,
                                            plan.y0 + (static_cast<double>(j) + 0.5) * plan.dy);
            // The first level whose centre lies above the ground.
            const double above = std::floor((ground - plan.z0) / plan.dz - 0.5) + 1.0;
            plan.first_wet[j * options.nx + i] = static_cast<std::uint32_t>(std::clamp(above, 0.0, static_cast<double>(options.nz)));
        }
    return plan;
}

void evaluate_sun_volume(const SunVolumePlan& plan, const CausticMesh& mesh, std::span<const float> positions,
                         std::span<const float> normals, std::span<float> light, CausticWorkspace* workspace) {
    const std::size_t nx = plan.nx, ny = plan.ny, columns = nx * ny;
    if (light.size() != columns * plan.nz)
        throw InputError("sun volume: " + std::to_string(light.size()) + " floats for " + std::to_string(nx) + " × " +
                         std::to_string(ny) + " × " + std::to_string(plan.nz) + " voxels");
    CausticWorkspace local;
    CausticWorkspace& w = workspace ? *workspace : local;
    w.level_map.resize(columns);
    for (std::size_t k = 0; k < plan.nz; ++k) {
        evaluate_caustics(plan.levels[k], mesh, positions, normals, w.level_map, &w);
        float* slice = &light[k * columns];
        for (std::size_t j = 0; j < ny; ++j) {
            const float* row = &w.level_map[(ny - 1 - j) * nx];  // the map's row 0 is the rectangle's top
            for (std::size_t i = 0; i < nx; ++i) slice[j * nx + i] = k < plan.first_wet[j * nx + i] ? 0.0f : row[i];
        }
    }
}

}  // namespace wave
