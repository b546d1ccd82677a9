// Tessendorf's open ocean: a tileable FFT patch, no seafloor and no traced swell; its
// surface is the FFT's own lattice and its normals the FFT's exact ones.
#include "../surface_model.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace wave::detail {
namespace {

void read_before(const Node& root, Scene& s) {
    // The open-ocean patch: no seafloor to trace over, no swell to trace.
    for (const char* key : {"seafloor", "isobaths", "waves", "trace", "fronts", "motion"})
        if (root.has(key))
            root[key].fail("not for the open-ocean patch (/surface/kind \"ocean\"): it has no seafloor and no traced "
                           "swell; superpose /gerstner waves, or use a coastal surface with /ocean");
    refuse_height_field_options(root, "ocean\" (set /ocean instead)");
    refuse_ray_strip_keys(root);
    if (root.has("surface") && root["surface"].value().is_object() && root["surface"].has("far_field"))
        root["surface"]["far_field"].fail("not for the open-ocean patch: a skirt of its own carries it to the horizon");
    s.far_field.reset();
    s.ocean = OceanOptions{};
    s.ocean->repeat_time = 20.0;  // Tessendorf's figure 5
}

Seafloor flat_bottom(const Scene& scene) {
    const OceanOptions o = scene.ocean.value_or(OceanOptions{});
    const double depth = std::isinf(o.spectrum.depth) ? 1e4 : o.spectrum.depth;
    Seafloor sea;
    sea.grid.nx = sea.grid.ny = 2;
    sea.grid.dx = sea.grid.dy = o.size;
    sea.grid.z.assign(4, -depth);
    sea.source = "open ocean: flat bottom " + fmt(depth) + " m under a " + fmt(o.size) + " m patch";
    sea.frame = "local metres";
    return sea;
}

void plan(const Scene& scene, ScenePlan& p, PlanStages stages) {
    if (stages == PlanStages::trace) return;  // nothing to trace
    OceanOptions o = scene.ocean.value_or(OceanOptions{});
    if (o.repeat_time == 0.0) o.repeat_time = 20.0;
    plan_wind_sea(o, p);
    p.loop_period = o.repeat_time;
    // The patch's (N+1)² vertices: the lattice and a repeat of its first row and column.
    const std::size_t side = p.ocean.n + 1;
    p.patch_triangles = grid_triangles(side, side);
    p.rest_x.reserve(side * side);
    p.rest_y.reserve(side * side);
    for (std::size_t row = 0; row < side; ++row)
        for (std::size_t col = 0; col < side; ++col) {
            p.rest_x.push_back(p.ocean.spacing() * static_cast<double>(col));
            p.rest_y.push_back(p.ocean.spacing() * static_cast<double>(row));
        }
}

bool move(const Scene&, const ScenePlan& p, double t, ModelState*, ModelFrame& frame) {
    const OceanFields fields = evaluate_ocean(p.ocean, t, *frame.wind_sea.workspace);
    if (!frame.fresnel) {  // exact normals; a far skirt's vertices follow (the pipeline's wind sea)
        const std::size_t side = p.ocean.n + 1;
        const std::span<float> j_minus(frame.wind_sea.vertex_j);
        ocean_patch_frame(p.ocean, fields, frame.positions, frame.normals, j_minus.empty() ? j_minus : j_minus.first(side * side));
        return true;
    }
    // Blocks of rows: each block's Fresnel weights while its positions and normals are
    // in cache (a second pass read 24 MB back at 1024²). The same bits as apart.
    const std::size_t side = p.ocean.n + 1, block = 8;
    tbb::parallel_for(std::size_t{0}, (side + block - 1) / block, [&](std::size_t b) {
        const std::size_t first = b * block, rows = std::min(block, side - first);
        const std::size_t v = first * side, count = rows * side;
        const auto pos = frame.positions.subspan(3 * v, 3 * count), nr = frame.normals.subspan(3 * v, 3 * count);
        ocean_patch_rows(p.ocean, fields, first, rows, pos, nr, std::span<float>(frame.wind_sea.vertex_j).subspan(v, count));
        fresnel_weights(pos, nr, *frame.fresnel, frame.reflect.subspan(v, count), frame.refract.subspan(v, count));
    });
    frame.weights_done = true;
    return true;
}

}  // namespace

extern const SurfaceModel kOceanPatchModel{
    .kind = SurfaceKind::ocean,
    .name = "ocean",
    .traced = Traced::nothing,
    .loop_keys = "/ocean/repeat_time",
    .size_keys = "lower /ocean/resolution, /ocean/repeat_time or /animation/fps",
    .untangle = false,
    .overturns = nullptr,
    .far_field_harmonics = 0,
    .read_before = read_before,
    .read_after = [](const Node&, Scene&) {},
    .seafloor = flat_bottom,
    .plan = plan,
    .triangles = [](const ScenePlan& p) -> const std::vector<std::uint32_t>& { return p.patch_triangles; },
    .start = [](const Scene&, const ScenePlan&, bool) { return std::unique_ptr<ModelState>(); },
    .move = move,
    .foam = nullptr,  // its foam is the fold foam every wind sea carries
    .lips = nullptr,
    .draws_overturned = nullptr,
    .skirt_size = nullptr,
    .plan_skirt = nullptr,
    .foam_of_time_alone = false,
    .wind_sea_patch = true,
    .holds_boundary = nullptr,
    .whitewater = nullptr,  // its whitewater is the wind sea's folds
    .whitewater_source = {},
    .long_shot_keys = "/ocean/repeat_time",
};

}  // namespace wave::detail
