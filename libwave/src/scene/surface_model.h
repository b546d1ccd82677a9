// The wave models a scene's /surface/kind names, behind one interface: the pipeline
// (plan.cpp, frames.cpp) and scene reading (read_scene.cpp) ask the model, never the kind.
//
// Adding a model: its file in scene/models/ (a SurfaceModel constant), one line in
// models/registry.cpp, its SurfaceKind value (libwave/scene.h) and its name in the
// schema's /surface/kind enum (docs/scene.schema.json).
#pragma once

#include "libwave/scene.h"
#include "scene_node.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace wave::detail {

/// A model's own buffers for a run of frames (e.g. the height field's control heights),
/// made once by SurfaceModel::start and reused by every frame.
struct ModelState {
    virtual ~ModelState() = default;
};

/// The FFT ocean's per-run buffers, shared by the ocean patch (its surface) and any
/// surface with a superposed wind sea.
struct WindSeaState {
    std::optional<OceanWorkspace> workspace;
    std::vector<float> lattice_j;  ///< J₋ on the FFT lattice
    std::vector<float> vertex_j;   ///< J₋ at the surface's (coarse) vertices
};

/// One frame of the surface's own (coarse) vertices, written by SurfaceModel::move.
struct ModelFrame {
    std::span<float> positions;  ///< 3 per vertex
    std::span<float> normals;    ///< 3 per vertex; written only by a model with exact normals
    WindSeaState& wind_sea;
    /// Set when the frame is shaded and nothing moves the model's vertices after it:
    /// a model may compute the Fresnel weights (1 per vertex) in its own pass, while
    /// its positions and normals are in cache, and say so in `weights_done`.
    const FresnelOptions* fresnel = nullptr;
    std::span<float> reflect{}, refract{};
    bool weights_done = false;
};

/// The long-shot keys of a model whose loop is its swell's period.
inline constexpr std::string_view kWindSeaLoopKeys =
    "a wind sea: /ocean with /ocean/repeat_time a whole multiple of the swell's period (the swell alone repeats every period)";

struct SurfaceModel {
    SurfaceKind kind;
    std::string_view name;       ///< the value of /surface/kind
    Traced traced;               ///< what its plan traces (reports, `wave trace`)
    std::string_view loop_keys;  ///< keys that lengthen its loop ("lengthen …")
    std::string_view size_keys;  ///< keys that lower its vertex count ("lower …")
    /// Its motion moves vertices sideways by fields neighbours may disagree on (phases
    /// of crossing rays, breakers): the pipeline untangles every frame (untangle_motion).
    bool untangle;
    /// Whether its motion, as the scene sets it, draws crests that turn over (the
    /// untangling then leaves their lips: UntangleOptions::lips_overturn); nullptr: never.
    bool (*overturns)(const Scene& s);
    /// Harmonics of each wave train its motion holds, which the far field fits at the
    /// border and carries beyond it (plan_far_field): 1 for a linear model, more for a
    /// profile with sharp crests; 0: no far field (the ocean patch tiles instead).
    int far_field_harmonics;

    /// Scene reading, the model's rules between keys, given every key of the file
    /// (`root`) and the scene read so far: keys it does not take, defaults it sets.
    /// `before` runs right after /surface is read, `after` once every key is read.
    void (*read_before)(const Node& root, Scene& s);
    void (*read_after)(const Node& root, Scene& s);

    /// The seafloor under the surface (the ocean patch: a flat bottom of its depth).
    Seafloor (*seafloor)(const Scene& s);

    /// Plans the model's surface: what it traces (all stages), then with
    /// PlanStages::surface or ::all its rest vertices (plan.rest_x, rest_y), its loop
    /// (plan.loop_period) and, for a model with its own FFT ocean, plan.ocean.
    void (*plan)(const Scene& s, ScenePlan& plan, PlanStages stages);

    /// The triangles of the surface's own vertices, before any refinement.
    const std::vector<std::uint32_t>& (*triangles)(const ScenePlan& plan);

    /// Its buffers for a run of frames (nullptr: none); `shaded` when foam is asked for.
    std::unique_ptr<ModelState> (*start)(const Scene& s, const ScenePlan& plan, bool shaded);

