// Budgets and limits: what a run writes and holds (estimate_run), the memory refusals
// before the work, the files form's chunk, how many frames run side by side, the codec
// a run's size chooses.
#include "libwave/scene.h"

#include "core/format.h"
#include "core/limits.h"
#include "libwave/errors.h"
#include "pipeline.h"
#include "surface_model.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace wave {

using detail::fmt;

namespace {

// The sunbeam volumes: a VDB per frame, ~1 byte a voxel (measured 0.87 on
// examples/sunbeams-cove.json: half floats, compressed, the ground and air inactive);
// while a frame is computed, two volumes in turn (4 bytes a voxel each) and the VDB tree
// of the one being encoded with its file (~8).
constexpr double kSunbeamFileBytesPerVoxel = 1.0, kSunbeamWorkBytesPerVoxel = 16.0;

double sunbeam_voxels(const Scene& scene) {
    if (!scene.underwater || !scene.underwater->sunbeams) return 0.0;
    const SunVolumeOptions& o = *scene.underwater->sunbeams;
    return static_cast<double>(o.nx) * static_cast<double>(o.ny) * static_cast<double>(o.nz);
}

}  // namespace

namespace detail {

// Frames side by side (docs/motion.md "Frames side by side"). A frame's passes each
// share their vertices out among the cores and wait for the slowest: at 66 k vertices
// (a 256² ocean) a frame is ten such joins of 50–100 µs, and on a shared machine each
// waits for its slowest core. Below kLaneVertices whole frames run at once instead,
// each on a run of its own (its model state, workspace and fold-foam samples), and a
// frame's own passes run inside it. A frame computes the same bits on any run, so the
// output does not depend on how many run side by side. Not with underwater maps or
// volumes (each frame's map is long and parallel by itself).
constexpr std::size_t kLaneVertices = std::size_t{1} << 18;
constexpr std::size_t kMaxLanes = 8;

std::size_t frame_lanes(const Scene& scene, std::size_t vertices, std::size_t frames) {
    const bool underwater = scene.underwater && (scene.underwater->caustics || scene.underwater->sunbeams);
    if (underwater || vertices > kLaneVertices || frames < 2) return 1;
    const auto cores = std::min(static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()),
                                tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    return std::clamp<std::size_t>(std::min(cores, frames), 1, kMaxLanes);
}

}  // namespace detail

Scene resolve_codec(Scene scene, const RunEstimate& plain) {
    if (scene.codec_auto && !scene.draco && !scene.quantize && !scene.meshopt)
        scene.meshopt = export_form(scene.form).gltf && plain.output_bytes > kAutoCodecBytes;
    scene.codec_auto = false;
    return scene;
}

