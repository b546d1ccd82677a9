// The wave models, one line each, in the order of SurfaceKind.
#include "../surface_model.h"

#include "libwave/errors.h"

#include <array>
#include <string>
#include <vector>

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

std::vector<std::string> whitewater_sources(const Scene& scene) {
    std::vector<std::string> sources;
    if (!scene.whitewater) return sources;
    const detail::SurfaceModel& m = detail::surface_model(scene.surface_kind);
    if (m.whitewater) sources.emplace_back(m.whitewater_source ? m.whitewater_source(scene) : m.name);
    if (scene.ocean) sources.emplace_back("wind sea folds");
    return sources;
}

std::string loop_lengthening_keys(const Scene& scene) {
    const detail::SurfaceModel& m = detail::surface_model(scene.surface_kind);
    if (scene.ocean && !m.wind_sea_patch) return "/ocean/repeat_time (a whole multiple of the swell's loop)";
    return std::string(m.long_shot_keys);
}

}  // namespace wave
