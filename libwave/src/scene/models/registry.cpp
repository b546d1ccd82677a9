// The wave models, one line each, in the order of SurfaceKind.
#include "../surface_model.h"

#include "libwave/errors.h"

#include <array>
#include <string>

namespace wave::detail {

extern const SurfaceModel kRayStripsModel, kHeightFieldModel, kOceanPatchModel, kWaveFieldModel;

namespace {
const std::array<const SurfaceModel*, 4> kModels{
    &kRayStripsModel,
    &kHeightFieldModel,
    &kOceanPatchModel,
    &kWaveFieldModel,
};
}  // namespace

std::span<const SurfaceModel* const> surface_models() { return kModels; }

const SurfaceModel& surface_model(SurfaceKind kind) {
    for (const SurfaceModel* m : kModels)
        if (m->kind == kind) return *m;
    throw InternalError("no model registered for surface kind " + std::to_string(static_cast<int>(kind)));
}

}  // namespace wave::detail

namespace wave {

std::string_view surface_kind_name(SurfaceKind kind) { return detail::surface_model(kind).name; }

Traced surface_kind_traces(SurfaceKind kind) { return detail::surface_model(kind).traced; }

}  // namespace wave