RunEstimate estimate_run(const Scene& scene, const ScenePlan& plan, double planned_resident_bytes, std::size_t run_frames) {
    RunEstimate e;
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    const std::size_t coarse_triangles = detail::surface_triangles(scene, plan).size() / 3;
    if (refined) {
        e.vertices = refined->fine_vertices;
        e.triangles = refined->triangles.size() / 3;
    } else if (scene.refine) {  // not planned yet (PlanStages::surface): predicted
        const double t = refined_triangle_estimate(coarse_triangles, *scene.refine);
        e.triangles = t < 1e18 ? static_cast<std::size_t>(t) : std::numeric_limits<std::size_t>::max();
        e.vertices = e.triangles / 2;
    } else {
        e.vertices = plan.rest_x.size();
        e.triangles = coarse_triangles;
    }
    const bool fine = scene.refine.has_value();
    e.frames = scene_loop_frames(scene, plan);
    const double n = static_cast<double>(e.vertices), loop = static_cast<double>(e.frames);
    // The frames the run writes: its files and, for a file written whole, the arrays it holds.
    const double frames = run_frames > 0 ? std::min(loop, static_cast<double>(run_frames)) : loop;
    const bool shaded = scene.attributes != Scene::Attributes::none;
    // animate_scene: positions + normals, reflect/refract/foam, colour (floats).
    const double arrays_per_vertex = 24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0);
    e.frame_array_bytes = loop * n * arrays_per_vertex;
    const double run_arrays = frames * n * arrays_per_vertex;
    // The writer: POSITION + NORMAL, TEXCOORD_0, shading (UV maps 2 × vec2, or 3 floats), COLOR_0.
    const double shading = scene.attributes == Scene::Attributes::uv_maps ? 16.0 : scene.attributes == Scene::Attributes::named ? 12.0 : 0.0;
    const double per_frame_vertex = 24.0 + shading + (scene.color ? 12.0 : 0.0);
    const double indices = 12.0 * static_cast<double>(e.triangles), uv0 = 8.0 * n;
    constexpr double kMeshoptShare = 0.5;  // EXT_meshopt_compression's bytes over the floats' (measured: docs/export.md)
    const double draco_frame = 9.2 * n;  // measured: default scene (the water mesh), 14-bit positions (see RunEstimate)
    e.output_bytes = export_form(scene.form).output_bytes(ExportSizing{
        .frames = frames, .vertices = n, .per_frame_vertex = per_frame_vertex, .indices = indices, .uv0 = uv0,
        .draco_frame = draco_frame, .meshopt_share = kMeshoptShare, .draco = scene.draco.has_value(), .quantize = scene.quantize,
        .meshopt = scene.meshopt, .shaded = shaded});
    // The seafloor beside the water (morph and nodes files; the files form's frame 0):
    // float positions and colours and the triangles of a grid of at most 256 a side.
    const ElevationGrid& g = plan.seafloor.grid;
    if (scene.dress_seafloor && surface_kind_traces(scene.surface_kind) != Traced::nothing && g.nx >= 2 && g.ny >= 2) {
        const double step = static_cast<double>(std::max<std::size_t>(1, (std::max(g.nx, g.ny) + 255) / 256));
        const double cols = std::floor(static_cast<double>(g.nx - 1) / step) + 1.0, rows = std::floor(static_cast<double>(g.ny - 1) / step) + 1.0;
        e.output_bytes += 24.0 * cols * rows + 24.0 * (cols - 1.0) * (rows - 1.0);
    }
    // The caustic maps (/underwater): a PNG per frame, ~1.2 bytes a pixel (measured on a
    // 1024² map of a breeze-driven sea: 1.17 MB); while a frame is computed, its map
    // (4 bytes a pixel) and the PNG's 16-bit pixels (2).
    double caustic_work = 0.0;
    if (scene.underwater && scene.underwater->caustics && g.nx >= 2 && g.ny >= 2) {
        const CausticOptions o = scene_caustic_options(scene, plan);
        const double pixels = static_cast<double>(o.width) * static_cast<double>(o.height);
        e.output_bytes += frames * 1.2 * pixels;
        caustic_work = 6.0 * pixels;
    }
    if (g.nx >= 2 && g.ny >= 2) {  // the sunbeam volumes (kSunbeam…BytesPerVoxel)
        e.output_bytes += frames * kSunbeamFileBytesPerVoxel * sunbeam_voxels(scene);
        caustic_work += kSunbeamWorkBytesPerVoxel * sunbeam_voxels(scene);
    }
    // Without a measured plan: ~30 MB of process and libraries, ~1.5 kB per surface
    // vertex of plan (isobaths, fronts, the OpenMesh strips, motion fields), measured on
    // the default scene. Refinement stencils ~12 weights per fine vertex; a quantised
    // single file holds its bytes twice at the end (the buffer and the file's string),
    // the files form one chunk of frames, a streamed form one chunk and one frame.
    const double planned = planned_resident_bytes > 0.0 ? planned_resident_bytes : 30e6 + 1500.0 * static_cast<double>(plan.rest_x.size());
    // While frames run, ~12 MB more than a process that has only planned: the export's
    // and Draco's code and buffers, the worker threads' stacks (measured over the
    // examples, bench/memory_estimate.py).
    // Draco's encoder holds ~650 B a vertex while it compresses a frame (measured: the
    // open ocean, the Okushiri coast).
    // A run's own state beside the plan: the normals' vertex–face adjacency (~32 B a
    // vertex) and, with an FFT ocean, its transform buffers (4 pairs' complex N² and
    // the frame's h̃: ~40 B a lattice cell).
    const double lattice = static_cast<double>(plan.ocean.n) * static_cast<double>(plan.ocean.n);
    // Frames side by side below kLaneVertices: a run's state per lane.
    const double lanes = static_cast<double>(detail::frame_lanes(scene, e.vertices, static_cast<std::size_t>(frames)));
    const double run_state = lanes * (32.0 * n + 40.0 * lattice);
    const double base = planned + 12e6 + run_state + (fine ? 96.0 * n : 0.0) + caustic_work + (scene.draco ? 650.0 * n : 0.0);
    // The ray strips' PLY, written when the frames are done: their OpenMesh TriMesh and
    // the file's bytes (~400 B a strip vertex, measured on Gonzato's island).
    const double ply = 400.0 * static_cast<double>(plan.strips.vertex_count());
    const double chunk = std::min(frames, static_cast<double>(files_form_chunk(e)));
    if (scene.form == Scene::Form::files) {  // one chunk of frames at a time, each frame encoded and written alone
        e.peak_memory_bytes = base + std::max(ply, run_arrays * chunk / frames + 2.0 * e.output_bytes / frames);
    } else if (streamed_form(scene)) {
        // One chunk of frames, one frame's attributes being encoded (twice: glTF axes and
        // deltas), the one-hot weights or scales (frames² floats) and the glTF JSON's
        // model (~6 kB a frame while tinygltf and nlohmann serialise it at the end).
        const double frame_out = (e.output_bytes - (scene.form == Scene::Form::pc2 ? 2.0 * (n * per_frame_vertex + uv0 + indices) : 0.0)) / frames;
        e.peak_memory_bytes = base + std::max(ply, run_arrays * chunk / frames + 2.0 * frame_out + 4.0 * frames * frames + 6e3 * frames);
    } else {  // every frame's arrays, and the encoded files held until they are published
        e.peak_memory_bytes = base + run_arrays + 2.0 * e.output_bytes + ply;
    }
    return e;
}