    /// The surface at time t: positions of the coarse vertices; returns true when it
    /// also wrote exact normals (and then, with a wind sea of its own, frame.wind_sea's
    /// vertex_j).
    bool (*move)(const Scene& s, const ScenePlan& plan, double t, ModelState* state, ModelFrame& frame);

    /// Its foam at time t at the coarse vertices (zeros on entry), or nullptr: none.
    void (*foam)(const Scene& s, const ScenePlan& plan, double t, ModelState* state, std::span<float> foam);

    /// Where its motion, as the scene sets it, draws walls and overturning lips at time
    /// t (a weight in [0, 1] per coarse vertex, zeros on entry), which the untangling
    /// then leaves instead of the foamy vertices (UntangleOptions::lip_foam); nullptr,
    /// or false returned: the foam marks the lips.
    bool (*lips)(const Scene& s, const ScenePlan& plan, double t, std::span<float> weight);
    /// With `lips`: whether its motion draws the triangle of coarse vertices (a, b, c)
    /// overturned at time t (untangle_motion's may_overturn: a lip's triangle that turns
    /// over elsewhere keeps its orientation); nullptr: every lip's triangle may.
    bool (*draws_overturned)(const Scene& s, const ScenePlan& plan, double t, std::uint32_t a, std::uint32_t b, std::uint32_t c);

    /// What it carries onto the far field's skirt beside the fit (nullptr: the fit alone).
    /// `skirt_size`: the skirt's target sizes it needs, given the far field's own;
    /// `plan_skirt`, once plan.skirt is planned: its share of the skirt's motion
    /// (plan.skirt_breakers), which the pipeline blends in after the fit.
    SkirtSize (*skirt_size)(const Scene& s, const ScenePlan& plan, SkirtSize size);
    void (*plan_skirt)(const Scene& s, ScenePlan& plan);

    /// Its foam and lips depend on the time alone, not on what `move` leaves in its
    /// state: a frame's moved positions kept from an earlier pass may stand in for
    /// `move` (the quantised morph form's delta-range pass, frames.cpp).
    bool foam_of_time_alone = false;

    /// Its surface is the FFT ocean patch itself (plan.ocean): the patch's folds are its
    /// whitecaps and its vertices stay the FFT's (never untangled); it stands on its own
    /// flat bottom, not on a given seafloor; its skirt is the ocean's own; one frame of
    /// it is held beside the FFT's lattice.
    bool wind_sea_patch = false;
    /// Whether the untangling holds the surface's boundary still (the shore, at the
    /// domain's sides); false: the boundary is where traced rays end, and the untangling
    /// keeps no angle bound (the strips hold slivers at rest). nullptr: always.
    bool (*holds_boundary)(const Scene& s) = nullptr;
    /// The whitewater its own breaking makes (nullptr: its motion breaks no water), and
    /// its name in the run's report (whitewater_sources).
    WhitewaterEvents (*whitewater)(const Scene& s, const ScenePlan& plan) = nullptr;
    std::string_view (*whitewater_source)(const Scene& s) = nullptr;
    /// The keys a shot longer than its loop is told to lengthen, without a superposed
    /// wind sea (loop_lengthening_keys).
    std::string_view long_shot_keys;
};

/// The model of a kind (the one place a kind is looked up).
const SurfaceModel& surface_model(SurfaceKind kind);

/// Every model, in the order of SurfaceKind.
std::span<const SurfaceModel* const> surface_models();

// Shared by the models.

/// Plans the FFT ocean of `o` into plan.ocean (with its warning on too coarse a patch).
void plan_wind_sea(const OceanOptions& o, ScenePlan& plan);

/// Refuses every /surface key but `kind` and `camera_grid` for a model without the
/// height field's options (`kind_hint`: what to say about this model).
void refuse_height_field_options(const Node& root, std::string_view kind_hint);

/// Refuses the keys only the ray strips take: /breakers and /surface/camera_grid.
void refuse_ray_strip_keys(const Node& root);

}  // namespace wave::detail
