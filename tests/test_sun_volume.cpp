// Sunlight in the water (libwave/underwater.h): flat water's beam at every depth, the
// floor's and the air's dark voxels, a sine crest's light gathering into its focal line
// at the depth the lens law gives, and the OpenVDB file read back.
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/physics.h"
#include "libwave/surface.h"
#include "libwave/underwater.h"

#include <gtest/gtest.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <sstream>
#include <vector>

namespace {

using namespace wave;


// A 2 × 2-node grid over [0, w] × [0, d] whose elevation rises linearly from z_left at
// x = 0 to z_right at x = w.
ElevationGrid floor_of(double w, double d, double z_left, double z_right) {
    return ElevationGrid{2, 2, 0.0, 0.0, w, d, {z_left, z_right, z_left, z_right}};
}

// z = z0 + a sin(k x) over [0, w] × [0, d], nx × ny vertices, exact unit normals.
struct Surface {
    std::vector<float> positions, normals;
    std::vector<std::uint32_t> triangles;
};
Surface sine_surface(double w, double d, std::size_t nx, std::size_t ny, double a, double k, double z0 = 0.0) {
    Surface s;
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
            const double x = w * double(i) / double(nx - 1), y = d * double(j) / double(ny - 1);
            const double slope = a * k * std::cos(k * x), len = std::hypot(slope, 1.0);
            s.positions.insert(s.positions.end(), {float(x), float(y), float(z0 + a * std::sin(k * x))});
            s.normals.insert(s.normals.end(), {float(-slope / len), 0.0f, float(1.0 / len)});
        }
    s.triangles = grid_triangles(nx, ny);
    return s;
}

std::vector<float> sunlight(const SunVolumePlan& plan, const Surface& s) {
    std::vector<float> light(plan.nx * plan.ny * plan.nz);
    evaluate_sun_volume(plan, plan_caustic_mesh(s.triangles, s.positions.size() / 3), s.positions, s.normals, light);
    return light;
}

double voxel_depth(const SunVolumePlan& plan, std::size_t k) { return -(plan.z0 + (double(k) + 0.5) * plan.dz); }

