// The `wave` subcommands: parse nothing, compute nothing themselves — they call
// libwave and print what it returns.
#include "commands.h"
#include "outputs.h"

#include "libwave/errors.h"
#include "libwave/io.h"
#include "libwave/isobath.h"
#include "libwave/export.h"
#include "libwave/scene.h"
#include "libwave/shade.h"
#include "libwave/physics.h"
#include "libwave/version.h"

#include <nlohmann/json.hpp>
#include <unistd.h>
#include <csignal>
#include <cerrno>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cstring>
#include <cmath>
#include <sstream>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <optional>

namespace wave::cli {

using nlohmann::json;

int run_dispersion(const DispersionArgs& a) {
    DispersionOptions opt;
    opt.capillary_length = a.capillary_length;
    const double omega = 2.0 * std::numbers::pi / a.period;
    const LinearWave w = linear_wave(omega, a.depth, opt);
    const double deep_wavelength = deep_water_wavelength(a.period);
    json j{{"period_s", a.period},
           {"depth_m", a.depth},
           {"dry", w.dry},
           {"k_rad_per_m", w.k},
           {"wavelength_m", w.wavelength},
           {"deep_wavelength_m", deep_wavelength},
           {"celerity_m_per_s", w.celerity},
           {"group_velocity_m_per_s", w.group_velocity},
           {"shoaling_coefficient", w.shoaling}};
    if (a.deep_height > 0.0) {
        const double height = a.deep_height * w.shoaling;
        j["deep_height_m"] = a.deep_height;
        j["height_m"] = height;
        j["breaking"] = is_depth_limited_breaking(height, a.depth);
    }
    if (a.json) {
        std::cout << j.dump(2) << '\n';
        return 0;
    }
    std::cout << std::setprecision(6);
    if (w.dry) {
        std::cout << "depth " << a.depth << " m is dry (h <= 0): no wave\n";
        return 0;
    }
    std::cout << "period T          " << a.period << " s\n"
              << "depth h           " << a.depth << " m\n"
              << "wavenumber k      " << w.k << " rad/m\n"
              << "wavelength L      " << w.wavelength << " m  (deep water L0 = " << deep_wavelength << " m)\n"
              << "celerity C        " << w.celerity << " m/s\n"
              << "group velocity Cg " << w.group_velocity << " m/s\n"
              << "shoaling Ks       " << w.shoaling << '\n';
    if (a.deep_height > 0.0)
        std::cout << "height H          " << j["height_m"].get<double>() << " m (H0 = " << a.deep_height
                  << " m); " << (j["breaking"].get<bool>() ? "breaking (H >= 0.78 h)" : "not breaking")
                  << '\n';
    return 0;
}

int run_seafloor_info(const SeafloorArgs& a) {
    const Seafloor s = load_seafloor(SeafloorSource{a.source, a.read});
    const SeafloorStats st = seafloor_stats(s);
    if (a.json) {
        json j{{"source", s.source},
               {"frame", s.frame},
               {"nodes", {st.nx, st.ny}},
               {"extent_m", {{"x", {st.x_min, st.x_max}}, {"y", {st.y_min, st.y_max}}}},
               {"spacing_m", {st.dx, st.dy}},
               {"depth_range_m", {st.depth_min, st.depth_max}},
               {"land_fraction", st.land_fraction},
               {"nodata_count", st.nodata_count},
               {"mesh_triangles", st.mesh_triangles},
               {"contour_lines", st.contour_lines}};
        std::cout << j.dump(2) << '\n';
        return 0;
    }
    std::cout << std::setprecision(6)
              << "source        " << s.source << '\n'
              << "frame         " << s.frame << '\n'
              << "grid          " << st.nx << " x " << st.ny << " nodes\n"
              << "extent        x " << st.x_min << " .. " << st.x_max << " m, y " << st.y_min
              << " .. " << st.y_max << " m\n"
              << "spacing       " << st.dx << " x " << st.dy << " m\n"
              << "depth         " << st.depth_min << " .. " << st.depth_max << " m (positive down)\n"
              << "land          " << std::setprecision(4) << 100.0 * st.land_fraction << " % of nodes\n"
              << "NODATA nodes  " << st.nodata_count << '\n';
    if (st.mesh_triangles) std::cout << "mesh          " << st.mesh_triangles << " triangles (kept for slicing)\n";
    if (st.contour_lines) std::cout << "contours      " << st.contour_lines << " polylines\n";
    return 0;
}

int run_contours(const ContoursArgs& a) {
    std::string ext = std::filesystem::path(a.output).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".json" && ext != ".obj")
        throw InputError(a.output + ": the output must end in .json (libwave contours) or .obj (polylines)");
    const Seafloor sea = load_seafloor(SeafloorSource{a.seafloor.source, a.seafloor.read});
    IsobathOptions o;
    o.levels = a.levels;
    o.spacing = a.level_spacing;
    o.include_shoreline = !a.no_shoreline;
    o.smoothing_samples = a.smooth_samples;
    o.smoothing_beta1 = a.beta1;
    o.smoothing_beta2 = a.beta2;
    const DepthContours c = extract_isobaths(sea, o);
    write_file_atomic(a.output, ext == ".json" ? contours_to_json(c) : contours_to_obj(c));
    std::size_t points = c.offsets.empty() ? 0 : c.offsets.back();
    std::size_t closed = 0;
    for (auto f : c.closed) closed += f;
    std::cout << "sliced " << sea.source << " into " << c.size() << " isobaths (" << closed << " closed, "
              << points << " points); wrote " << a.output << '\n';
    return 0;
}

namespace {

// What the tracing stage produced, for reports.
// Where the traced rays break (Jeschke's automatic parametrisation).
json breakers_summary(const JeschkeMotionPlan& b) {
    std::size_t breaking = 0, rays = 0, again = 0;  // first breaks; breaks after a re-form
    double h_min = std::numeric_limits<double>::infinity(), h_max = 0.0;
    std::map<std::string, std::size_t> types;
    for (const RayBreak& r : b.rays) {
        if (r.surf_zone == 0) ++rays;
        if (!r.breaks) continue;
        if (r.surf_zone == 0) ++breaking;
        else ++again;
        h_min = std::min(h_min, r.depth);
        h_max = std::max(h_max, r.depth);
        ++types[to_string(r.type)];
    }
    json out{{"model", "jeschke"}, {"rays", rays}, {"breaking_rays", breaking}, {"breaks_after_reforming", again},
             {"breaker_types", types}};
    if (breaking > 0) out["break_depth_m"] = {h_min, h_max};
    out["varied_waves"] = b.loop_periods();  // the loop holds this many swell periods
    out["wave_variation"] = b.variation;
    return out;
}

json trace_summary(const Scene& scene, const ScenePlan& plan) {
    const Traced traced = surface_kind_traces(scene.surface_kind);
    if (traced == Traced::nothing) return json::object();
    if (traced == Traced::field) {
        json fields = json::array();
        for (const WaveField& f : plan.wave_fields)
            fields.push_back({{"nodes", {f.nx, f.ny}}, {"spacing_m", f.dx}, {"incident_height_m", f.incident_height},
                              {"broken_nodes", f.broken_nodes}});
        return {{"mode", "wave field (wide-angle parabolic mild-slope)"}, {"fields", fields}};
    }
    if (traced == Traced::fronts) {
        const FrontSet& f = plan.fronts;
        return {{"mode", scene.fronts.refraction == FrontRefraction::gradient ? "gonzato-fronts (gradient refraction)"
                                                                             : "gonzato-fronts (exact isobath crossings)"},
                {"initial_rays", f.initial_rays},
                {"inserted_rays", f.inserted_rays},
                {"rays_aground", f.rays_aground},
                {"rays_trapped", f.rays_trapped},
                {"caustic_points", f.caustic_points},
                {"steps", f.front_count() - 1},
                {"points", f.x.size()},
                {"vertices", plan.strips.vertex_count()},
                {"triangles", plan.strips.triangle_count()},
                {"degenerate_cells_skipped", plan.strips.degenerate_skipped}};
    }
    const RaySet& r = plan.rays;
    std::size_t aground = 0, capped = 0, doubtful = 0, reflected = 0, crossings = 0;
    for (std::size_t i = 0; i < r.ray_count(); ++i) aground += r.event[r.offsets[i + 1] - 1] == RayEvent::aground;
    for (std::size_t i = 0; i < r.point_count(); ++i) {
        capped += (r.flags[i] & kAmplitudeCapped) != 0;
        doubtful += (r.flags[i] & kRefractionDoubtful) != 0;
        reflected += r.event[i] == RayEvent::reflected;
        crossings += r.event[i] == RayEvent::refracted || r.event[i] == RayEvent::reflected;
    }
    return {{"mode", "tso-barsky (exact isobath crossings)"}, {"rays", r.ray_count()}, {"crossings", crossings},
            {"rays_aground", aground}, {"reflections", reflected}, {"amplitude_capped_points", capped},
            {"refraction_doubtful_points", doubtful}};
}

}  // namespace

