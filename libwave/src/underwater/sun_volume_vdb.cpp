// A frame's sunlight as an OpenVDB file (libwave/underwater.h). OpenVDB stays in this
// file: no public header names it.
#include "libwave/errors.h"
#include "libwave/underwater.h"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <cstdint>
#include <cstdio>
#include <mutex>
#include <sstream>

namespace wave {

namespace {

// An archive's header: the magic number, the file format's and library's versions, a
// byte saying whether grids carry offsets, then a random 36-character UUID. Identical
// frames must give identical files, so the UUID is replaced by one made of the
// content's FNV-1a hash (still one per content, which is what readers key caches on).
constexpr std::size_t kUuidOffset = 8 + 4 + 4 + 4 + 1, kUuidLength = 36;

void derive_uuid(std::string& bytes) {
    if (bytes.size() < kUuidOffset + kUuidLength || bytes[kUuidOffset + 8] != '-' || bytes[kUuidOffset + 13] != '-')
        throw RuntimeError("sun volume: OpenVDB wrote an archive header of an unknown layout");
    std::uint64_t hash = 1469598103934665603ull;
    for (std::size_t i = kUuidOffset + kUuidLength; i < bytes.size(); ++i)
        hash = (hash ^ static_cast<unsigned char>(bytes[i])) * 1099511628211ull;
    char uuid[kUuidLength + 1];
    const auto part = [&](int shift, int digits) { return static_cast<unsigned long long>((hash >> shift) & ((1ull << (4 * digits)) - 1)); };
    std::snprintf(uuid, sizeof uuid, "%08llx-%04llx-%04llx-%04llx-%012llx", part(32, 8), part(16, 4), part(0, 4), part(48, 4),
                  (hash * 0x9e3779b97f4a7c15ull) >> 16);
    bytes.replace(kUuidOffset, kUuidLength, uuid, kUuidLength);
}

}  // namespace

std::string sun_volume_vdb(const SunVolumePlan& plan, std::span<const float> light) {
    const std::size_t nx = plan.nx, ny = plan.ny, nz = plan.nz;
    if (light.size() != nx * ny * nz || light.empty())
        throw InputError("sun volume: " + std::to_string(light.size()) + " floats for " + std::to_string(nx) + " × " +
                         std::to_string(ny) + " × " + std::to_string(nz) + " voxels");
    static std::once_flag initialised;
    std::call_once(initialised, [] { openvdb::initialize(); });
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("sunlight");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setSaveFloatAsHalf(true);
    openvdb::math::Mat4d frame = openvdb::math::Mat4d::identity();
    frame.setToScale(openvdb::Vec3d(plan.dx, plan.dy, plan.dz));
    frame.setTranslation(openvdb::Vec3d(plan.x0 + 0.5 * plan.dx, plan.y0 + 0.5 * plan.dy, plan.z0 + 0.5 * plan.dz));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(frame));
    openvdb::FloatGrid::Accessor voxels = grid->getAccessor();
    for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t j = 0; j < ny; ++j)
            for (std::size_t i = 0; i < nx; ++i)
                if (const float v = light[(k * ny + j) * nx + i]; v > 0.0f)
                    voxels.setValue(openvdb::Coord(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)), v);
    std::ostringstream out(std::ios_base::binary);
    openvdb::io::Stream(out).write(openvdb::GridCPtrVec{grid});
    std::string bytes = std::move(out).str();
    derive_uuid(bytes);
    return bytes;
}

}  // namespace wave