TEST(SunVolume, FlatWaterLightsEveryVoxelWithTheBeamAttenuatedToItsDepth) {
    const double h = 10.0, c = 0.12, elevation = 55.0 * std::numbers::pi / 180.0, azimuth = 30.0 * std::numbers::pi / 180.0;
    CausticOptions o;
    o.sun = {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
    o.attenuation = c;
    o.surface_irradiance = 2.5;
    SunVolumeOptions v;
    v.nx = 40, v.ny = 32, v.nz = 10;
    const SunVolumePlan plan = plan_sun_volume(plan_caustics(floor_of(100.0, 80.0, -h, -h), o), v);
    EXPECT_DOUBLE_EQ(plan.z0, -h);  // the beam is still bright at the floor: the volume reaches it
    EXPECT_DOUBLE_EQ(plan.dx, 2.5);
    const std::vector<float> light = sunlight(plan, sine_surface(100.0, 80.0, 51, 41, 0.0, 1.0));
    const double cos_i = std::sin(elevation), sin_t = std::sqrt(1.0 - cos_i * cos_i) / kWaterRefractiveIndex;
    const double cos_t = std::sqrt(1.0 - sin_t * sin_t);
    double worst = 0.0;
    for (std::size_t k = 0; k < v.nz; ++k) {
        const double expected = fresnel_transmissivity(cos_i) * 2.5 * std::exp(-c * voxel_depth(plan, k) / cos_t);
        for (std::size_t j = 0; j < v.ny; ++j)
            for (std::size_t i = 0; i < v.nx; ++i) worst = std::max(worst, std::abs(light[(k * v.ny + j) * v.nx + i] / expected - 1.0));
    }
    EXPECT_LT(worst, 0.01);  // flat water beyond lights the up-sun borders too
    // Murkier water: the volume ends where the beam has fallen to a thousandth.
    o.attenuation = 1.0;
    const SunVolumePlan murky = plan_sun_volume(plan_caustics(floor_of(100.0, 80.0, -h, -h), o), v);
    EXPECT_NEAR(murky.z0, -std::log(1000.0) * cos_t, 1e-9);
}

TEST(SunVolume, VoxelsUnderTheFloorOrAboveTheWaterAreDark) {
    CausticOptions o;
    o.flat_water_beyond = false;
    o.attenuation = 0.05;
    SunVolumeOptions v;
    v.nx = 50, v.ny = 4, v.nz = 20;
    // A floor rising from 10 m deep at x = 0 to 0 at x = 100 (the sun overhead), under
    // water lowered 3 m (a trough as wide as the box).
    const SunVolumePlan plan = plan_sun_volume(plan_caustics(floor_of(100.0, 10.0, -10.0, 0.0), o), v);
    const std::vector<float> light = sunlight(plan, sine_surface(100.0, 10.0, 101, 11, 0.0, 1.0, -3.0));
    std::size_t wet = 0, ground = 0, air = 0;
    for (std::size_t k = 0; k < v.nz; ++k)
        for (std::size_t i = 1; i + 1 < v.nx; ++i) {
            const double x = (double(i) + 0.5) * plan.dx, z = -voxel_depth(plan, k), value = light[(k * v.ny + 1) * v.nx + i];
            if (z < -10.0 + 0.1 * x) {
                EXPECT_EQ(value, 0.0f) << "under the floor at x " << x << ", z " << z;
                ++ground;
            } else if (z > -3.0) {
                EXPECT_EQ(value, 0.0f) << "above the water at x " << x << ", z " << z;
                ++air;
            } else {
                EXPECT_GT(value, 0.5f) << "in the water at x " << x << ", z " << z;
                ++wet;
            }
        }
    EXPECT_GT(wet, 100u);
    EXPECT_GT(ground, 100u);
    EXPECT_GT(air, 100u);
}

// The sine crest z = a sin(kx) focuses vertical light D = n / ((n − 1) a k²) below it
// (test_caustics.cpp derives it): the volume's brightest level lies there, a little
// deeper for the off-axis rays, and every level carries the same mean light.
TEST(SunVolume, ASineCrestGathersItsLightIntoALineAtItsFocalDepth) {
    const double a = 0.05, wavelength = 4.0, k = 2.0 * std::numbers::pi / wavelength;
    const double focus = kWaterRefractiveIndex / ((kWaterRefractiveIndex - 1.0) * a * k * k);
    CausticOptions o;
    o.attenuation = 0.0;
    SunVolumeOptions v;
    v.nx = 1600, v.ny = 4, v.nz = 50;  // 200 voxels a wavelength, levels 1 m apart
    const SunVolumePlan plan = plan_sun_volume(plan_caustics(floor_of(8.0 * wavelength, 1.0, -50.0, -50.0), o), v);
    ASSERT_DOUBLE_EQ(plan.dz, 1.0);
    const std::vector<float> light = sunlight(plan, sine_surface(8.0 * wavelength, 1.0, 3201, 3, a, k));
    double brightest = 0.0, where = 0.0, first_mean = 0.0;
    for (std::size_t level = 0; level < v.nz; ++level) {
        const auto row = light.begin() + static_cast<std::ptrdiff_t>((level * v.ny + 1) * v.nx + 400);
        const double peak = *std::max_element(row, row + 800), mean = std::accumulate(row, row + 800, 0.0) / 800.0;
        if (level == 0) first_mean = mean;
        EXPECT_NEAR(mean / first_mean, 1.0, 0.01) << "level " << level;
        if (peak / mean > brightest) brightest = peak / mean, where = voxel_depth(plan, level) + a;
    }
    EXPECT_GT(brightest, 20.0);
    RecordProperty("brightest_depth_over_focus", std::to_string(where / focus));
    EXPECT_GE(where / focus, 1.0) << "brightest " << where << " m below the crest, focus " << focus;
    EXPECT_LE(where / focus, 1.2);
}

TEST(SunVolume, ALevelIsTheCausticMapOfAFloorAtItsHeight) {
    const SunVolumeOptions v{64, 48, 8, 1e-3};
    CausticOptions o;
    o.sun = {0.3, -0.2, 0.9};
    const CausticPlan caustics = plan_caustics(floor_of(64.0, 48.0, -12.0, -4.0), o);
    const SunVolumePlan plan = plan_sun_volume(caustics, v);
    const Surface s = sine_surface(64.0, 48.0, 129, 97, 0.3, 2.0 * std::numbers::pi / 9.0);
    const std::vector<float> light = sunlight(plan, s);
    const std::size_t level = 5;
    CausticOptions at = o;
    at.width = v.nx, at.height = v.ny;
    const double z = plan.z0 + (double(level) + 0.5) * plan.dz;
    std::vector<float> map(v.nx * v.ny);
    evaluate_caustics(plan_caustics(floor_of(64.0, 48.0, z, z), at), s.positions, s.normals, s.triangles, map);
    std::size_t lit = 0;
    for (std::size_t j = 0; j < v.ny; ++j)
        for (std::size_t i = 0; i < v.nx; ++i) {
            const float voxel = light[(level * v.ny + j) * v.nx + i], pixel = map[(v.ny - 1 - j) * v.nx + i];
            const bool under_floor = z < -12.0 + 8.0 * (double(i) + 0.5) / double(v.nx);
            EXPECT_EQ(voxel, under_floor ? 0.0f : pixel) << i << ", " << j;
            lit += voxel > 0.0f;
        }
    EXPECT_GT(lit, v.nx * v.ny / 4);
}

TEST(SunVolume, TheVdbFileHoldsEachVoxelWhereItLies) {
    CausticOptions o;
    o.sun = {0.3, -0.2, 0.9};
    const SunVolumePlan plan = plan_sun_volume(plan_caustics(floor_of(60.0, 30.0, -12.0, -2.0), o), SunVolumeOptions{30, 15, 12, 1e-3});
    const std::vector<float> light = sunlight(plan, sine_surface(60.0, 30.0, 61, 31, 0.2, 2.0 * std::numbers::pi / 7.0));
    const std::string bytes = sun_volume_vdb(plan, light);
    EXPECT_EQ(bytes, sun_volume_vdb(plan, light));  // no random archive identifier
    openvdb::initialize();
    std::istringstream in(bytes);
    const openvdb::GridPtrVecPtr grids = openvdb::io::Stream(in).getGrids();
    ASSERT_EQ(grids->size(), 1u);
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "sunlight");
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_FOG_VOLUME);
    std::size_t active = 0;
    for (std::size_t k = 0; k < plan.nz; ++k)
        for (std::size_t j = 0; j < plan.ny; ++j)
            for (std::size_t i = 0; i < plan.nx; ++i) {
                const float expected = light[(k * plan.ny + j) * plan.nx + i];
                const openvdb::Vec3d centre{plan.x0 + (double(i) + 0.5) * plan.dx, plan.y0 + (double(j) + 0.5) * plan.dy,
                                            plan.z0 + (double(k) + 0.5) * plan.dz};
                const openvdb::Vec3d index = grid->transform().worldToIndex(centre);
                const openvdb::Coord c(int(std::lround(index.x())), int(std::lround(index.y())), int(std::lround(index.z())));
                ASSERT_NEAR((index - c.asVec3d()).length(), 0.0, 1e-9);
                EXPECT_NEAR(grid->tree().getValue(c), expected, 1e-3 * expected) << i << ", " << j << ", " << k;  // half floats
                EXPECT_EQ(grid->tree().isValueOn(c), expected > 0.0f);
                active += expected > 0.0f;
            }
    EXPECT_EQ(grid->activeVoxelCount(), active);
    EXPECT_GT(active, plan.nx * plan.ny * plan.nz / 4);
}