int run_trace(const TraceArgs& a) {
    if (a.output.empty() && a.mesh_out.empty() && !a.json)
        throw InputError("trace: nothing to do; give -o CSV, --mesh-out PLY and/or --json");
    const Scene scene = read_scene(a.scene);
    const Traced traced = surface_kind_traces(scene.surface_kind);
    const bool strips = traced == Traced::fronts;
    if (traced == Traced::nothing || traced == Traced::field)
        throw InputError(a.scene + ": the " + std::string(surface_kind_name(scene.surface_kind)) +
                         " surface (/surface/kind) traces no rays; use wave run" + (traced == Traced::field ? " or wave field" : ""));
    if (!a.mesh_out.empty() && !strips)
        throw InputError(a.scene + ": --mesh-out needs the ray-strips surface (this scene's /surface/kind is " +
                         std::string(surface_kind_name(scene.surface_kind)) + ")");
    const ScenePlan plan = plan_scene(scene, PlanStages::trace);  // no surface or motion plan
    if (!a.output.empty()) write_file_atomic(a.output, strips ? fronts_to_csv(plan.fronts) : rays_to_csv(plan.rays));
    if (!a.mesh_out.empty()) write_ray_strips_ply(plan.strips, a.mesh_out);
    const json summary = trace_summary(scene, plan);
    if (a.json) {
        std::cout << summary.dump(2) << '\n';
        return 0;
    }
    if (strips)
        std::cout << "traced " << plan.fronts.initial_rays << " rays (+" << plan.fronts.inserted_rays << " inserted, "
                  << plan.fronts.rays_aground << " aground) over " << plan.fronts.front_count() - 1 << " steps -> "
                  << plan.strips.vertex_count() << " vertices, " << plan.strips.triangle_count() << " triangles\n";
    else
        std::cout << "traced " << plan.rays.ray_count() << " rays (" << plan.rays.point_count() << " points) over "
                  << plan.isobaths.size() << " isobaths\n";
    if (!a.output.empty()) std::cout << "wrote " << a.output << '\n';
    if (!a.mesh_out.empty()) std::cout << "wrote " << a.mesh_out << '\n';
    return 0;
}

namespace {

// "A:B" → [A, B); empty → everything.
// A non-negative whole number, or InputError(`usage`).
std::size_t whole_number(const std::string& part, const std::string& usage) {
    if (part.empty() || part.size() > 18 || part.find_first_not_of("0123456789") != std::string::npos) throw InputError(usage);
    return std::stoull(part);
}

FrameRange parse_frames(const std::string& text) {
    if (text.empty()) return {};
    const auto colon = text.find(':');
    const auto whole = [&](const std::string& part) {
        return whole_number(part, "--frames: expected A:B with whole numbers A < B, got \"" + text + "\"");
    };
    if (colon == std::string::npos) throw InputError("--frames: expected A:B, got \"" + text + "\"");
    FrameRange r{whole(text.substr(0, colon)), whole(text.substr(colon + 1))};
    if (r.first >= r.end) throw InputError("--frames: the range " + text + " is empty (A must be < B)");
    return r;
}

// "I/N" → slice I of N of a loop of `loop_frames`: frames [I·F/N, (I+1)·F/N).
FrameRange slice_frames(const std::string& text, std::size_t loop_frames) {
    const auto slash = text.find('/');
    const auto whole = [&](const std::string& part) {
        return whole_number(part, "--slice: expected I/N with whole numbers 0 <= I < N, got \"" + text + "\"");
    };
    if (slash == std::string::npos) throw InputError("--slice: expected I/N, got \"" + text + "\"");
    const std::size_t i = whole(text.substr(0, slash)), n = whole(text.substr(slash + 1));
    if (n == 0 || i >= n) throw InputError("--slice: expected 0 <= I < N, got \"" + text + "\"");
    if (n > loop_frames)
        throw InputError("--slice " + text + ": the loop has only " + std::to_string(loop_frames) + " frames; use at most " +
                         std::to_string(loop_frames) + " slices");
    return {i * loop_frames / n, (i + 1) * loop_frames / n};
}

// The report of a run of frames [first, first + count) that is not the whole loop.
std::string slice_report_name(std::size_t first, std::size_t count) {
    return "report-frames-" + std::to_string(first) + "-" + std::to_string(first + count) + ".json";
}

}  // namespace

