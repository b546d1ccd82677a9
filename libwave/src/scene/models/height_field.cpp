// Ts'o and Barsky's height field: rays traced through exact isobath crossings, their
// wave trains summed on a Beta2-spline control grid (any number of trains).
#include "../surface_model.h"

#include "libwave/physics.h"

#include <algorithm>
#include <limits>
#include <numbers>

namespace wave::detail {
namespace {

void read_before(const Node& root, Scene&) {
    if (root.has("fronts")) root["fronts"].fail("only for the ray-strips surface");
    if (root.has("motion")) root["motion"].fail("only for the ray-strips surface (the height field moves as Ts'o's sinusoids)");
    refuse_ray_strip_keys(root);
}

// The grid's cell against the rays' spacing and the trains' wavelengths (Ts'o §3.2.3).
void check_grid(const Scene& scene, const TraceOptions& trace, ScenePlan& p) {
    const ElevationGrid& g = p.seafloor.grid;
    if (scene.surface.nx < 2 || scene.surface.ny < 2) return;
    const double cell = std::min((g.x_max() - g.x0) / static_cast<double>(scene.surface.nx - 1),
                                 (g.y_max() - g.y0) / static_cast<double>(scene.surface.ny - 1));
    if (scene.surface.footprint == Footprint::bresenham && trace.ray_spacing > cell)
        throw InputError("scene: the Bresenham footprint needs at least one orthogonal per grid line (Ts'o): "
                         "ray spacing " + fmt(trace.ray_spacing) + " m exceeds the grid cell " +
                         fmt(cell) + " m; lower /trace/ray_spacing, raise "
                         "/trace/orthogonals_per_grid_line, or use the smooth footprint");
    for (std::size_t n = 0; n < scene.waves.size(); ++n) {
        const double shortest = linear_wave(2.0 * std::numbers::pi / scene.waves[n].period,
                                            std::max(0.05, seafloor_stats(p.seafloor).depth_max)).wavelength;
        if (2.0 * cell > shortest)
            p.warnings.push_back("wave train " + std::to_string(n) + " (T = " + fmt(scene.waves[n].period) +
                                 " s, L <= " + fmt(shortest) + " m) is shorter than two surface cells (" +
                                 fmt(cell) + " m): it aliases on this grid");
    }
}

// A train of which fewer than two rays entered the water moves nothing (an empty
// animation, "heights 0 .. 0 m", used to follow): say why, naming its keys.
void refuse_dry_trains(const Scene& scene, const ScenePlan& p, const TraceOptions& trace) {
    std::vector<std::size_t> rays(scene.waves.size(), 0);
    for (std::size_t r = 0; r < p.rays.ray_count(); ++r)
        if (p.rays.train[r] < rays.size() && p.rays.offsets[r + 1] > p.rays.offsets[r]) ++rays[p.rays.train[r]];
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (rays[i] >= 2) continue;
        const WaveTrain& w = scene.waves[i];
        const std::string where = "scene: no ray enters the water over " + p.seafloor.source + " from /waves/" + std::to_string(i) +
                                  " (" + std::to_string(rays[i]) + " ray(s)): ";
        const SeafloorStats st = seafloor_stats(p.seafloor);
        const double len = std::hypot(w.direction_x, w.direction_y);
        const double across = (std::abs(w.direction_y) * (st.x_max - st.x_min) + std::abs(w.direction_x) * (st.y_max - st.y_min)) / len;
        if (across / trace.ray_spacing < 2.0)
            throw InputError(where + "/trace/ray_spacing " + fmt(trace.ray_spacing) + " m leaves fewer than two rays across the " +
                             fmt(across) + " m the swell enters over; lower /trace/ray_spacing");
        throw InputError(where + "the swell travels towards [" + fmt(w.direction_x) + ", " + fmt(w.direction_y) + "] (/waves/" +
                         std::to_string(i) + "/direction), so its rays start on the seafloor's upwave side, and that side is land; "
                         "a direction points where the waves go, from the open sea towards the shore");
    }
}

void plan(const Scene& scene, ScenePlan& p, PlanStages stages) {
    const TraceOptions trace = scene_trace_options(scene, p.seafloor);
    check_grid(scene, trace, p);
    p.isobaths = extract_isobaths(p.seafloor, scene.isobaths);
    p.rays = trace_rays(p.seafloor, p.isobaths, scene.waves, trace);
    refuse_dry_trains(scene, p, trace);
    if (scene.amplitudes_from_field) {  // rays keep direction and phase; the fields give the heights
        FieldOptions share = scene.field;  // every train's grid is held: the memory limit is shared
        share.max_bytes /= static_cast<double>(scene.waves.size());
        for (const WaveTrain& w : scene.waves) p.wave_fields.push_back(solve_wave_field(p.seafloor, w, share));
        take_field_amplitudes(p.wave_fields, p.rays);
    }
    if (stages == PlanStages::trace) return;
    p.surface = plan_height_field(p.seafloor, p.rays, scene.waves, scene.surface);
    p.loop_period = p.surface.loop_period;
    // The evaluated vertices span the seafloor's rectangle evenly.
    const ElevationGrid& g = p.seafloor.grid;
    const HeightFieldPlan& sp = p.surface;
    for (std::size_t v = 0; v < sp.vertex_count(); ++v) {
        const std::size_t row = v / sp.vertex_nx, col = v % sp.vertex_nx;
        p.rest_x.push_back(g.x0 + (g.x_max() - g.x0) * static_cast<double>(col) / static_cast<double>(sp.vertex_nx - 1));
        p.rest_y.push_back(g.y0 + (g.y_max() - g.y0) * static_cast<double>(row) / static_cast<double>(sp.vertex_ny - 1));
    }
}

struct State : ModelState {
    std::vector<float> heights;                // the control nodes' heights of a frame
    std::vector<float> node_depth, node_foam;  // foam is computed at the control nodes
    // Per vertex: the highest the water may stand, a twentieth of the highest train's
    // amplitude below the land where the vertex lies on land (depth_at ≤ 0); +∞ over
    // water. The spline's heights spill past the wet control nodes, and over a flat beach
    // at the waterline the water stood level with the sand: Cycles drew wedges of either
    // (dark slashes across Ts'o and Barsky's beach from the default camera).
    std::vector<float> ceiling;
};

// Land elevations less the margin at the vertices over land (see State::ceiling).
std::vector<float> water_ceiling(const Scene& scene, const ScenePlan& p) {
    double highest = 0.0;
    for (const WaveTrain& w : scene.waves) highest = std::max(highest, w.amplitude);
    const double margin = 0.05 * highest;
    std::vector<float> out(p.surface.vertex_count());
    for (std::size_t v = 0; v < out.size(); ++v) {
        const double depth = depth_at(p.seafloor.grid, p.rest_x[v], p.rest_y[v]);
        out[v] = depth > 0.0 ? std::numeric_limits<float>::infinity() : static_cast<float>(-depth - margin);
    }
    return out;
}

std::unique_ptr<ModelState> start(const Scene& scene, const ScenePlan& p, bool shaded) {
    auto s = std::make_unique<State>();
    const HeightFieldPlan& sp = p.surface;
    s->heights.resize(sp.control_count());
    s->ceiling = water_ceiling(scene, p);
    if (shaded) {
        const ElevationGrid& g = p.seafloor.grid;
        s->node_depth.resize(sp.control_count());
        s->node_foam.resize(sp.control_count());
        for (std::size_t j = 0; j < sp.ny; ++j)
            for (std::size_t i = 0; i < sp.nx; ++i)
                s->node_depth[j * sp.nx + i] = static_cast<float>(std::max(
                    0.0, depth_at(g, sp.x0 + static_cast<double>(i) * sp.dx, sp.y0 + static_cast<double>(j) * sp.dy)));
    }
    return s;
}

bool move(const Scene&, const ScenePlan& p, double t, ModelState* state, ModelFrame& frame) {
    State& s = *static_cast<State*>(state);
    evaluate_height_field(p.surface, t, s.heights, frame.positions);
    for (std::size_t v = 0; v < s.ceiling.size(); ++v) frame.positions[3 * v + 2] = std::min(frame.positions[3 * v + 2], s.ceiling[v]);
    return false;
}

void foam(const Scene& scene, const ScenePlan& p, double t, ModelState* state, std::span<float> out) {
    State& s = *static_cast<State*>(state);
    height_field_foam(p.surface, s.node_depth, t, scene.foam, s.node_foam, out);
}

}  // namespace

extern const SurfaceModel kHeightFieldModel{
    .kind = SurfaceKind::height_field,
    .name = "height-field",
    .traced = Traced::rays,
    .loop_keys = "/surface/repeat_time or the periods in /waves",
    .size_keys = "lower /surface/samples_per_span, /surface/grid or /animation/fps",
    .untangle = false,
    .overturns = nullptr,
    .far_field_harmonics = 1,
    .read_before = read_before,
    .read_after = [](const Node&, Scene&) {},
    .seafloor = [](const Scene& s) { return load_seafloor(s.seafloor); },
    .plan = plan,
    .triangles = [](const ScenePlan& p) -> const std::vector<std::uint32_t>& { return p.surface.triangles; },
    .start = start,
    .move = move,
    .foam = foam,
    .lips = nullptr,
    .draws_overturned = nullptr,
    .skirt_size = nullptr,
    .plan_skirt = nullptr,
    .foam_of_time_alone = false,
    .wind_sea_patch = false,
    .holds_boundary = nullptr,
    .whitewater = nullptr,
    .whitewater_source = {},
    .long_shot_keys = "/surface/repeat_time",
};

}  // namespace wave::detail
