/// \file
/// libwave — scene: a JSON job description, validated, and the wiring of the stages.
///
/// Every value has a default (docs/scene.md), so a scene can be tiny. Errors name the
/// file and the JSON pointer of the bad value and say what would be valid.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/export.h"
#include "libwave/field.h"
#include "libwave/isobath.h"
#include "libwave/motion.h"
#include "libwave/shade.h"
#include "libwave/surface.h"
#include "libwave/trace.h"
#include "libwave/underwater.h"
#include "libwave/whitewater.h"

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wave {

/// Where the seafloor comes from: a procedural name (procedural_seafloor_names()) or a
/// file (relative paths are resolved against the scene file's folder), read with
/// `read`.
struct SeafloorSource {
    std::string source = "gonzato-bay";  ///< a procedural name or a file path
    ReadOptions read{};  ///< how a file is read (sign, scales, NODATA, SWAN grid)
};

/// Loads a procedural seafloor when `source` names one and no file of that name exists,
/// otherwise reads the file.
Seafloor load_seafloor(const SeafloorSource& source);

/// Which water surface a scene builds.
enum class SurfaceKind {
    ray_strips,    ///< Gonzato: adaptive fronts → ray strips, animated by the plunging profile (one train)
    height_field,  ///< Ts'o: rays at exact isobath crossings → Beta2-spline height field (any trains)
    ocean,         ///< Tessendorf: a tileable open-ocean FFT patch (no seafloor, no traced swell)
    wave_field,    ///< the refraction–diffraction field η̂ e^{−iωt} of every train, on a grid (field.h)
};

/// What a surface kind's plan traces over the seafloor: nothing (the open-ocean patch),
/// Ts'o's rays (ScenePlan::rays), Gonzato's fronts and strips (ScenePlan::fronts, strips)
/// or the trains' wave fields (ScenePlan::wave_fields).
enum class Traced {
    nothing,  ///< no tracing (the open-ocean patch)
    rays,     ///< Ts'o's rays (ScenePlan::rays)
    fronts,   ///< Gonzato's fronts and strips (ScenePlan::fronts, strips)
    field,    ///< the trains' wave fields (ScenePlan::wave_fields)
};

/// The kind's name in scene files (/surface/kind), e.g. "ray-strips".
std::string_view surface_kind_name(SurfaceKind kind);

/// What the kind's plan traces.
Traced surface_kind_traces(SurfaceKind kind);

/// A Gerstner wave as a scene gives it (Tessendorf §3.1); its ω comes from the
/// dispersion relation, quantised to the scene's loop (eq. 18).
struct GerstnerSpec {
    double wavelength = 10.0;  ///< λ = 2π/k (m)
    double amplitude = 0.1;    ///< A (m)
    double direction_x = 1.0;  ///< direction of travel
    double direction_y = 0.0;  ///< direction of travel
    double phase = 0.0;        ///< φ (rad)
};

/// /underwater: the caustic maps a run writes (CausticOptions for each frame).
struct UnderwaterOptions {
    bool caustics = true;  ///< write the caustic maps
    double attenuation = 0.15;  ///< c (1/m): /underwater/attenuation or /underwater/water_type's
    std::size_t map_size = 512;  ///< pixels along the seafloor's longer side (the other in proportion)
    double full_scale = 4.0;     ///< E / I₀ written as white (65 535) in the PNGs
    /// /underwater/sunbeams: the sunlight in the water, an OpenVDB volume per frame
    /// (evaluate_sun_volume; none when empty).
    std::optional<SunVolumeOptions> sunbeams{};
};

/// A job: the seafloor, the wave trains, every stage's options and the outputs, as a
/// scene file gives them (read_scene, parse_scene; docs/scene.md lists the keys).
struct Scene {
    std::string name = "default";  ///< recorded in the outputs
    SurfaceKind surface_kind = SurfaceKind::ray_strips;  ///< the wave model (/surface/kind)
    SeafloorSource seafloor{};  ///< /seafloor
    IsobathOptions isobaths;  ///< /isobaths
    std::vector<WaveTrain> waves{};  ///< /waves
    TraceOptions trace{};  ///< /trace
    /// Ts'o's sampling rule: this many orthogonals per surface grid line (overrides
    /// trace.ray_spacing when > 0: spacing = min(cell dx, dy) / n).
    double orthogonals_per_grid_line = 0.0;
    HeightFieldOptions surface{};  ///< /surface: the height field's options
    /// Adaptive fronts (ray strips); ray_spacing, breaker_index and max_rays come from `trace`.
    FrontOptions fronts{};
    FieldOptions field{};  ///< the refraction–diffraction field (/field; breaker_index from /trace)
    /// Ray strips and the height field: amplitudes from the field (finite where rays
    /// cross) rather than from the rays' spacing (/field/amplitudes "field" or "rays").
    bool amplitudes_from_field = true;
    GonzatoProfileOptions profile{};  ///< /motion: Gonzato's profile
    /// Jeschke's procedural breakers instead of Gonzato's profile (ray strips only),
    /// parametrised from the traced rays; their foam replaces the breaking foam.
    std::optional<JeschkeBreakerOptions> breakers;
    /// Hinsinger's camera-projected grid as the surface (with breakers): sampled from
    /// the camera at /camera/position (or the default camera) instead of the strips.
    std::optional<GridCamera> camera_grid;
    /// The ray-strips surface that is exported: when set (the default; /surface/water_mesh),
    /// the water mesh — a graded triangulation of the water bounded by the domain and
    /// the shoreline (mesh_water), this many vertices per local wavelength, the strips'
    /// fields (or the breakers) resampled at its vertices; when empty
    /// (`"water_mesh": false`), the strips themselves. A camera grid replaces both
    /// (reading /surface/camera_grid empties it).
    std::optional<double> water_mesh_per_wavelength = 16.0;
    /// /surface/water_mesh/surf_zone (experimental): with Jeschke's breakers, the water
    /// mesh's edge over the band where crests break, as a fraction of the local height H
    /// (SurfZoneMesh; 0.25 is H/4); 0 (the default) = the wavelength's spacing there too.
    double surf_zone_mesh = 0.0;
    /// The far field (/surface/far_field): the sea beyond the domain, so that no edge
    /// shows towards the horizon.
    struct FarField {
        /// How far the skirt reaches beyond the domain (m); 0: 2000 times the camera's
        /// height, at least 10 times the domain's size.
        double distance = 0.0;
        /// The swell keeps its resolution this many local wavelengths beyond the border,
        /// then fades out where the skirt's edges grow (> 0).
        double swell_wavelengths = 2.0;
        /// With /breakers: where the border's water breaks, the breakers carry on this
        /// many local wavelengths beyond it on a skirt as fine as the border, fading
        /// out over the last one (continue_jeschke_breakers); 0: the fit alone (>= 0).
        double breaker_wavelengths = 2.0;
    };
    /// Set (the default): traced surfaces continue on a skirt out to the far rectangle
    /// (plan_sea_skirt, plan_far_field); empty (`"far_field": false`, the ocean patch,
    /// which tiles, and the camera grid, which reaches the horizon itself): the surface
    /// ends at the domain's border.
    std::optional<FarField> far_field = FarField{};
    /// The preview renderer's view, sun and bump waves (`wave preview`, `--preview`);
    /// its camera position is the scene's camera.
    PreviewOptions preview{};
    bool preview_look_at_set = false;  ///< else the view looks at the domain's centre
    /// OpenSubdiv refinement of the surface (any kind); the exported mesh is the refined one.
    std::optional<RefineOptions> refine;
    std::size_t max_refined_vertices = 50'000'000;  ///< refuse refinements above this (LimitError)
    /// Tessendorf's FFT wind waves: the surface itself (kind ocean) or superposed on the
    /// traced swell, scaled by wind_sea_depth_factor so they calm down over the shelf.
    /// A repeat time of 0 in a scene means: the multiple of the swell's loop nearest
    /// 20 s (kind ocean: 20 s).
    std::optional<OceanOptions> ocean;
    std::vector<GerstnerSpec> gerstner;  ///< Gerstner waves superposed on any surface
    FoldFoamOptions fold_foam{};         ///< foam where the choppy FFT surface folds
    /// /shade/fold_threshold was given: the fold foam keeps it. Otherwise plan_scene
    /// calibrates the threshold so that the foam covers `whitecap_coverage` of the sea.
    bool fold_threshold_set = false;
    /// The share of the sea the fold foam covers (/shade/whitecap_coverage, in [0, 1]);
    /// empty: the wind's (whitecap_coverage(wind speed), Callaghan et al. 2008).
    std::optional<double> whitecap_coverage;
    /// Camera for the Fresnel weights (m, z up); empty = above the domain's up-wave
    /// side, looking across it (scene_camera).
    std::optional<std::array<double, 3>> camera;
    FresnelModel fresnel = FresnelModel::exact;  ///< /shade/fresnel
    FoamOptions foam{};  ///< /shade: breaking foam
    /// Light under the water (/underwater, docs/underwater.md): the caustics each frame's
    /// surface focuses onto the seafloor under the scene's sun (/preview/sun), a 16-bit
    /// PNG per frame beside the animation. Empty: none.
    std::optional<UnderwaterOptions> underwater;
    /// Spray, foam and bubbles as particles (/whitewater, docs/whitewater.md): thrown by
    /// Jeschke's breakers (/breakers) and the wind sea's folds (/ocean), a POINTS .glb per
    /// frame beside the animation (kWhitewaterPoints). Empty: none.
    std::optional<WhitewaterOptions> whitewater;
    /// Which shading attributes the export carries: none, the Blender 3.4 UV-map layout
    /// (default: every glTF client reads UV maps), or the named `_` attributes.
    enum class Attributes {
        none,     ///< positions and normals only
        uv_maps,  ///< TEXCOORD_1 = (R, T), TEXCOORD_2 = (foam, 0): every glTF client, Blender 3.4 too
        named,    ///< as `_REFLECT`, `_REFRACT`, `_FOAM` attributes
    };
    Attributes attributes = Attributes::uv_maps;  ///< /outputs/attributes
    bool color = false;  ///< bake COLOR_0 (Ts'o eq. 4.1)
    /// What the single-file forms carry beside the water (/outputs/seafloor, camera, sun,
    /// material): the seafloor coloured by depth, the scene camera, the sun, a water material.
    bool dress_seafloor = true;  ///< /outputs/seafloor
    bool dress_camera = true;    ///< /outputs/camera
    bool dress_sun = true;       ///< /outputs/sun
    bool dress_material = true;  ///< /outputs/material
    /// How the animation is written (export_forms(): morph, nodes, files, pc2).
    using Form = ExportForm;
    Form form = Form::morph;  ///< /outputs/form
    bool quantize = false;  ///< KHR_mesh_quantization (not with Draco)
    /// EXT_meshopt_compression (MorphAnimationView::meshopt; not with Draco or quantize).
    bool meshopt = false;
    /// /outputs/codec "auto" (the default, when the scene names no codec): the run
    /// chooses with resolve_codec, meshopt for a big output, plain floats for a small one.
    bool codec_auto = true;
    /// Binary .glb, or text .gltf with an external .bin.
    using Container = ExportContainer;
    Container container = Container::glb;  ///< /outputs/container
    /// Draco compression (empty = none); in the morph form, of the base mesh.
    std::optional<DracoOptions> draco;
    double fps = 24.0;  ///< frames per second of the animation (> 0)
    /// Refuse loops of more frames (LimitError before any frame is computed); the
    /// scene key /animation/max_frames raises it.
    std::size_t max_frames = 100'000;
    /// The scene as it was written: the JSON document parse_scene read (compact, keys as
    /// given, defaults not filled in) and the folder its relative paths are resolved
    /// against. parse_scene(document, origin, base_dir) gives this scene again: the
    /// Python module's Scene.to_dict() and Scene.set() edit it and parse it again.
    std::string document = "{}";
    std::string base_dir = ".";  ///< relative seafloor paths are resolved against it
};

/// The built-in default scene: Gonzato's bay with a 5 s swell, ray strips animated by
/// the plunging profile (what `wave run` does with no argument).
Scene default_scene();

/// The export forms and containers as scene files (/outputs) and the command line spell
/// them (the forms: export_forms()'s names; "glb", "gltf"). The *_from_name functions
/// throw InputError naming the valid names.
std::string_view form_name(Scene::Form form);
/// The form spelt `name` (InputError naming the valid names).
Scene::Form form_from_name(std::string_view name);
/// The name of a container: "glb" or "gltf".
std::string_view container_name(Scene::Container container);
/// The container spelt `name` (InputError naming the valid names).
Scene::Container container_from_name(std::string_view name);

/// Parses a scene from JSON text. `origin` names the file in messages; `base_dir` is
/// where relative seafloor paths are resolved. Unknown keys are errors (typos); every
/// number must lie in the range scene_schema() gives its key, text nested deeper than
/// 64 levels is refused before parsing.
Scene parse_scene(std::string_view json_text, const std::string& origin, const std::string& base_dir);

/// The scene file's JSON Schema (docs/scene.schema.json): keys, types, defaults and the
/// valid range of every number — the ranges parse_scene enforces.
std::string_view scene_schema();

/// Reads and parses a scene file.
Scene read_scene(const std::string& path);

/// The seafloor a scene stands on: its source, or for the open-ocean patch a flat
/// bottom under the patch at /ocean/depth (10 km when deep).
Seafloor scene_seafloor(const Scene& scene);

/// The camera of a scene: its own, or by default 60 % of the domain's length before
/// its up-wave edge (against the first train's direction), at 40 % of that length up.
std::array<double, 3> scene_camera(const Scene& scene, const Seafloor& seafloor);

/// What makes a scene's whitewater, as the run's report names it: "breakers", the
/// surface model's own breaking (e.g. "gonzato breaking"), "wind sea folds". Empty
/// without /whitewater.
std::vector<std::string> whitewater_sources(const Scene& scene);

/// What moves a ray-strips scene's strips, as the run summary names it ("Jeschke's
/// breakers", "Gonzato's plunging profile"); empty for the other surface kinds.
std::string_view strip_motion_name(const Scene& scene);

/// The keys that lengthen a scene's loop, as a shot longer than the loop is told
/// (docs/scene.md, "Long shots").
std::string loop_lengthening_keys(const Scene& scene);

/// The preview options of a scene with its camera filled in: the scene's camera,
/// looking at /preview/look_at or the centre of the domain at still water.
PreviewOptions scene_preview(const Scene& scene, const Seafloor& seafloor);

/// The caustic options of a scene with /underwater: its sun (/preview/sun), water, and
/// a map over the seafloor grid's rectangle, map_size pixels along its longer side;
/// I₀ = 1, so the maps hold irradiance relative to the sun's on flat water. Flat water
/// beyond the surface lights the floor unless the plan has a far-field skirt, which
/// brings that light itself.
struct ScenePlan;
/// The caustic options of `scene`, over the grid of its plan's seafloor.
CausticOptions scene_caustic_options(const Scene& scene, const ScenePlan& plan);


/// The scene's trace options with Ts'o's rule applied: when orthogonals_per_grid_line
/// > 0, ray_spacing = min(surface cell dx, dy) / orthogonals_per_grid_line.
TraceOptions scene_trace_options(const Scene& scene, const Seafloor& seafloor);

/// The per-scene (static) products of the pipeline, computed once. Only the members
/// of the scene's surface kind are filled.
struct ScenePlan {
    Seafloor seafloor;  ///< as read (or generated) and transformed
    DepthContours isobaths;  ///< sliced at /isobaths
    RaySet rays;              ///< height field: Ts'o's rays
    HeightFieldPlan surface;  ///< height field
    FrontSet fronts;          ///< ray strips: Gonzato's fronts
    std::vector<WaveField> wave_fields;  ///< the trains' refraction–diffraction fields, where the model uses them
    RayStrips strips;         ///< ray strips: the tessellated surface
    GonzatoMotionPlan motion; ///< ray strips without breakers: the profile's per-vertex shapes (empty with them)
    JeschkeMotionPlan breakers; ///< ray strips with Scene::breakers: the breakers' plan (on the camera grid if any)
    CameraGrid camera_grid;     ///< Scene::camera_grid: the sampled points (empty otherwise)
    WaterMesh water_mesh;       ///< Scene::water_mesh_per_wavelength: the mesh (empty otherwise)
    SeaSkirt skirt;             ///< Scene::far_field: the skirt beyond the domain (no vertices otherwise)
    FarFieldPlan far_field;     ///< … its motion
    SkirtBreakers skirt_breakers;  ///< … and, with breakers, the breakers carried onto it
    /// Scene::whitewater with breakers: where and when the breaking crests throw
    /// whitewater over the loop (periodic; the wind sea's come from each frame's folds).
    WhitewaterEvents whitewater;
    /// With a skirt: the model's own vertices (they come first in rest_x, rest_y) and the
    /// surface's triangles with the skirt's (empty without a skirt).
    std::size_t model_vertices = 0;
    std::vector<std::uint32_t> skirted_triangles;  ///< the model's triangles, then the skirt's
    RayStrips water_strips;     ///< … the strips' fields resampled at its vertices (Gonzato's profile and foam move it)
    Refinement refinement;      ///< Scene::refine: refined topology + stencils (fine_vertices = 0 when none)
    OceanPlan ocean;          ///< the FFT ocean (kind ocean, or superposed); n = 0 when none
    std::vector<GerstnerWave> gerstner;  ///< with ω quantised to the loop
    std::vector<std::uint32_t> patch_triangles;  ///< grid surfaces (ocean, wave-field): their triangles
    /// Per surface vertex, for the superposed components: rest position, depth there,
    /// and the wind-sea amplitude factor (1 in deep water, → 0 at the shore).
    std::vector<double> rest_x, rest_y;  ///< rest positions (m)
    std::vector<float> rest_depth;      ///< depth there (m)
    std::vector<float> wind_sea_scale;  ///< wind-sea amplitude factor
    double loop_period = 0.0; ///< the animation repeats after this (s)
    /// The fold foam the frames use: the scene's, with the threshold calibrated to the
    /// whitecap coverage when the scene did not give one (a wind sea only).
    FoldFoamOptions fold_foam{};
    double whitecap_coverage = 0.0;  ///< the coverage the threshold was calibrated to (0: not calibrated)
    /// Frame 0's fold-foam past, kept from that calibration: its lattice indices (newest
    /// first) and the samples at the surface's vertices, the same bits a frame computes.
    /// A run through frame 0 starts with them. Empty when the threshold was given.
    std::vector<std::pair<long long, FoldSample>> fold_past;
    /// Doubts about the result that are not errors, e.g. a train whose wavelength the
    /// surface grid cannot resolve (aliasing).
    std::vector<std::string> warnings;
};

/// How far plan_scene goes: through the tracing only (what `wave trace` needs); through
/// the surface and motion plans (`surface`: enough for estimate_run, without /refine's
/// subdivision, which can take gigabytes); or all of it (`all` = `surface`, then
/// refine_scene_plan).
enum class PlanStages {
    trace,    ///< through the tracing only
    surface,  ///< through the surface and motion plans, without /refine's subdivision
    all,      ///< surface, then refine_scene_plan
};

/// Runs every static stage of a scene through the model of /surface/kind: e.g.
/// seafloor → isobaths → trace → surface plan (height field), or seafloor → isobaths
/// → fronts → ray strips → water mesh → motion plan (ray strips). The scene's
/// /trace/ray_spacing, breaker_index and max_rays are the fronts' too (FrontOptions'
/// own fields are overwritten by them).
/// Throws InputError when the Bresenham footprint is asked for with fewer than one
/// orthogonal per grid line (Ts'o's minimum: the grid would have holes), or when ray
/// strips are asked for with other than one wave train.
ScenePlan plan_scene(const Scene& scene, PlanStages stages = PlanStages::all);

/// plan_scene on a seafloor the caller made (seafloor_from_mesh of a DCC's terrain,
/// seafloor_from_grid of an array) instead of the one /seafloor names: the scene's
/// /seafloor keys are not read (the caller applied what they say — a vertical offset
/// for the water level, scales). The same plan as plan_scene of a scene whose /seafloor
/// reads those values from a file. Traced surfaces only (the open ocean's flat bottom
/// is its own); throws as plan_scene does.
ScenePlan plan_scene(const Scene& scene, Seafloor seafloor, PlanStages stages = PlanStages::all);

/// The explicit last planning step: /refine's subdivision of the planned surface (a
/// no-op without /refine). Call it after estimate_run and check_run_memory have found
/// the run affordable; plan_scene(…, PlanStages::all) calls it itself.
void refine_scene_plan(const Scene& scene, ScenePlan& plan);

/// Every frame of one animation loop of a planned scene, ready for an exporter.
struct SceneAnimation {
    std::size_t vertex_count = 0;  ///< per frame
    std::size_t frame_count = 0;   ///< frames held
    std::size_t first_frame = 0;  ///< of the loop: these are frames first_frame … first_frame + frame_count − 1
    std::size_t loop_frames = 0;  ///< frames in the whole loop
    std::vector<float> positions;  ///< frame_count · vertex_count · 3, z up
    std::vector<float> normals;    ///< same layout, unit (area-weighted, Jeschke §5)
    std::vector<float> texcoords;  ///< vertex_count · 2: rest position scaled to the domain
    /// Shading per frame (frame_count · vertex_count each; empty when the scene's
    /// attributes are none): Fresnel weights, foam from depth-limited breaking, and
    /// COLOR_0 (3 per vertex) when asked.
    std::vector<float> reflect;  ///< Fresnel R per frame and vertex
    std::vector<float> refract;  ///< T = 1 − R
    std::vector<float> foam;     ///< in [0, 1]
    std::vector<float> colors;   ///< COLOR_0, 3 per vertex (/outputs/color)
    ScalarLayout layout = ScalarLayout::blender34;  ///< how the exporters lay out the scalars
    std::optional<DracoOptions> draco;  ///< the scene's Draco options
    bool quantize = false;  ///< KHR_mesh_quantization
    bool meshopt = false;   ///< EXT_meshopt_compression
    float z_min = 0;  ///< height range over all frames (m)
    float z_max = 0;  ///< height range over all frames (m)
    double fps = 24.0;  ///< frames per second
    std::vector<std::uint32_t> triangles;  ///< a copy of the plan's index list (the animation outlives the plan)
    std::string scene;  ///< the scene's name (recorded in the files)
    /// The scene around the water (morph and nodes forms; SceneDressing): the seafloor mesh
    /// (z up), its colours and triangles, and the camera, sun and material settings.
    std::vector<float> seafloor_positions;  ///< 3 per vertex (m, z up)
    std::vector<float> seafloor_colors;     ///< 3 per vertex (linear RGB)
    std::vector<std::uint32_t> seafloor_triangles;  ///< 3 per triangle
    std::optional<SceneDressing> dressing;  ///< its spans are set by view()
    /// /underwater's caustic maps, one 16-bit PNG per frame (empty without them), and
    /// the seafloor's TEXCOORD_0 in the maps' frame (the dressing's seafloor vertices).
    std::vector<std::string> caustics;
    std::vector<float> seafloor_texcoords;  ///< 2 per seafloor vertex
    /// /underwater/sunbeams: one OpenVDB volume of the sunlight in the water per frame
    /// (sun_volume_vdb; empty without them).
    std::vector<std::string> sunbeams;
    /// /whitewater: one POINTS .glb of the frame's particles per frame (whitewater_glb;
    /// empty without them).
    std::vector<std::string> whitewater;

    MorphAnimationView view() const;  ///< a view for the exporters (spans into this)
};

/// Which frames of the loop to evaluate: [first, end) clipped to the loop; the default
/// is all of them. Slices let several machines share one animation (`files` form).
struct FrameRange {
    std::size_t first = 0;  ///< first frame of the loop
    std::size_t end = static_cast<std::size_t>(-1);  ///< one past the last (clipped to the loop)
};

/// What a run of the whole loop, or of `run_frames` of it (a slice), would hold and
/// write (`wave validate`, `wave run`), from a plan:
/// the per-frame float arrays animate_scene keeps (positions, normals, shading,
/// colour), the files of the scene's form, and the peak memory of `wave run` (the plan,
/// those arrays, and the encoded files, held until they are published; the constants
/// were measured on the default scene, src/scene/budgets.cpp).
/// Uncompressed sizes follow the writer's layout exactly (docs/export.md); Draco
/// frames are estimated at 9.2 bytes per vertex (measured on the default scene's water mesh with
/// the default 14-bit positions), quantised morph targets at 0.7 of plain.
struct RunEstimate {
    std::size_t vertices = 0;   ///< of the exported surface
    std::size_t triangles = 0;  ///< of the exported surface
    std::size_t frames = 0;     ///< in the loop
    double frame_array_bytes = 0.0;  ///< the loop's per-frame arrays held at once
    double output_bytes = 0.0;       ///< the files the run writes
    double peak_memory_bytes = 0.0;  ///< of the run, streamed forms holding one chunk
};
/// Frames in one loop of the planned animation: round(loop period · fps), at least 1
/// (SIZE_MAX when it does not fit; /animation/max_frames refuses it).
std::size_t scene_loop_frames(const Scene& scene, const ScenePlan& plan);

/// Also for a plan of PlanStages::surface: /refine's vertex count is then predicted from
/// the coarse triangles (uniform subdivision's count; an upper bound for adaptive).
/// `planned_resident_bytes`: the resident memory of a process that has just planned the
/// scene (`wave validate` measures its own: the process, its libraries and the plan as
/// `wave run` will hold them); 0 = modelled from the surface's vertex count.
/// `run_frames`: the frames the run computes (`--frames`); 0 or more than the loop's =
/// the whole loop.
RunEstimate estimate_run(const Scene& scene, const ScenePlan& plan, double planned_resident_bytes = 0.0,
                         std::size_t run_frames = 0);

/// The plain output size above which /outputs/codec "auto" compresses (bytes).
inline constexpr double kAutoCodecBytes = 32e6;
/// /outputs/codec "auto" decided (docs/export.md, "Which codec"): a glTF output
/// (morph, nodes, files) whose plain estimate (`plain`: estimate_run of the scene
/// without a codec) exceeds kAutoCodecBytes gets EXT_meshopt_compression; smaller ones
/// and PC2 stay plain floats, which every glTF client reads. A scene that names a codec
/// keeps it. Returns the scene with codec_auto cleared.
Scene resolve_codec(Scene scene, const RunEstimate& plain);

/// What a scene needs at least before its plan exists (bytes): an FFT ocean's lattice
/// and transforms (92 B per lattice point) and, for the open-ocean patch, one frame's
/// arrays of its (N+1)² vertices; 0 for scenes without /ocean. A lower bound of the
/// peak a run reaches (measured in bench/RESULTS.md), known from the scene alone.
double planned_memory_floor_bytes(const Scene& scene);

/// Refuses, before any planning, a scene whose planned_memory_floor_bytes exceeds
/// `max_bytes` (LimitError naming /ocean/resolution and `wave run --max-memory-gb`), or
/// whose sunbeam volume alone would (16 bytes a voxel while a frame is computed;
/// naming /underwater/sunbeams/voxels): `wave run` and `wave validate` call it first, so
/// that a 4096² ocean beyond the limit is refused at once instead of after planning its
/// lattice.
void check_plan_limits(const Scene& scene, double max_bytes);

/// The limits of a run, checked by `wave validate`, by `wave run` before the refinement
/// is planned, and by animate_scene: the loop's estimate.frames within
/// /animation/max_frames, the per-frame arrays of the `frames` held at once of the
/// estimate's surface within `max_bytes`, and the estimate's peak_memory_bytes (0 = not
/// estimated) within `max_bytes` too. LimitError naming the scene keys that shrink it
/// and `wave run --max-memory-gb`.
void check_run_limits(const Scene& scene, const RunEstimate& estimate, std::size_t frames, double max_bytes);

/// How many frames the `files` form computes, writes and indexes at a time: it never
/// holds the whole loop (a killed run loses at most one chunk; `wave run --resume`
/// continues from the frames its index lists). At most 256 MB (and `max_bytes`) of
/// per-frame arrays, at least one frame, and at most ~64 chunks per loop so that the
/// index is rewritten a bounded number of times.
std::size_t files_form_chunk(const RunEstimate& e, double max_bytes = 2e9);

/// Frames of one loop evaluated a chunk at a time, for runs that must not hold every
/// frame (the streamed export forms, docs/export.md): constructed once per range (the
/// model's state, normals' adjacency, untangling and caustic plans, the fold foam's
/// past samples carry from chunk to chunk), then `next` until it returns 0. Each chunk
/// equals, bit for bit, what animate_scene returns for the same frames. The scene and
/// plan must outlive the stream.
class AnimationStream {
public:
    /// Throws InputError for an empty frame range (naming it).
    AnimationStream(const Scene& scene, const ScenePlan& plan, FrameRange range = {});
    ~AnimationStream();  ///< frees the stream's state
    AnimationStream(const AnimationStream&) = delete;  ///< not copyable
    AnimationStream& operator=(const AnimationStream&) = delete;  ///< not copyable
    std::size_t first_frame() const noexcept;   ///< of the loop
    std::size_t frame_count() const noexcept;   ///< in the range
    std::size_t frames_left() const noexcept;  ///< frames not yet evaluated
    /// The next min(count, frames_left()) frames into `out` (every array resized to them,
    /// its first_frame, z range and caustics theirs). The static parts — triangles,
    /// texcoords, dressing, seafloor — are set on the first call into `out` and left on
    /// later calls into the same `out` while its triangles are the ones set (not
    /// replaced or resized; change none of these in place between calls). Returns how
    /// many (0 at the end). `progress(done, total)` counts frames of the whole range.
    std::size_t next(SceneAnimation& out, std::size_t count,
                     const std::function<void(std::size_t, std::size_t)>& progress = {});
    /// The largest |delta| of any position coordinate from the range's first frame,
    /// over the whole range, from a pass of its own (`chunk` frames at a time, positions
    /// only: no shading, colour, caustics, whitewater or normals); this stream is not advanced. What a
    /// quantised morph file needs before its first target (MorphAnimationView::quantize_range).
    /// Where the untangling runs on a surface whose foam needs nothing of the motion's
    /// state (the ray strips, no wind sea), the pass's moved positions are kept in an
    /// unnamed temporary file (12 bytes a vertex and frame) and this stream's frames take
    /// them instead of moving and untangling again (the same bits).
    double position_delta_range(std::size_t chunk) const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

/// Whether wave run streams the scene's form (stream_animation): morph (plain or
/// quantised: a first pass finds the deltas' range), nodes and pc2 (not quantised:
/// KHR_mesh_quantization's range of positions spans every frame). The files form
/// writes a chunk of frames at a time by its own index (`wave run --resume`).
bool streamed_form(const Scene& scene);
// streamed_form(ExportForm, bool), StreamedWriter and encode_animation: export.h.

/// What stream_animation wrote and saw.
struct StreamedAnimation {
    std::vector<std::pair<std::string, std::size_t>> files;  ///< (name under the folder, bytes), as encode_animation orders them
    float z_min = 0;  ///< height range over every frame (m)
    float z_max = 0;  ///< height range over every frame (m)
    SceneAnimation first;        ///< the range's first frame alone (for an OBJ, a preview)
};

/// encode_animation for a form streamed_form accepts, a chunk of frames at a time:
/// evaluates `stream` `chunk` frames at a time and writes each chunk into `folder` (it
/// must exist) as it comes, so that memory holds one chunk of frames and the file's
/// index, never the animation (docs/export.md, "Streamed output"). The files' names and
/// bytes equal encode_animation's of the whole range (`whole` as there). Throws
/// InputError for a form it does not stream; what it wrote is removed if it fails.
StreamedAnimation stream_animation(AnimationStream& stream, const Scene& scene, const std::string& folder, bool whole,
                                   std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& progress = {});

/// The run key of a scene's frames (FrameIndexInfo::run_key, MorphAnimationView::run_key):
/// SHA-256 over what decides their bytes — libwave's version, `source` (the scene's
/// text: `wave run` gives the scene file's bytes, or "built-in default scene\n"; the
/// Python module the scene's document), the export settings a command line overrides
/// (fps, container, quantize, Draco's bits, meshopt) and the seafloor's grid and heights
/// (a scene naming a data file that changed gets another key). Threads do not count.
std::string scene_run_key(const Scene& scene, const ScenePlan& plan, std::string_view source);

/// What write_files_form wrote and kept: the files form of a range of frames, in a
/// hidden partial folder of the output folder, to publish (stage, or publish_files_form).
struct FilesFormRun {
    std::vector<std::string> entries;  ///< frame_entry_json text per frame of the range, in order
    /// Every frame file of the range (name under the output folder, bytes), in the
    /// entries' order: those in the partial folder and those kept in the output folder.
    std::vector<std::pair<std::string, std::size_t>> files;
    float z_min = 0.0f;  ///< height range over the range's frames (m)
    float z_max = 0.0f;  ///< height range over the range's frames (m)
    std::size_t verified = 0;  ///< frames kept (`resume`: their files matched their entries)
    std::size_t computed = 0;  ///< frames computed and written by this run
    bool whole_loop = false;   ///< the range is the whole loop (its index replaces every entry)
    std::string partial;       ///< the partial folder (removed once published)
    std::vector<std::string> partial_files;  ///< frame files in it (names under it and the output folder), to publish
    FolderLock lock;           ///< on the partial folder while the run holds it
    /// Links the partial folder's frame files into `staging` (a folder of the output
    /// folder's file system; copied where it has no hard links) and returns their names:
    /// the partial folder keeps them, so that a publication that fails leaves them for
    /// `--resume`.
    std::vector<std::string> stage(const std::string& staging) const;
};

/// The files form (frames/frame-NNNN.glb, each frame's underwater files after it) of
/// frames [range.first, range.end) of a planned scene, computed files_form_chunk frames
/// at a time (`max_bytes` as there) into a hidden partial folder of `out_dir` (created
/// with its parents; named by the run key and the range, locked while the run holds it:
/// a second run of the same range and key gets InputError naming it). Each chunk's
/// frame files are written whole and then listed, with their sizes and SHA-256, in that
/// folder's own index.json: a run killed at any moment leaves every frame it listed
/// whole. With `resume`, frames the partial index (or `out_dir`/index.json, same run
/// key) lists and whose files still match it are kept; the others are computed. Without
/// `resume` the partial folder starts empty. Frames carry info.run_key.
/// Before any frame: InputError when `out_dir`/index.json belongs to another animation
/// or run key (merged_frame_index's rules, `resume` rebuilding an unreadable one), or the
/// range holds no frame of the loop (info.loop_frames). When it fails part way, the
/// frames already listed stay for `resume`; with none, nothing is left (nor `out_dir`,
/// when it made it). `progress(done, total)` counts the range's frames, kept ones first.
FilesFormRun write_files_form(const Scene& scene, const ScenePlan& plan, const std::string& out_dir, const FrameIndexInfo& info,
                              FrameRange range, bool resume, double max_bytes = 2e9,
                              const std::function<void(std::size_t, std::size_t)>& progress = {});

/// After the run's frames and index are published: removes its partial folder (releasing
/// its lock) and the partial folders of other run keys in `out_dir` (earlier versions of
/// the scene, which can no longer be resumed into its animation), except those another
/// run holds locked or that cannot be locked. Returns the names removed besides its own.
std::vector<std::string> remove_files_form_partials(const std::string& out_dir, FilesFormRun& run, const FrameIndexInfo& info);

/// Publishes a write_files_form run without a staging folder of the caller's (the
/// Python module): holding a lock on `out_dir` (waiting for slices that publish into it),
/// moves the partial folder's frame files into place, then writes `out_dir`/index.json
/// (merged_frame_index of the run's entries; `resume` rebuilds an unreadable one), then
/// remove_files_form_partials. Returns the index's bytes. Throws what merged_frame_index
/// throws before any frame is moved, InputError for a name that leaves `out_dir`, and
/// RuntimeError when a file cannot be moved or written (the frames not yet moved stay in
/// the partial folder; `resume` computes the moved ones again).
std::string publish_files_form(FilesFormRun& run, const std::string& out_dir, const FrameIndexInfo& info, bool resume);

/// Evaluates frames of one loop (round(loop_period · fps) frames, t = k / fps): the
/// model's motion (e.g. the height field, or Gonzato's profile on the water mesh),
/// any superposed wind sea or Gerstner waves, untangling, then normals and shading.
/// `progress(done, total)` is called after each frame when given.
/// Throws InputError for an empty frame range, LimitError when the frames would exceed
/// `max_bytes` as float arrays (naming the scene values that lower it).
SceneAnimation animate_scene(const Scene& scene, const ScenePlan& plan, double max_bytes = 2e9,
                             FrameRange range = {},
                             const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace wave