namespace {

// What decides the bytes of a run's frames: libwave's version, the scene file (or the
// built-in scene), the command-line overrides and the seafloor's heights (a scene
// naming a data file that changed gets another key). Threads do not count: outputs do
// not depend on them.
std::string run_key(const RunArgs& a, const Scene& scene, const ScenePlan& plan) {
    std::string source;
    if (a.scene.empty()) {
        source = "built-in default scene\n";
    } else {
        std::ifstream in(a.scene, std::ios::binary);
        source.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    return scene_run_key(scene, plan, source);
}

}  // namespace

std::string run_out_dir(const RunArgs& a) {
    if (!a.out_dir.empty()) return a.out_dir;
    return "wave-out/" + (a.scene.empty() ? std::string("default") : std::filesystem::path(a.scene).stem().string());
}

namespace {

// The scene of a run: the file's (or the built-in one) with the command line's overrides.
Scene run_scene(const RunArgs& a) {
    Scene scene = a.scene.empty() ? default_scene() : read_scene(a.scene);
    if (a.fps > 0.0) scene.fps = a.fps;
    if (!a.form.empty()) scene.form = form_from_name(a.form);
    if (a.draco && !scene.draco) scene.draco = DracoOptions{};
    if (a.no_draco) scene.draco.reset();
    if (a.quantize) scene.quantize = true;
    // Draco asked for on the command line replaces a scene's quantisation (it quantises
    // itself); so does another form than morph (a scene quantises its morph file, whose
    // float base keeps the far field; quantised frames of their own would drop it).
    const bool other_form = !a.form.empty() && scene.form != Scene::Form::morph;
    if (a.no_quantize || ((a.draco || other_form) && !a.quantize)) scene.quantize = false;
    if (scene.draco && scene.quantize) throw InputError("choose --draco or --quantize, not both (Draco quantises itself)");
    // --no-draco / --no-quantize ask for plain floats: no codec chosen by size either.
    if (a.no_draco || a.no_quantize || a.draco || a.quantize) scene.codec_auto = scene.meshopt = false;
    if (!a.codec.empty()) {
        scene.codec_auto = a.codec == "auto";
        scene.meshopt = a.codec == "meshopt";
        scene.quantize = a.codec == "quantize";
        if (a.codec == "draco") {
            if (!scene.draco) scene.draco = DracoOptions{};
        } else {
            scene.draco.reset();
        }
    }
    if (!a.container.empty()) scene.container = container_from_name(a.container);
    if (!a.frames.empty() && !a.slice.empty()) throw InputError("choose --frames or --slice, not both");
    if (a.resume && scene.form != Scene::Form::files)
        throw InputError("--resume continues a run of the files form (one file per frame); this run's form is " +
                         std::string(form_name(scene.form)));
    return scene;
}

// A progress bar on stderr when it is a terminal.
std::function<void(std::size_t, std::size_t)> progress_bar(const RunArgs& a) {
    if (a.quiet || a.json || !isatty(STDERR_FILENO)) return {};
    return [](std::size_t done, std::size_t total) {
        const int width = 40, filled = static_cast<int>(width * done / total);
        std::cerr << "\rframes [" << std::string(static_cast<std::size_t>(filled), '#')
                  << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << done << "/" << total
                  << (done == total ? "\n" : "") << std::flush;
    };
}

// Everything a run did and wrote: printed as report.json, as JSON on stdout, or as text.
struct RunSummary {
    const Scene& scene;
    const ScenePlan& plan;
    std::string out_dir, run_key, report_name;
    std::size_t vertices = 0, triangles = 0, frames = 0, first_frame = 0, loop_frames = 0;
    float z_min = 0.0f, z_max = 0.0f;
    std::vector<std::string> animation_names{};  ///< the animation's files (and the files form's index)
    std::size_t animation_bytes = 0;
    std::vector<std::string> side_files{};        ///< isobaths, the trace, frame 0's OBJ, the report
    double plan_ms = 0.0, frames_ms = 0.0, export_ms = 0.0;
    const FilesFormRun* files_run = nullptr;
    bool resumed = false;  ///< --resume: say what was kept
};

// The codec a (resolved) scene's glTF output uses, as /outputs/codec names it.
const char* codec_name(const Scene& scene) {
    return scene.meshopt ? "meshopt" : scene.draco ? "draco" : scene.quantize ? "quantize" : scene.codec_auto ? "auto" : "none";
}

json surface_summary(const RunSummary& r) {
    const Scene& scene = r.scene;
    const ScenePlan& plan = r.plan;
    json surface{{"kind", surface_kind_name(scene.surface_kind)},
                 {"vertices", r.vertices},
                 {"triangles", r.triangles},
                 {"loop_period_s", plan.loop_period},
                 {"fps", scene.fps},
                 {"frames", r.frames},
                 {"first_frame", r.first_frame},
                 {"loop_frames", r.loop_frames},
                 {"form", form_name(scene.form)},
                 {"draco", scene.draco.has_value()},
                 {"quantized", scene.quantize},
                 {"codec", codec_name(scene)},
                 {"shading", scene.attributes == Scene::Attributes::none ? "none"
                             : scene.attributes == Scene::Attributes::named ? "named" : "uv-maps"},
                 {"height_range_m", {r.z_min, r.z_max}}};
    if (plan.surface.nx > 0) surface["control_grid"] = {plan.surface.nx, plan.surface.ny};
    if (plan.ocean.n > 0) {
        const OceanOptions& o = *scene.ocean;
        surface["wind_sea"] = {{"resolution", plan.ocean.n},
                               {"size_m", plan.ocean.size},
                               {"repeat_time_s", plan.ocean.repeat_time},
                               {"choppiness", plan.ocean.choppiness},
                               {"wind_speed_m_s", o.spectrum.wind_speed},
                               {"significant_height_m", 4.0 * std::sqrt(plan.ocean.expected_variance)},
                               {"fold_threshold", plan.fold_foam.threshold}};
        if (plan.whitecap_coverage > 0.0) surface["wind_sea"]["whitecap_coverage"] = plan.whitecap_coverage;
    }
    if (!plan.gerstner.empty()) surface["gerstner_waves"] = plan.gerstner.size();
    if (!plan.breakers.rays.empty()) surface["breakers"] = breakers_summary(plan.breakers);
    if (plan.water_mesh.vertex_count() > 0)
        surface["water_mesh"] = {{"vertices_per_wavelength", scene.water_mesh_per_wavelength.value_or(0.0)},
                                 {"vertices", plan.water_mesh.vertex_count()},
                                 {"triangles", plan.water_mesh.triangles.size() / 3}};
    if (plan.skirt.vertex_count() > 0)
        surface["far_field"] = {{"vertices", plan.skirt.vertex_count()},
                                {"triangles", plan.skirt.triangles.size() / 3},
                                {"distance_m", plan.skirt.reach},
                                {"components", plan.far_field.component_count()},
                                {"anchors", plan.far_field.anchor_vertex.size()},
                                {"breaker_vertices", plan.skirt_breakers.vertex_count()}};
    if (plan.camera_grid.vertex_count() > 0)
        surface["camera_grid"] = {{"columns", plan.camera_grid.columns}, {"rows", plan.camera_grid.rows}};
    if (scene.refine)
        surface["refine"] = {{"scheme", scene.refine->scheme == RefineScheme::loop ? "loop" : "catmull-clark"},
                             {"level", scene.refine->level},
                             {"adaptive", scene.refine->adaptive},
                             {"crest_sharpness_per_metre", scene.refine->crest_sharpness_per_metre},
                             {"coarse_vertices", plan.rest_x.size()}};
    return surface;
}

// report.json: byte-identical from run to run (no timings).
json run_report(const RunSummary& r) {
    const SeafloorStats st = seafloor_stats(r.plan.seafloor);
    json report{{"libwave", version()},
                {"scene", r.scene.name},
                {"run_key", r.run_key},
                {"seafloor", {{"source", r.plan.seafloor.source}, {"nodes", {st.nx, st.ny}}, {"depth_range_m", {st.depth_min, st.depth_max}}}},
                {"isobaths", r.plan.isobaths.size()},
                {"trace", trace_summary(r.scene, r.plan)},
                {"surface", surface_summary(r)},
                {"warnings", r.plan.warnings},
                {"outputs", json::array()}};
    if (r.scene.underwater && r.scene.underwater->caustics) {
        const CausticOptions o = scene_caustic_options(r.scene, r.plan);
        report["underwater"] = {{"caustic_maps", kCausticImages}, {"map_size", {o.width, o.height}},
                                {"attenuation_per_m", o.attenuation}, {"full_scale", r.scene.underwater->full_scale},
                                {"sun_towards", o.sun}};
    }
    if (r.scene.underwater && r.scene.underwater->sunbeams) {
        const SunVolumePlan v = plan_sun_volume(plan_caustics(r.plan.seafloor.grid, scene_caustic_options(r.scene, r.plan)),
                                                *r.scene.underwater->sunbeams);
        report["underwater"]["sunbeam_volumes"] = kSunbeamVolumes;
        report["underwater"]["voxels"] = {v.nx, v.ny, v.nz};
        report["underwater"]["voxel_size_m"] = {v.dx, v.dy, v.dz};
        report["underwater"]["volume_bottom_m"] = v.z0;
    }
    if (r.scene.whitewater) {
        json sources = whitewater_sources(r.scene);
        report["whitewater"] = {{"points", kWhitewaterPoints}, {"sources", sources}, {"breaker_events", r.plan.whitewater.size()},
                                {"breaker_events_repeat_s", r.plan.whitewater.period}};
    }
    for (const std::string& f : r.animation_names) report["outputs"].push_back(f);
    for (const std::string& f : r.side_files) report["outputs"].push_back(f);
    return report;
}

void print_surface_text(const RunSummary& r) {
    const Scene& scene = r.scene;
    const ScenePlan& plan = r.plan;
    const std::size_t coarse_vertices = plan.rest_x.size();
    switch (surface_kind_traces(scene.surface_kind)) {
        case Traced::nothing:
            if (plan.ocean.n > 0 && plan.wind_sea_scale.empty())  // the surface is the FFT patch itself
                std::cout << "surface    ocean patch: " << plan.ocean.n << "² FFT (Tessendorf) over " << plan.ocean.size << " m -> "
                          << coarse_vertices << " vertices, Hs " << 4.0 * std::sqrt(plan.ocean.expected_variance) << " m\n";
            else
                std::cout << "surface    " << surface_kind_name(scene.surface_kind) << ": " << coarse_vertices << " vertices\n";
            break;
        case Traced::fronts:
            std::cout << "fronts     " << plan.fronts.initial_rays << " rays + " << plan.fronts.inserted_rays << " inserted, "
                      << plan.fronts.front_count() - 1 << " steps, " << plan.fronts.rays_aground << " aground (Gonzato)\n"
                      << "surface    ray strips: " << plan.strips.vertex_count() << " vertices, " << plan.strips.triangle_count()
                      << " triangles; " << strip_motion_name(scene) << '\n';
            break;
        case Traced::field:
            std::cout << "field      " << plan.wave_fields.size() << " train(s), wide-angle parabolic mild-slope, "
                      << plan.wave_fields[0].nx << " x " << plan.wave_fields[0].ny << " nodes -> " << coarse_vertices
                      << " vertices\n";
            break;
        case Traced::rays:
            std::cout << "rays       " << plan.rays.ray_count() << " traced (Ts'o-Barsky, exact isobath crossings)\n"
                      << "surface    " << plan.surface.nx << " x " << plan.surface.ny << " Beta2-spline control grid -> "
                      << coarse_vertices << " vertices\n";
            break;
    }
    if (plan.camera_grid.vertex_count() > 0)
        std::cout << "sampled    camera grid (Hinsinger): " << plan.camera_grid.columns << " x " << plan.camera_grid.rows
                  << " points seeing the water, " << plan.camera_grid.triangles.size() / 3 << " triangles\n";
    if (!plan.breakers.rays.empty()) {
        const json b = breakers_summary(plan.breakers);
        std::cout << "breakers   " << b["breaking_rays"].get<std::size_t>() << " of " << b["rays"].get<std::size_t>()
                  << " rays break";
        if (b.contains("break_depth_m"))
            std::cout << " in " << b["break_depth_m"][0].get<double>() << " .. " << b["break_depth_m"][1].get<double>()
                      << " m of water (H = γh), " << b["breaker_types"].dump();
        if (const auto again = b["breaks_after_reforming"].get<std::size_t>(); again > 0)
            std::cout << "; " << again << " breaks more after re-forming behind a surf zone";
        std::cout << '\n';
    }
    if (scene.refine)
        std::cout << "refined    OpenSubdiv " << (scene.refine->scheme == RefineScheme::loop ? "Loop" : "Catmull-Clark")
                  << (scene.refine->adaptive ? ", adaptive up to level " : ", level ") << scene.refine->level << ": "
                  << coarse_vertices << " -> " << r.vertices << " vertices, " << r.triangles << " triangles ("
                  << (scene.refine->crest_sharpness_per_metre > 0.0 ? "crest creases: refined again each frame"
                                                                    : "stencils applied per frame")
                  << ")\n";
    else
        std::cout << "mesh       " << r.vertices << " vertices, " << r.triangles << " triangles\n";
}

// The export form's summary (ExportFormInfo::summary) with its fields filled in.
std::string form_summary(std::string_view pattern, const std::string& first, std::size_t frames, std::size_t files) {
    std::string out(pattern);
    for (const auto& [key, value] : {std::pair<std::string_view, std::string>{"{first}", first}, {"{n}", std::to_string(frames)},
                                     {"{files}", std::to_string(files)}})
        for (std::size_t at = out.find(key); at != std::string::npos; at = out.find(key, at + value.size()))
            out.replace(at, key.size(), value);
    return out;
}

void print_run_text(const RunSummary& r) {
    const Scene& scene = r.scene;
    const ScenePlan& plan = r.plan;
    const SeafloorStats st = seafloor_stats(plan.seafloor);
    const bool traced = surface_kind_traces(scene.surface_kind) != Traced::nothing;
    std::cout << std::setprecision(4)
              << "scene      " << scene.name << '\n'
              << "seafloor   " << plan.seafloor.source << ", " << st.nx << " x " << st.ny << " nodes, depth "
              << st.depth_min << " .. " << st.depth_max << " m\n";
    if (traced) std::cout << "isobaths   " << plan.isobaths.size() << " polylines (CGAL slicer)\n";
    print_surface_text(r);
    const std::string shown_name = r.animation_names.empty() ? "" : r.animation_names.front();
    const std::size_t animation_files = r.animation_names.size() - (scene.form == Scene::Form::files ? 1 : 0);
    std::string side;
    for (const std::string& f : r.side_files) side += (side.empty() ? "" : ", ") + f;
    std::cout << "animation  " << r.frames << " frames at " << scene.fps << " fps, loop " << plan.loop_period
              << " s, heights " << r.z_min << " .. " << r.z_max << " m\n"
              << "time       plan " << r.plan_ms << " ms, frames " << r.frames_ms / static_cast<double>(std::max<std::size_t>(r.frames, 1))
              << (scene.form == Scene::Form::files || streamed_form(scene)
                      ? std::string(" ms each, each chunk written as it came\n")  // the frames' time holds the export
                      : " ms each, export " + std::to_string(static_cast<long long>(std::llround(r.export_ms))) + " ms\n")
              << "wrote      " << r.out_dir << "/"
              << form_summary(export_form(scene.form).summary_files, shown_name, r.frames, animation_files) << " ("
              << form_summary(export_form(scene.form).summary_contents, shown_name, r.frames, animation_files)
              << "; " << static_cast<double>(r.animation_bytes) / 1e6 << " MB; set the scene fps to " << scene.fps
              << " before importing)\n"
              << "           " << r.out_dir << "/{" << side << "}\n";
    if (r.resumed)
        std::cout << "resumed    " << r.files_run->verified << " of " << r.frames
                  << " frames kept (their files match the index's sizes and SHA-256), " << r.files_run->computed << " computed\n";
    if (!plan.wind_sea_scale.empty())
        std::cout << "wind sea   " << plan.ocean.n << "² FFT patch of " << plan.ocean.size << " m superposed, Hs "
                  << 4.0 * std::sqrt(plan.ocean.expected_variance) << " m offshore, loop " << plan.ocean.repeat_time << " s\n";
    for (const std::string& w : plan.warnings) std::cout << "warning    " << w << '\n';
}

// preview.png: four frames spread over the evaluated range, side by side (half-size each).
std::string preview_sheet(const Scene& scene, const ScenePlan& plan, const SceneAnimation& anim, std::size_t frames,
                          bool first_frame_only, double max_bytes) {
    PreviewOptions o = scene_preview(scene, plan.seafloor);
    o.width = std::max<std::size_t>(1, o.width / 2);
    o.height = std::max<std::size_t>(1, o.height / 2);
    std::vector<Image> shots;
    const std::size_t n = anim.vertex_count;
    for (std::size_t k = 0; k < 4; ++k) {
        const std::size_t f = k * frames / 4;
        if (k > 0 && f == (k - 1) * frames / 4) continue;  // fewer than four frames
        if (!first_frame_only) {
            shots.push_back(render_preview(std::span<const float>(&anim.positions[3 * n * f], 3 * n),
                                           std::span<const float>(&anim.normals[3 * n * f], 3 * n), anim.triangles, o));
            continue;
        }
        // The files form and the streamed forms keep one frame: each shown frame is evaluated again.
        const SceneAnimation shown = animate_scene(scene, plan, max_bytes, {anim.first_frame + f, anim.first_frame + f + 1});
        shots.push_back(render_preview(shown.positions, shown.normals, shown.triangles, o));
    }
    return png_bytes(contact_sheet(shots, 2));
}

// What the static stages leave beside the animation (the open ocean traces nothing). A
// slice reports in its own file (slices may run at once into one folder; `wave merge`
// joins their reports) and only the slice holding frame 0 writes its OBJ.
void add_side_files(RunSummary& r, const SceneAnimation& anim, Files& files) {
    const Traced traced = surface_kind_traces(r.scene.surface_kind);
    const char* trace_file = traced == Traced::fronts ? "strips.ply" : "rays.csv";
    if (traced != Traced::nothing) {
        r.side_files.emplace_back("isobaths.json");
        files.emplace_back("isobaths.json", contours_to_json(r.plan.isobaths));
    }
    if (traced == Traced::fronts || traced == Traced::rays) r.side_files.emplace_back(trace_file);
    if (traced == Traced::rays) files.emplace_back(trace_file, rays_to_csv(r.plan.rays));
    if (r.first_frame == 0) {
        r.side_files.emplace_back("surface-frame-0000.obj");
        const std::span<const float> first(anim.positions.data(), 3 * anim.vertex_count);
        files.emplace_back("surface-frame-0000.obj", mesh_to_obj(first, anim.triangles, "libwave " + std::string(version()) +
                                                                                           ": " + r.scene.name + ", frame 0, z up"));
    }
    r.side_files.push_back(r.report_name);
}

// The files form's frames (and its index) in the summary.
void summarise_files_form(const FilesFormRun& run, bool resumed, RunSummary& r) {
    for (const auto& [name, bytes] : run.files) {
        r.animation_names.push_back(name);
        r.animation_bytes += bytes;
    }
    r.animation_names.emplace_back("index.json");
    r.z_min = run.z_min;
    r.z_max = run.z_max;
    r.files_run = &run;
    r.resumed = resumed;
}

// A streamed form's files written into the staging folder as the frames come
// (stream_animation), `chunk` frames at a time; on failure that folder goes, and the
// output folder too when this run made it.
StreamedAnimation stream_to_staging(const Scene& scene, const ScenePlan& plan, const std::string& out_dir, FrameRange range,
                                    bool whole, std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& progress) {
    const bool created = !std::filesystem::exists(out_dir);
    const std::filesystem::path staging = staging_folder(out_dir);
    try {
        AnimationStream stream(scene, plan, range);
        std::filesystem::create_directories(staging);
        return stream_animation(stream, scene, staging.string(), whole, chunk, progress);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove_all(staging, ignored);
        if (created) std::filesystem::remove_all(out_dir, ignored);
        throw;
    }
}

// This process's resident memory (Linux /proc/self/statm; 0 when it cannot be read).
double resident_bytes() {
    std::ifstream statm("/proc/self/statm");
    double pages = 0.0, resident = 0.0;
    if (!(statm >> pages >> resident)) return 0.0;
    return resident * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

// `-o FILE.glb`: the run goes to a hidden folder beside FILE, its one animation file is
// renamed to FILE and the rest (report, strips, OBJ) removed: one file, written whole
// or not at all.
int run_to_one_file(const RunArgs& a) {
    const std::filesystem::path target(a.out_dir);
    const Scene scene = run_scene(a);
    if (scene.form != Scene::Form::morph && scene.form != Scene::Form::nodes)
        throw InputError("-o " + a.out_dir + ": one .glb holds the morph or nodes form, not " + std::string(form_name(scene.form)) +
                         " (give a folder for it)");
    if (scene.container != Scene::Container::glb)
        throw InputError("-o " + a.out_dir + ": the scene's /outputs/container is gltf (a .gltf and a .bin): give a folder");
    if (a.preview) throw InputError("-o " + a.out_dir + ": --preview writes preview.png beside the animation: give a folder");
    if (std::filesystem::is_directory(target)) throw InputError("-o " + a.out_dir + ": is a folder, not a .glb file");
    const std::filesystem::path parent = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
    std::filesystem::create_directories(parent);
    RunArgs work = a;
    work.out_dir = (parent / (".wave-" + target.filename().string() + "-" + std::to_string(::getpid()))).string();
    std::error_code ignored;
    std::filesystem::remove_all(work.out_dir, ignored);
    try {
        const int rc = run_job(work);
        std::string name;
        for (const auto& e : std::filesystem::directory_iterator(work.out_dir)) {
            const std::string n = e.path().filename().string();
            if (n.starts_with("animation") && n.ends_with(".glb")) name = n;
        }
        if (name.empty()) throw RuntimeError("-o " + a.out_dir + ": the run wrote no .glb");
        std::filesystem::rename(std::filesystem::path(work.out_dir) / name, target);
        std::filesystem::remove_all(work.out_dir);
        return rc;
    } catch (...) {
        std::filesystem::remove_all(work.out_dir, ignored);
        throw;
    }
}

int run_job(const RunArgs& a) {
    if (a.out_dir.ends_with(".glb")) return run_to_one_file(a);
    // Limits libwave's parallel loops (TBB) for this run; each vertex is computed alone,
    // so the files do not depend on the count.
    std::optional<tbb::global_control> threads;
    if (a.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(a.threads));
    Scene scene = run_scene(a);
    FrameRange range = parse_frames(a.frames);
    const std::string out_dir = run_out_dir(a);
    check_out_dir(out_dir);
    if (std::filesystem::is_directory(out_dir)) remove_dead_staging(out_dir);  // what killed runs left, whatever this one does
    if (scene.form == Scene::Form::files) check_files_form_places(out_dir);  // before the plan: at once
    // Another form's whole loop into a folder of a files run: its index and frames go once
    // this run is published (not left for merge, convert and the readers to take for the
    // animation); refused when no report claims them. (A slice of another form leaves
    // the files animation whole beside it.)
    const bool files_left_over = scene.form != Scene::Form::files && !a.overwrite && a.frames.empty() && a.slice.empty() &&
                                 std::filesystem::is_directory(out_dir) && files_form_left_over(out_dir, std::string(form_name(scene.form)));

    auto clock = std::chrono::steady_clock::now();
    const double max_bytes = a.max_memory_gb * 1e9;
    scene.fronts.max_bytes = max_bytes;  // the front points and a wave field's grid within the run's memory limit
    scene.field.max_bytes = max_bytes;
    check_plan_limits(scene, max_bytes);
    ScenePlan plan = plan_scene(scene, PlanStages::surface);
    const bool files_form = scene.form == Scene::Form::files;
    const std::size_t loop_frames = scene_loop_frames(scene, plan);
    if (!a.slice.empty()) range = slice_frames(a.slice, loop_frames);
    // A shot longer than the loop is never cut short in silence (it wrote the loop's
    // frames alone, exit 0): the loop's length is the scene's to change.
    if (!a.frames.empty() && range.end > loop_frames)
    {
        // The key that lengthens this scene's loop (docs/scene.md, "Long shots").
        const std::string keys = loop_lengthening_keys(scene);
        std::ostringstream why;
        why << "--frames " << a.frames << ": the loop has " << loop_frames << " frames (" << plan.loop_period << " s at "
            << scene.fps << " fps, /animation/fps); frames past it would repeat it: render --frames A:" << loop_frames
            << " and repeat them in the DCC, or lengthen the loop to at least " << static_cast<double>(range.end) / scene.fps
            << " s with " << keys;
        throw InputError(why.str());
    }
    const std::size_t range_end = std::min(range.end, loop_frames), in_range = range.first < range_end ? range_end - range.first : 0;
    check_report_place(out_dir, range.first == 0 && range_end == loop_frames ? "report.json" : slice_report_name(range.first, in_range));
    // The files form and the streamed forms compute a chunk of frames at a time; the
    // others (quantised single files) hold every frame of the range.
    const bool streamed = streamed_form(scene), chunked = files_form || streamed;
    std::size_t chunk = in_range;
    {  // the run's limits, before /refine's subdivision (which alone can take gigabytes)
        RunEstimate e = estimate_run(scene, plan, resident_bytes(), in_range);  // this process holds the plan now
        if (scene.codec_auto) {  // the codec chosen by the whole loop's plain size, the same for every slice
            scene = resolve_codec(scene, estimate_run(scene, plan));
            e = estimate_run(scene, plan, resident_bytes(), in_range);
        }
        if (chunked) chunk = std::min(files_form_chunk(e, max_bytes), in_range);
        if (scene.draco && !a.quiet) {  // what Draco's one step for all axes costs (docs/export.md, "Which codec")
            const ElevationGrid& g = plan.seafloor.grid;
            const double extent = std::max(static_cast<double>(g.nx > 0 ? g.nx - 1 : 0) * g.dx, static_cast<double>(g.ny > 0 ? g.ny - 1 : 0) * g.dy);
            const double step = std::exp2(std::floor(std::log2(extent / (std::exp2(scene.draco->position_bits) - 1.0))));
            if (step > 1e-3)
                std::cerr << "note: Draco puts positions on a " << step << " m lattice over the " << extent
                          << " m domain (coarser on a far-field skirt and its seam): heights come in terraces; "
                             "--codec meshopt keeps them within 8 µm\n";
        }
        check_run_limits(scene, e, chunk, max_bytes);
    }
    refine_scene_plan(scene, plan);
    const double plan_ms = ms_since(clock);
    // --overwrite: what earlier runs left goes now that the scene and its limits passed,
    // before any frame of this run is written.
    if (a.overwrite && std::filesystem::is_directory(out_dir)) remove_stale_outputs(out_dir, every_recorded_output(out_dir), {});

    // The files form writes its frames below (a killed run can resume); the streamed
    // forms write theirs into the staging folder now, as they come. `anim` then holds
    // the range's first frame only (sizes, the OBJ). (An empty range passes whole to
    // animate_scene or the stream, which name it.)
    clock = std::chrono::steady_clock::now();
    const auto progress = progress_bar(a);
    const bool whole = range.first == 0 && range_end == loop_frames;
    std::optional<StreamedAnimation> stream_out;
    SceneAnimation held;
    if (streamed) {
        stream_out = stream_to_staging(scene, plan, out_dir, range, whole, chunk, progress);
    } else {
        held = animate_scene(scene, plan, max_bytes, files_form && in_range > 0 ? FrameRange{range.first, range.first + 1} : range,
                             files_form ? std::function<void(std::size_t, std::size_t)>{} : progress);
    }
    const SceneAnimation& anim = stream_out ? stream_out->first : held;
    RunSummary r{.scene = scene, .plan = plan, .out_dir = out_dir, .run_key = run_key(a, scene, plan), .report_name = "",
                 .vertices = anim.vertex_count, .triangles = anim.triangles.size() / 3,
                 .frames = chunked ? range_end - anim.first_frame : anim.frame_count, .first_frame = anim.first_frame,
                 .loop_frames = loop_frames, .z_min = stream_out ? stream_out->z_min : anim.z_min,
                 .z_max = stream_out ? stream_out->z_max : anim.z_max, .plan_ms = plan_ms};
    r.report_name = whole ? "report.json" : slice_report_name(r.first_frame, r.frames);
    const FrameIndexInfo index_info{scene.name, scene.fps, plan.loop_period, loop_frames, r.run_key};
    const std::string index_path = (std::filesystem::path(out_dir) / "index.json").string();
    std::optional<FilesFormRun> files_run;
    Files files;
    if (files_form) {
        // libwave's writer refuses a foreign index before any frame is written.
        files_run.emplace(write_files_form(scene, plan, out_dir, index_info, range, a.resume, max_bytes, progress));
        summarise_files_form(*files_run, a.resume, r);
    }
    r.frames_ms = ms_since(clock);  // the files form computed and wrote its frames together
    clock = std::chrono::steady_clock::now();
    if (stream_out) {
        for (const auto& [name, bytes] : stream_out->files) {
            r.animation_names.push_back(name);
            r.animation_bytes += bytes;
        }
    } else if (!files_form) {
        files = encode_animation(anim.view(), scene.form, scene.container, whole, anim.caustics, anim.sunbeams, anim.whitewater);
        for (const auto& f : files) {
            r.animation_names.push_back(f.first);
            r.animation_bytes += f.second.size();
        }
    }
    r.export_ms = ms_since(clock);
    add_side_files(r, anim, files);
    json report = run_report(r);
    // Slices writing into one folder at once take turns to merge and publish the index
    // (a lock on the folder), so no slice's entries are lost.
    std::optional<FolderLock> index_lock;
    if (files_form) {
        index_lock.emplace(out_dir, true, "");
        files.emplace_back("index.json", merged_frame_index(index_path, index_info, files_run->entries, whole, a.resume));
    }
    if (a.preview) {
        files.emplace_back("preview.png", preview_sheet(scene, plan, anim, r.frames, chunked, max_bytes));
        report["outputs"].push_back("preview.png");
    }
    files.emplace_back(r.report_name, report.dump(2) + "\n");
    // What an earlier run with the same report left: stale unless written again.
    const std::vector<std::string> earlier = recorded_outputs(out_dir, r.report_name);
    const std::vector<std::string> published = publish(out_dir, files, [&](const std::filesystem::path& staging) {
        std::vector<std::string> names = files_run ? files_run->stage(staging.string()) : std::vector<std::string>{};
        if (stream_out)  // written there as the frames came
            for (const auto& f : stream_out->files) names.push_back(f.first);
        if (surface_kind_traces(scene.surface_kind) == Traced::fronts) {
            write_ray_strips_ply(plan.strips, (staging / "strips.ply").string());  // OpenMesh writes the file itself
            names.emplace_back("strips.ply");
        }
        return names;
    });
    remove_stale_outputs(out_dir, earlier, published);
    if (files_left_over) remove_stale_outputs(out_dir, {"index.json", "frames"}, published);
    if (files_run) {
        index_lock.reset();
        remove_files_form_partials(out_dir, *files_run, index_info);
    }
    if (a.quiet) return 0;
    if (!a.json) {
        print_run_text(r);
        return 0;
    }
    // Timings only on stdout: report.json is byte-identical from run to run.
    report["timings_ms"] = {{"plan", r.plan_ms}, {"frames", r.frames_ms}, {"export", r.export_ms}};
    if (files_run) report["resume"] = {{"kept_frames", files_run->verified}, {"computed_frames", files_run->computed}};
    std::cout << report.dump(2) << '\n';
    return 0;
}

int run_validate(const std::string& path, bool as_json, double max_memory_gb) {
    Scene read = read_scene(path);
    read.fronts.max_bytes = max_memory_gb * 1e9;  // the front points and a wave field's grid within the run's memory limit
    read.field.max_bytes = max_memory_gb * 1e9;
    const Seafloor sea = scene_seafloor(read);
    const auto camera = scene_camera(read, sea);
    const SeafloorStats st = seafloor_stats(sea);
    const std::string_view kind = surface_kind_name(read.surface_kind);
    // The plan (tracing, surfaces; every limit is checked here, before the frames) gives
    // what a run would hold and write; /refine's subdivision is predicted, not built, and
    // the run's own limits are checked as `wave run` checks them.
    const double max_bytes = max_memory_gb * 1e9;
    check_plan_limits(read, max_bytes);
    const ScenePlan plan = plan_scene(read, PlanStages::surface);
    const Scene scene = resolve_codec(read, estimate_run(read, plan));  // the codec a run would choose
    const RunEstimate e = estimate_run(scene, plan, resident_bytes());  // this process now holds what wave run's plan holds
    check_run_limits(scene, e, scene.form == Scene::Form::files || streamed_form(scene) ? files_form_chunk(e, max_bytes) : e.frames, max_bytes);
    const std::string_view form = form_name(scene.form);
    if (as_json) {
        std::cout << json{{"scene", scene.name}, {"valid", true}, {"surface", kind}, {"waves", scene.waves.size()},
                          {"seafloor", sea.source}, {"camera", camera}, {"fps", scene.fps},
                          {"estimate", {{"vertices", e.vertices}, {"triangles", e.triangles}, {"frames", e.frames}, {"form", form},
                                        {"output_bytes", e.output_bytes}, {"codec", codec_name(scene)}, {"frame_array_bytes", e.frame_array_bytes},
                                        {"peak_memory_bytes", e.peak_memory_bytes}}},
                          {"water_mesh_vertices", plan.water_mesh.vertex_count()},
                          {"far_field_vertices", plan.skirt.vertex_count()}}
                         .dump(2)
                  << '\n';
        return 0;
    }
    std::cout << path << ": valid — " << scene.name << "; " << kind << " surface, " << scene.waves.size()
              << " wave train(s) over " << sea.source << " (" << st.nx << " x " << st.ny << " nodes), camera at ["
              << camera[0] << ", " << camera[1] << ", " << camera[2] << "], " << scene.fps << " fps\n"
              << "estimate: " << e.vertices << " vertices, " << e.triangles << " triangles, " << e.frames << " frames; "
              << form << " output ~" << e.output_bytes / 1e6 << " MB (codec " << codec_name(scene) << "); peak memory of wave run ~" << e.peak_memory_bytes / 1e9
              << " GB\n";
    if (plan.water_mesh.vertex_count() > 0)
        std::cout << "water mesh: " << plan.water_mesh.vertex_count() << " vertices (far field: " << plan.skirt.vertex_count()
                  << ")\n";
    return 0;
}

namespace {

// What wave convert read and wrote.
struct Converted {
    std::size_t frames = 0, first_frame = 0, vertices = 0;
    double fps = 0.0;
    std::vector<std::pair<std::string, std::size_t>> staged;  // written into the staging folder: (name, bytes)
};

// The input's settings on a view for the output (Draco, quantisation).
MorphAnimationView output_view(const StoredAnimation& piece, const ConvertArgs& a) {
    MorphAnimationView view = piece.view();
    if (a.draco) view.draco = DracoOptions{};
    view.quantize = a.quantize;
    view.meshopt = a.meshopt;
    return view;
}

// Quantised morph targets need their range before the first target: a first pass over
// the input's positions, a piece at a time.
std::optional<double> convert_delta_range(const ConvertArgs& a, Scene::Form form) {
    if (!a.quantize || form != Scene::Form::morph) return std::nullopt;
    std::vector<float> base;
    double range = 0.0;
    read_animation_pieces(a.input, [&](StoredAnimation&& piece, std::size_t) {
        if (base.empty()) base.assign(piece.positions.begin(), piece.positions.begin() + static_cast<std::ptrdiff_t>(3 * piece.vertex_count));
        range = position_delta_range(base, piece.positions, range);
    });
    return range;
}

// The input's pieces (the files form's frames one by one, one file whole) re-encoded as
// they are read, into the staging folder: a form streamed_form accepts goes through a
// StreamedWriter, the files form frame by frame with its index. Memory holds one piece.
Converted convert_streamed(const ConvertArgs& a, Scene::Form form, Scene::Container container,
                           const std::filesystem::path& staging, Files& held) {
    Converted c;
    const std::optional<double> range = convert_delta_range(a, form);
    std::optional<StreamedWriter> writer;
    std::vector<std::string> entries;
    std::size_t loop_frames = 0;
    std::string scene;
    bool whole = false;
    read_animation_pieces(a.input, [&](StoredAnimation&& piece, std::size_t total) {
        MorphAnimationView view = output_view(piece, a);
        view.quantize_range = range;
        if (c.frames == 0) {
            c.first_frame = piece.first_frame, c.vertices = piece.vertex_count, c.fps = piece.fps;
            loop_frames = piece.loop_frames, scene = piece.scene;
            whole = piece.first_frame == 0 && total == piece.loop_frames;
            if (form != Scene::Form::files) writer.emplace(staging.string(), form, container, whole, view, total);
        }
        c.frames += piece.frame_count;
        if (writer) {
            writer->append(view);
            return;
        }
        // Entries with each frame's files (size, SHA-256) and height range; no run key:
        // these frames were re-encoded, not computed from a scene.
        const Files files = encode_animation(view, form, container, whole);
        const std::size_t per_frame = files.size() / piece.frame_count, n = piece.vertex_count;
        for (std::size_t k = 0; k < piece.frame_count; ++k) {
            const Files frame(files.begin() + static_cast<std::ptrdiff_t>(k * per_frame),
                              files.begin() + static_cast<std::ptrdiff_t>((k + 1) * per_frame));
            entries.push_back(frame_entry_json(piece.first_frame + k, piece.fps, frame, view.positions.subspan(3 * n * k, 3 * n)));
            for (const auto& [name, bytes] : frame) {
                std::filesystem::create_directories((staging / name).parent_path());
                write_file_atomic((staging / name).string(), bytes);
                c.staged.emplace_back(name, bytes.size());
            }
        }
    });
    if (writer) {
        c.staged = writer->finish();
    } else {
        const FrameIndexInfo info{scene, c.fps, static_cast<double>(loop_frames) / c.fps, loop_frames, ""};
        std::string index = merged_frame_index((std::filesystem::path(a.out_dir) / "index.json").string(), info, entries, whole);
        held.emplace_back("index.json", std::move(index));
    }
    return c;
}

// The forms that hold every frame (quantised nodes and pc2: KHR_mesh_quantization's
// range spans the animation): the input read whole, then encoded.
Converted convert_whole(const ConvertArgs& a, Scene::Form form, Scene::Container container, Files& held) {
    const StoredAnimation stored = read_animation(a.input);
    const bool whole = stored.first_frame == 0 && stored.frame_count == stored.loop_frames;
    held = encode_animation(output_view(stored, a), form, container, whole);
    return {stored.frame_count, stored.first_frame, stored.vertex_count, stored.fps, {}};
}

}  // namespace

int run_convert(const ConvertArgs& a) {
    if (a.draco + a.quantize + a.meshopt > 1) throw InputError("convert: choose one of --draco, --quantize and --meshopt");
    check_out_dir(a.out_dir);
    if (std::filesystem::is_directory(a.out_dir)) remove_dead_staging(a.out_dir);  // what killed converts left, whatever this one does
    const Scene::Form form = form_from_name(a.form.empty() ? "morph" : a.form);
    const Scene::Container container = container_from_name(a.container.empty() ? "glb" : a.container);
    Files held;  // small files (or, for the forms that hold every frame, all) to publish
    Converted c;
    const bool created = !std::filesystem::exists(a.out_dir);
    const std::filesystem::path staging = staging_folder(a.out_dir);
    try {
        if (streamed_form(form, a.quantize) || (form == Scene::Form::files && !a.quantize)) {
            std::filesystem::create_directories(staging);
            c = convert_streamed(a, form, container, staging, held);
        } else {
            c = convert_whole(a, form, container, held);
        }
        publish(a.out_dir, held, [&](const std::filesystem::path&) {  // the streamed files lie in the staging folder
            std::vector<std::string> names;
            for (const auto& f : c.staged) names.push_back(f.first);
            return names;
        });
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove_all(staging, ignored);
        if (created) std::filesystem::remove_all(a.out_dir, ignored);
        throw;
    }
    std::size_t bytes = 0;
    std::vector<std::string> outputs;
    for (const auto& f : c.staged) bytes += f.second, outputs.push_back(f.first);
    for (const auto& f : held) bytes += f.second.size(), outputs.push_back(f.first);
    json summary{{"input", a.input}, {"frames", c.frames}, {"first_frame", c.first_frame},
                 {"vertices", c.vertices}, {"fps", c.fps}, {"form", a.form.empty() ? "morph" : a.form},
                 {"draco", a.draco}, {"quantized", a.quantize}, {"meshopt", a.meshopt}, {"bytes", bytes}, {"outputs", outputs}};
    if (a.json) std::cout << summary.dump(2) << '\n';
    else if (!a.quiet)
        std::cout << "converted " << a.input << " (" << c.frames << " frames of " << c.vertices << " vertices) -> " << a.out_dir
                  << "/ (" << outputs.size() << " files, " << static_cast<double>(bytes) / 1e6 << " MB)\n";
    return 0;
}

// asset.extras.libwave of a .glb or .gltf, from its JSON alone (the binary is not read).
json frame_metadata(const std::string& path) {
    require_input_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the file");
    std::string text;
    char head[20];
    if (in.read(head, 20) && std::memcmp(head, "glTF", 4) == 0) {
        std::uint32_t length = 0;
        std::memcpy(&length, head + 12, 4);
        std::error_code ec;
        if (length > std::filesystem::file_size(path, ec) || ec) throw InputError(path + ": truncated GLB");  // before allocating it
        text.resize(length);
        if (!in.read(text.data(), length)) throw InputError(path + ": truncated GLB");
    } else {
        in.clear();
        in.seekg(0);
        text.assign(std::istreambuf_iterator<char>(in), {});
    }
    json extras;
    try {
        extras = json::parse(text).at("asset").at("extras").at("libwave");
    } catch (const json::exception&) {
        throw InputError(path + ": not a frame written by libwave (no asset.extras.libwave)");
    }
    if (!extras.is_object() || !extras.value("scene", json()).is_string() || !extras.value("fps", json()).is_number() ||
        !extras.value("loop_frames", json()).is_number_unsigned() || !extras.value("first_frame", json()).is_number_unsigned() ||
        !extras.value("run_key", json("")).is_string())
        throw InputError(path + ": asset.extras.libwave lacks scene, fps, loop_frames or first_frame of the types libwave writes");
    return extras;
}

// The slices' reports joined into the report.json of one run over the whole loop: the
// same plan, the frame count and height range over every slice, the whole run's
// outputs. Only when the slices tile the loop exactly; returns the slice reports used.
// The slice reports of a folder (report-frames-A-B.json) by first frame, each a regular
// file (a FIFO blocked wave merge for ever; refused naming it, exit 2).
std::map<std::size_t, std::filesystem::path> slice_reports(const std::filesystem::path& out_dir) {
    std::map<std::size_t, std::filesystem::path> reports;
    for (const auto& e : std::filesystem::directory_iterator(out_dir)) {
        const std::string name = e.path().filename().string();
        std::size_t first = 0, end = 0;
        char tail[8] = {};
        if (std::sscanf(name.c_str(), "report-frames-%zu-%zu%7s", &first, &end, tail) != 3 || std::strcmp(tail, ".json") ||
            name != slice_report_name(first, end - first))
            continue;
        require_input_file(e.path().string());
        reports.emplace(first, e.path());
    }
    return reports;
}

std::vector<std::filesystem::path> join_slice_reports(const std::filesystem::path& out_dir, std::size_t loop_frames) {
    namespace fs = std::filesystem;
    std::map<std::size_t, std::pair<fs::path, json>> slices;  // by first frame
    for (const auto& [first, path] : slice_reports(out_dir)) {
        json r = json::parse(read_input_bytes(path), nullptr, false);
        const fs::directory_entry e(path);
        // What the join reads, of the types libwave writes.
        const auto is_report = [](const json& j) {
            if (!j.is_object() || !j.contains("surface") || !j["surface"].is_object() || !j.contains("outputs") ||
                !j["outputs"].is_array())
                return false;
            const json& s = j["surface"];
            const json range = s.value("height_range_m", json());
            return s.value("frames", json()).is_number_unsigned() && range.is_array() && range.size() == 2 &&
                   range[0].is_number() && range[1].is_number() &&
                   std::all_of(j["outputs"].begin(), j["outputs"].end(), [](const json& o) { return o.is_string(); });
        };
        if (r.is_discarded() || !is_report(r)) throw InputError(e.path().string() + ": not a libwave report");
        slices.emplace(first, std::make_pair(e.path(), std::move(r)));
    }
    std::size_t next = 0;
    for (const auto& [first, s] : slices) {
        if (first != next) return {};  // a gap or an overlap: the reports stay per slice
        next = first + s.second.at("surface").at("frames").get<std::size_t>();
    }
    if (slices.empty() || next != loop_frames) return {};
    // What every slice must share: the report without its frame-dependent fields.
    const auto plan_part = [](json r) {
        for (const char* k : {"frames", "first_frame", "height_range_m"}) r["surface"].erase(k);
        r.erase("outputs");
        return r;
    };
    json report = slices.begin()->second.second;
    const json shared = plan_part(report);
    json frame_files = json::array(), rest = json::array();
    double z_min = report["surface"]["height_range_m"][0], z_max = report["surface"]["height_range_m"][1];
    std::vector<fs::path> used;
    for (const auto& [first, s] : slices) {
        const auto& [path, r] = s;
        if (plan_part(r) != shared)
            throw InputError(path.string() + ": a report of another run than " + slices.begin()->second.first.string());
        z_min = std::min(z_min, r["surface"]["height_range_m"][0].get<double>());
        z_max = std::max(z_max, r["surface"]["height_range_m"][1].get<double>());
        for (const auto& o : r.at("outputs"))
            if (o.get<std::string>().starts_with("frames/")) frame_files.push_back(o);
        used.push_back(path);
    }
    for (const auto& o : report.at("outputs")) {
        const std::string name = o.get<std::string>();
        if (!name.starts_with("frames/")) rest.push_back(name.starts_with("report-frames-") ? "report.json" : name);
    }
    report["surface"]["frames"] = loop_frames;
    report["surface"]["first_frame"] = 0;
    report["surface"]["height_range_m"] = {z_min, z_max};
    report["outputs"] = frame_files;
    for (auto& o : rest) report["outputs"].push_back(o);
    write_file_atomic((out_dir / "report.json").string(), report.dump(2) + "\n");
    return used;
}

int run_merge(const MergeArgs& a) {
    // The frames present, each described by its own asset extras (name, fps, loop).
    namespace fs = std::filesystem;
    const fs::path frames = fs::path(a.out_dir) / "frames";
    if (fs::is_directory(a.out_dir)) remove_dead_staging(a.out_dir);  // what killed runs left, whatever this one does
    if (!fs::is_directory(frames)) throw InputError(a.out_dir + ": no frames/ folder (the files form's output)");
    path_inside(a.out_dir, "frames", a.out_dir + ": its");  // a link to frames elsewhere is not this folder's
    std::map<std::size_t, std::string> files;
    bool gltf = false;
    for (const auto& e : fs::directory_iterator(frames)) {
        const std::string name = e.path().filename().string();
        std::size_t frame = 0;
        char ext[8] = {};
        if (std::sscanf(name.c_str(), "frame-%zu.%7s", &frame, ext) != 2 || (std::strcmp(ext, "glb") && std::strcmp(ext, "gltf")))
            continue;
        gltf = std::strcmp(ext, "gltf") == 0;
        path_inside(a.out_dir, "frames/" + name, a.out_dir + ": a frame");
        files[frame] = "frames/" + name;
    }
    if (files.empty()) throw InputError(frames.string() + ": no frame files");
    json meta;
    for (const auto& [frame, file] : files) {
        const json m = frame_metadata((fs::path(a.out_dir) / file).string());
        if (meta.is_null()) meta = m;
        if (m.value("scene", "") != meta.value("scene", "") || m.at("fps") != meta.at("fps") ||
            m.at("loop_frames") != meta.at("loop_frames"))
            throw InputError(file + ": belongs to another animation than " + files.begin()->second + " (name, fps or loop differ)");
        if (m.value("run_key", "") != meta.value("run_key", ""))
            throw InputError(file + ": computed from another version of the scene, its seafloor or libwave than " +
                             files.begin()->second + " (their run keys differ); run its slice again with the scene of the others");
        if (m.at("first_frame").get<std::size_t>() != frame) throw InputError(file + ": holds frame " + m.at("first_frame").dump());
    }
    const auto loop_frames = meta.at("loop_frames").get<std::size_t>();
    const double fps = meta.at("fps").get<double>();
    std::vector<std::size_t> missing;
    for (std::size_t f = 0; f < loop_frames; ++f)
        if (!files.count(f)) missing.push_back(f);
    // Each frame's files with their sizes and SHA-256; the run key and height ranges of
    // the slices' own index carried over where the files are the ones it listed.
    const fs::path old_path = fs::path(a.out_dir) / "index.json";
    (void)slice_reports(a.out_dir);  // what the join will read, checked before the index is written
    const FolderLock index_lock(a.out_dir, true, "");  // slices may still be publishing their entries
    const std::optional<std::string> old_text = read_files_form_index(old_path.string());
    const json old = old_text ? json::parse(*old_text) : json::object();
    std::map<std::size_t, json> old_entries;
    if (old.contains("frames"))
        for (const json& e : old["frames"])
            if (e.is_object() && e.contains("frame") && e["frame"].is_number_unsigned()) old_entries[e["frame"].get<std::size_t>()] = e;
    // The frames' own run key (frames written before frames carried one: the old index's).
    const std::string frames_key = meta.value("run_key", "");
    const FrameIndexInfo info{meta.value("scene", ""), fps, static_cast<double>(loop_frames) / fps, loop_frames,
                              frames_key.empty() ? old.value("run_key", "") : frames_key};
    bool all_listed = true;  // every frame's files are those the old index listed with the run key
    std::vector<std::string> entries;
    for (const auto& [frame, file] : files) {
        Files content;
        const auto add = [&](const std::string& name) { content.emplace_back(name, read_input_bytes(path_inside(a.out_dir, name, a.out_dir + ": a frame"))); };
        add(file);
        if (file.ends_with(".gltf")) add(file.substr(0, file.size() - 5) + ".bin");
        json entry = json::parse(frame_entry_json(frame, fps, content));
        const auto o = old_entries.find(frame);
        if (o != old_entries.end() && o->second.value("content", json()) == entry["content"] && o->second.contains("height_range_m"))
            entry["height_range_m"] = o->second["height_range_m"];
        else
            all_listed = false;
        entries.push_back(entry.dump());
    }
    const std::string index =
        frame_index_json(all_listed || !frames_key.empty() ? info : FrameIndexInfo{info.scene, info.fps, info.loop_period, info.loop_frames, ""},
                         entries);
    if (!missing.empty() && !a.partial)
        throw InputError(a.out_dir + ": " + std::to_string(missing.size()) + " of " + std::to_string(loop_frames) +
                         " frames are missing (first: " + std::to_string(missing.front()) +
                         "); run their slices, or --partial to index what is there");
    write_file_atomic(old_path.string(), index);
    (void)gltf;
    const std::vector<fs::path> joined = missing.empty() ? join_slice_reports(a.out_dir, loop_frames) : std::vector<fs::path>{};
    for (const fs::path& p : joined) fs::remove(p);  // report.json now holds them
    if (!a.quiet) {
        if (loop_frames == 0)  // frames written without their loop's length (Python's frame_glb without loop_frames)
            std::cout << "indexed " << files.size() << " frames in " << a.out_dir
                      << "/index.json (they record no loop length: frame_glb(..., loop_frames=) records it)\n";
        else
            std::cout << "indexed " << files.size() << " of " << loop_frames << " frames in " << a.out_dir << "/index.json\n";
        if (!joined.empty()) std::cout << "joined " << joined.size() << " slice reports into " << a.out_dir << "/report.json\n";
    }
    return 0;
}

int run_preview(const PreviewArgs& a) {
    const Scene scene = a.scene.empty() ? default_scene() : read_scene(a.scene);
    const ScenePlan plan = plan_scene(scene);
    const SceneAnimation anim = animate_scene(scene, plan, 2e9, FrameRange{a.frame, a.frame + 1});
    PreviewOptions o = scene_preview(scene, plan.seafloor);
    if (a.width > 0) o.width = a.width;
    if (a.height > 0) o.height = a.height;
    if (!std::isnan(a.sun_azimuth)) o.sun_azimuth_degrees = a.sun_azimuth;
    if (!std::isnan(a.sun_elevation)) o.sun_elevation_degrees = a.sun_elevation;
    const auto t0 = std::chrono::steady_clock::now();
    const Image image = render_preview(anim.positions, anim.normals, anim.triangles, o);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    write_png(image, a.output);
    if (!a.quiet)
        std::cout << "rendered   frame " << a.frame << " of " << scene.name << ": " << image.width << " x " << image.height
                  << " pixels, " << anim.triangles.size() / 3 << " triangles, in " << ms << " ms -> " << a.output << '\n';
    return 0;
}

int run_schema() {
    std::cout << scene_schema();
    return 0;
}

}  // namespace wave::cli
