// The `wave` subcommands, free of CLI11 so that only main.cpp pays its compile time.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/inspect.h"

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace wave::cli {

struct DispersionArgs {
    double period = 0.0;
    double depth = 0.0;
    double capillary_length = 0.0;
    double deep_height = 0.0;  ///< optional H∞ (m) to report the shoaled height and breaking
    bool json = false;
};
int run_dispersion(const DispersionArgs& a);

struct SeafloorArgs {
    std::string source;  ///< file path or procedural name
    ReadOptions read;
    bool json = false;
};
int run_seafloor_info(const SeafloorArgs& a);

struct ContoursArgs {
    SeafloorArgs seafloor;
    std::vector<double> levels;
    double level_spacing = 0.0;
    bool no_shoreline = false;
    int smooth_samples = 0;
    double beta1 = 1.0, beta2 = 0.0;
    std::string output;  ///< .json (our contour format) or .obj (polylines)
};
int run_contours(const ContoursArgs& a);

struct TraceArgs {
    std::string scene;     ///< scene file
    std::string output;    ///< CSV of the rays (height field) or fronts (ray strips); optional
    std::string mesh_out;  ///< PLY of the ray strips with per-vertex properties; optional
    bool json = false;     ///< print a JSON summary
};
int run_trace(const TraceArgs& a);

/// `wave field`: the refraction–diffraction field of a scene's wave train.
struct FieldArgs {
    std::string scene;      ///< scene file; empty = the built-in default scene
    std::string output;     ///< GeoTIFF (bands H/H0, phase, direction); optional
    std::string png;        ///< plot of H/H0 with the depth contours; optional
    std::size_t train = 0;  ///< which of /waves
    bool json = false;      ///< print a JSON summary
    double max_memory_gb = 2.0;  ///< the grid's memory limit (GB)
};
int run_field(const FieldArgs& a);

struct RunArgs {
    std::string scene;   ///< scene file; empty = the built-in default scene
    std::string out_dir; ///< default: wave-out/<scene file stem or "default">
    int threads = 0;     ///< worker threads (0 = all cores); outputs do not depend on it
    std::string form;    ///< morph | nodes | files; empty = the scene's
    std::string frames;  ///< "A:B" slice of the loop's frames; empty = all
    std::string slice;   ///< "I/N": slice I of N equal slices of the loop (farm array jobs)
    double fps = 0.0;    ///< > 0 overrides the scene's fps
    bool draco = false;     ///< Draco-compress (whatever the scene says)
    bool no_draco = false;  ///< plain meshes (whatever the scene says)
    bool no_quantize = false;  ///< float attributes (whatever the scene says)
    std::string container;  ///< glb | gltf; empty = the scene's
    bool quantize = false;  ///< KHR_mesh_quantization
    /// auto | none | meshopt | draco | quantize; empty = the scene's (docs/export.md, "Which codec")
    std::string codec;
    bool quiet = false;  ///< no progress bar and no text report
    bool json = false;
    bool preview = false;  ///< also write preview.png: a contact sheet of four frames
    bool view = false;     ///< then serve the output in the viewer (wave view)
    double max_memory_gb = 2.0;  ///< refuse animations whose frame arrays exceed this
    bool resume = false;   ///< files form: keep the frames the index lists whose files still match it
    /// Remove every output an earlier run recorded in the folder (all reports' outputs,
    /// the index and frames/) before publishing; without it only the outputs the same
    /// report listed and this run does not write again are removed (stale ones).
    bool overwrite = false;
};
int run_job(const RunArgs& a);
/// Where run_job writes: --out, else wave-out/<scene file stem or "default">.
std::string run_out_dir(const RunArgs& a);

/// `wave view`: the outputs a path holds (a .glb/.gltf, index.json, or a folder with
/// animation*.glb/.gltf and/or index.json), relative to `root`.
struct ViewerOutputs {
    struct Output {
        std::string name;  ///< file name inside root
        std::string kind;  ///< "gltf" (morph or nodes form) or "index" (files form)
    };
    std::filesystem::path root;
    std::vector<Output> outputs;
    /// Loop frames with a whitewater file beside the outputs (whitewater/whitewater-NNNN.glb).
    std::vector<int> whitewater_frames;
};
/// Throws InputError naming the path when it holds none.
ViewerOutputs find_viewer_outputs(const std::string& path);

struct ViewArgs {
    std::string path;                ///< output folder or file
    std::string host = "127.0.0.1";
    int port = 8765;                 ///< 0 = any free port
    bool port_given = false;         ///< a busy --port is an error; a busy default falls back to any port
    bool open = true;                ///< hand the URL to xdg-open when a display is available
};
/// Serves the viewer until interrupted (SIGINT/SIGTERM); prints the URL.
int run_view(const ViewArgs& a);

/// `wave preview`: one frame of a scene rendered by the sunset ray caster to PNG.
struct PreviewArgs {
    std::string scene;  ///< empty = the built-in default scene
    std::size_t frame = 0;
    std::string output = "preview.png";
    std::size_t width = 0, height = 0;  ///< 0 = the scene's /preview/image
    double sun_azimuth = std::numeric_limits<double>::quiet_NaN(), sun_elevation = std::numeric_limits<double>::quiet_NaN();
    bool quiet = false;
};
int run_preview(const PreviewArgs& a);

/// `wave batch`: every scene of the inputs (files, folders of *.json, glob patterns)
/// run by its own `wave run` process into OUT/<file stem>, `jobs` at a time; a failed
/// scene does not stop the others. Writes OUT/batch-summary.json; returns 0 when all
/// succeeded, else 2 if any scene had bad input, else 1.
struct BatchArgs {
    std::vector<std::string> inputs;
    std::string out_dir = "wave-out/batch";
    int jobs = 1;
    std::vector<std::string> run_args;  ///< passed to every `wave run` (--form, --fps, …)
    bool quiet = false, json = false;
};
int run_batch(const BatchArgs& a);

/// `wave convert`: re-encodes an output of `wave run` (any form; its index.json for
/// the files form) into another form / compression / container without recomputing.
struct ConvertArgs {
    std::string input, out_dir;
    std::string form = "morph";  ///< morph | nodes | files
    std::string container = "glb";
    bool draco = false, quantize = false, meshopt = false, quiet = false, json = false;
};
int run_convert(const ConvertArgs& a);

/// `wave merge OUT`: rebuilds OUT/index.json of the files form from the frame files
/// present (each records its animation and frame), e.g. after slices ran on several
/// machines at once. Refuses frames of different animations and, unless `partial`, a
/// loop with frames missing (naming the first).
struct MergeArgs {
    std::string out_dir;
    bool partial = false, quiet = false;
};
int run_merge(const MergeArgs& a);

/// `wave inspect`: folds, lips, slivers, boundary loops and vertex speeds of an output
/// of `wave run` (a folder, a .glb/.gltf or the files form's index.json), every frame.
struct InspectArgs {
    std::string path;
    InspectOptions options;
    bool json = false;
    /// --against REF: compare the positions of `path` (e.g. a compressed output) with
    /// REF's (a float run of the same scene), frame by frame, instead of inspecting.
    std::string against;
    /// --scene SCENE: the scene `path` was run from; its breakers say which triangles
    /// facing down are the lips they draw (InspectOptions::drawn_lips), not the foam.
    std::string scene;
};
int run_inspect(const InspectArgs& a);

/// Checks a scene file (JSON, keys, values, the seafloor source, the camera) without
/// running it; prints what it would do.
int run_validate(const std::string& scene, bool json, double max_memory_gb);

/// Prints the scene JSON Schema (docs/scene.schema.json).
int run_schema();

}  // namespace wave::cli