namespace {

// What lowers a run's memory, or raises its limit: the end of both memory refusals.
std::string memory_advice(const Scene& scene) {
    return (scene.refine ? std::string("lower /refine/level, or ") : std::string()) +
           (scene.camera_grid ? std::string("raise /surface/camera_grid/pixel_step or lower /surface/camera_grid/image, or ")
                              : std::string()) +
           (scene.quantize && scene.form != Scene::Form::morph
                ? std::string("use the morph form or drop /outputs/quantize (quantised nodes files are written whole), or ")
                : std::string()) +
           std::string(detail::surface_model(scene.surface_kind).size_keys) + ", or raise the limit (wave run --max-memory-gb)";
}

}  // namespace

double planned_memory_floor_bytes(const Scene& scene) {
    if (!scene.ocean) return 0.0;
    // The lattice: h̃0, conj h̃0(−k) (complex float), ω (double), ω̄ steps (int32); the
    // workspace: eight half spectra (complex float) and eight real fields (float).
    const double n = static_cast<double>(scene.ocean->resolution), lattice = (8.0 + 8.0 + 8.0 + 4.0) * n * n,
                 workspace = 8.0 * 8.0 * n * (n / 2.0 + 1.0) + 8.0 * 4.0 * n * n;
    const bool shaded = scene.attributes != Scene::Attributes::none;
    const double frame = detail::surface_model(scene.surface_kind).wind_sea_patch
                             ? (n + 1.0) * (n + 1.0) * (24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0))
                             : 0.0;
    return lattice + workspace + frame;
}