TEST(SunVolume, BadOptionsAndSizesAreRefused) {
    const CausticPlan caustics = plan_caustics(floor_of(10.0, 10.0, -5.0, -5.0), CausticOptions{});
    const auto refused = [&](SunVolumeOptions v, const std::string& words) {
        try {
            plan_sun_volume(caustics, v);
            ADD_FAILURE() << "accepted: " << words;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
    };
    refused({0, 8, 8, 1e-3}, "nx = 0 voxels");
    refused({8, 8, 5000, 1e-3}, "nz = 5000 voxels");
    refused({8, 8, 8, 1.5}, "darkest 1.5");
    EXPECT_THROW(plan_sun_volume(plan_caustics(floor_of(10.0, 10.0, 1.0, 2.0), CausticOptions{}), SunVolumeOptions{}), InputError);
    const SunVolumePlan plan = plan_sun_volume(caustics, SunVolumeOptions{8, 8, 4, 1e-3});
    std::vector<float> light(8 * 8 * 3);
    const Surface s = sine_surface(10.0, 10.0, 5, 5, 0.0, 1.0);
    EXPECT_THROW(evaluate_sun_volume(plan, plan_caustic_mesh(s.triangles, 25), s.positions, s.normals, light), InputError);
    EXPECT_THROW(sun_volume_vdb(plan, light), InputError);
}

}  // namespace