void check_plan_limits(const Scene& scene, double max_bytes) {
    // A camera grid's vertices, from the scene alone: every pixel_step-th pixel of every
    // row (rows that miss the water are dropped later; a bound, not a guess), at what a
    // run of one holds a vertex at its peak (the plan's arrays, the breakers resampled on
    // it, one frame and its file: estimate_run has 4 GB for 16 M vertices; 260 bytes, a margin over it).
    // At the schema's 10⁸ pixels and step 1, validate built 13 GB of plan before a limit
    // named other keys; at 16 M vertices it planned 2.2 GB before refusing the run's 4 GB.
    if (scene.camera_grid && scene.camera_grid->pixel_step > 0) {
        const GridCamera& c = *scene.camera_grid;
        const double columns = std::ceil(static_cast<double>(c.image_width) / static_cast<double>(c.pixel_step)),
                     rows = std::ceil(static_cast<double>(c.image_height) / static_cast<double>(c.pixel_step));
        const double per_vertex = 260.0;
        if (const double bytes = columns * rows * per_vertex; bytes > max_bytes)
            throw LimitError("scene: /surface/camera_grid/image [" + std::to_string(c.image_width) + ", " + std::to_string(c.image_height) +
                             "] at /surface/camera_grid/pixel_step " + std::to_string(c.pixel_step) + " samples up to " +
                             detail::format_count(static_cast<std::size_t>(columns * rows)) + " vertices, about " +
                             fmt(std::ceil(bytes / 1e7) / 100.0) + " GB at a run's peak (" + fmt(per_vertex) +
                             " bytes a vertex), over the limit of " + fmt(max_bytes / 1e9) +
                             " GB; raise /surface/camera_grid/pixel_step or lower /surface/camera_grid/image, or raise the limit "
                             "(wave run --max-memory-gb)");
    }
    if (const double volume = kSunbeamWorkBytesPerVoxel * sunbeam_voxels(scene); volume > max_bytes) {
        const SunVolumeOptions& o = *scene.underwater->sunbeams;
        throw LimitError("scene: /underwater/sunbeams/voxels [" + std::to_string(o.nx) + ", " + std::to_string(o.ny) + ", " +
                         std::to_string(o.nz) + "] need about " + fmt(std::ceil(volume / 1e7) / 100.0) +
                         " GB while a frame is computed (16 bytes a voxel), over the limit of " + fmt(max_bytes / 1e9) +
                         " GB; give fewer voxels, or raise the limit (wave run --max-memory-gb)");
    }
    const double floor = planned_memory_floor_bytes(scene);
    if (floor > max_bytes)
        throw LimitError("scene: /ocean/resolution " + std::to_string(scene.ocean->resolution) + " needs at least " +
                         fmt(std::ceil(floor / 1e7) / 100.0) + " GB before its first frame is written (its lattice, transforms" +
                         (detail::surface_model(scene.surface_kind).wind_sea_patch ? " and one frame" : "") + "), over the limit of " +
                         fmt(max_bytes / 1e9) + " GB; lower /ocean/resolution, or raise the limit (wave run --max-memory-gb)");
}

void check_run_limits(const Scene& scene, const RunEstimate& e, std::size_t frames, double max_bytes) {
    if (e.frames > scene.max_frames)
        throw LimitError("scene: the loop holds " + detail::format_count(e.frames) + " frames (at " + fmt(scene.fps) +
                         " fps), more than the limit of " + detail::format_count(scene.max_frames) +
                         "; lower /animation/fps, or raise /animation/max_frames");
    const bool shaded = scene.attributes != Scene::Attributes::none;
    const double bytes_per_vertex = 24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0);
    if (static_cast<double>(frames) * static_cast<double>(e.vertices) * bytes_per_vertex > max_bytes)
        throw LimitError("scene: the animation would hold " + detail::format_count(frames) + " frames of " +
                         detail::format_count(e.vertices) + " vertices (over " + fmt(max_bytes / 1e9) +
                         " GB of per-frame arrays); " + memory_advice(scene));
    // The whole run's peak (a streamed run holds a chunk of frames, but its plan, e.g. a
    // subdivision's stencils, can still outgrow the machine).
    if (e.peak_memory_bytes > max_bytes)
        throw LimitError("scene: a run would need about " + fmt(std::ceil(e.peak_memory_bytes / 1e7) / 100.0) +
                         " GB of memory at its peak (" + detail::format_count(e.vertices) + " vertices: the plan, " +
                         detail::format_count(frames) + (frames == 1 ? " frame" : " frames") +
                         " at a time and the files), over the limit of " + fmt(max_bytes / 1e9) + " GB; " + memory_advice(scene));
}

std::size_t files_form_chunk(const RunEstimate& e, double max_bytes) {
    if (e.frames == 0) return 1;
    const double per_frame = e.frame_array_bytes / static_cast<double>(e.frames);
    const double by_memory = per_frame > 0.0 ? std::floor(std::min(max_bytes, 256e6) / per_frame) : static_cast<double>(e.frames);
    const std::size_t spread = std::max<std::size_t>(8, (e.frames + 63) / 64);
    const std::size_t chunk = by_memory < static_cast<double>(spread) ? static_cast<std::size_t>(std::max(1.0, by_memory)) : spread;
    return std::min(chunk, e.frames);
}

}  // namespace wave
