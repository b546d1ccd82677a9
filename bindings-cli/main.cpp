// wave — command-line front end of libwave. Exit codes: 0 ok, 2 bad input or usage,
// 1 runtime failure; errors go to stderr as "error: …".
#include "commands.h"
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/io.h"
#include "libwave/version.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace {

// The export forms' names (export_forms(), the one table of them): what --form accepts.
std::vector<std::string> form_names() {
    std::vector<std::string> names;
    for (const wave::ExportFormInfo& f : wave::export_forms()) names.emplace_back(f.name);
    return names;
}

// --form's help: each form's name and what it writes, from the same table.
std::string form_help() {
    std::string help = "animation form:";
    for (const wave::ExportFormInfo& f : wave::export_forms())
        help += std::string(&f == wave::export_forms().data() ? " " : ", ") + std::string(f.name) + " (" + std::string(f.description) + ")";
    return help;
}

// CLI11's NonNegativeNumber/PositiveNumber print their range up to DBL_MAX in full;
// these say it plainly: "--fps: must be > 0, got 0".
CLI::Validator number_above(double lo, bool strict) {
    return CLI::Validator(
        [lo, strict](std::string& text) {
            double v = 0.0;
            try {
                std::size_t used = 0;
                v = std::stod(text, &used);
                if (used != text.size()) return "expected a number, got \"" + text + "\"";
            } catch (const std::exception&) {
                return "expected a number, got \"" + text + "\"";
            }
            const bool ok = strict ? v > lo : v >= lo;
            return ok ? std::string() : std::string(strict ? "must be > " : "must be >= ") + CLI::detail::to_string(lo) + ", got " + text;
        },
        strict ? "NUMBER > 0" : "NUMBER >= 0");
}
const CLI::Validator non_negative = number_above(0.0, false);
const CLI::Validator positive = number_above(0.0, true);

using namespace wave;

void add_reader_options(CLI::App& cmd, cli::SeafloorArgs& a) {
    static const std::map<std::string, ValueSign> signs{{"elevation", ValueSign::elevation},
                                                        {"depth", ValueSign::depth}};
    static const std::map<std::string, NodataPolicy> policies{{"land", NodataPolicy::land},
                                                              {"error", NodataPolicy::error}};
    ReadOptions& r = a.read;
    cmd.add_option("--sign", r.sign, "Sign of the stored values: elevation (positive up) or depth (positive down); default: the format's")
        ->transform(CLI::CheckedTransformer(signs, CLI::ignore_case));
    cmd.add_option("--vertical-scale", r.vertical_scale, "metres = value * scale + offset")->capture_default_str();
    cmd.add_option("--vertical-offset", r.vertical_offset, "added after scaling (m)")->capture_default_str();
    cmd.add_option("--horizontal-scale", r.horizontal_scale, "multiplies x and y (e.g. 400 for a 1:400 model)")->capture_default_str();
    cmd.add_option("--nodata", r.nodata_value, "value marking missing nodes (overrides the file's)");
    cmd.add_option("--nodata-policy", r.nodata_policy, "land: missing nodes become dry land; error: refuse them")
        ->transform(CLI::CheckedTransformer(policies, CLI::ignore_case));
    cmd.add_option("--nodata-elevation", r.nodata_elevation, "elevation of filled NODATA nodes (m)")->capture_default_str();
    cmd.add_option("--swan-grid", [&r](const CLI::results_t& v) {
        r.swan_nx = std::stoul(v.at(0));
        r.swan_ny = std::stoul(v.at(1));
        return true;
    }, "SWAN .bot: nodes per row and rows, NX,NY")->expected(2)->delimiter(',')->type_name("NX,NY")
        ->check(positive);
    cmd.add_option("--swan-spacing", [&r](const CLI::results_t& v) {
        r.swan_dx = std::stod(v.at(0));
        r.swan_dy = v.size() > 1 ? std::stod(v.at(1)) : 0.0;
        return true;
    }, "SWAN .bot: spacing DX[,DY] (m)")->expected(1, 2)->delimiter(',')->type_name("DX[,DY]")
        ->check(positive);
    cmd.add_option("--swan-origin", [&r](const CLI::results_t& v) {
        r.swan_x0 = std::stod(v.at(0));
        r.swan_y0 = std::stod(v.at(1));
        return true;
    }, "SWAN .bot: position of the first value X0,Y0 (m)")->expected(2)->delimiter(',')->type_name("X0,Y0")
        ->check(CLI::Number);
    cmd.add_option("--spacing", r.resample_spacing, "node spacing when a mesh or contour file is gridded (m; 0 = automatic)")
        ->check(non_negative)->capture_default_str();
    cmd.add_option("--max-nodes", r.max_nodes, "refuse grids with more nodes than this")->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"wave — coastal wave tracing and animated water meshes (libwave " +
                 std::string(wave::version()) + ")"};
    app.set_version_flag("--version", std::string("wave ") + wave::version());
    app.require_subcommand(1);

    cli::RunArgs run;
    auto* run_cmd = app.add_subcommand("run", "Run the main job on a scene file, or on the built-in default scene (Gonzato's bay with a swell)");
    run_cmd->add_option("scene", run.scene, "scene file (JSON); none = the built-in default scene");
    run_cmd->add_option("-o,--out", run.out_dir, "output folder (default: wave-out/<scene name>), or FILE.glb: only the animation, as that one file (morph or nodes form)");
    run_cmd->add_flag("--json", run.json, "print the report as JSON");
    run_cmd->add_option("--form", run.form, form_help())->check(CLI::IsMember(form_names()));
    run_cmd->add_option("--frames", run.frames, "A:B: only frames A … B-1 of the loop, B at most the loop's frame count (slices of one animation can run on different machines; the files form merges them in index.json)");
    run_cmd->add_option("--slice", run.slice, "I/N: slice I (0-based) of N equal slices of the loop, e.g. a Slurm array task's $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT");
    run_cmd->add_option("--container", run.container, "glb (binary, default) or gltf (JSON + external .bin)")
        ->check(CLI::IsMember({"glb", "gltf"}));
    auto* quantize_opt = run_cmd->add_flag("--quantize", run.quantize, "KHR_mesh_quantization: int16 position and normal deltas (morph) or positions, int8 normals, uint16 UV maps (the default scene: 44 MB instead of 69; its default)");
    run_cmd->add_flag("--no-quantize", run.no_quantize, "float attributes even where the scene asks for quantisation")->excludes(quantize_opt);
    auto* draco_opt = run_cmd->add_flag("--draco", run.draco, "Draco-compress the meshes (morph: the base mesh only; default quantisation: positions 14 bits)");
    run_cmd->add_flag("--no-draco", run.no_draco, "plain meshes even where the scene asks for Draco (Blender's own glTF importer reads no Draco)")
        ->excludes(draco_opt);
    run_cmd->add_option("--codec", run.codec, "compression of the animation, overriding the scene's /outputs/codec: auto (meshopt above 32 MB of plain output, else none), none (plain floats: Blender's own importer, any glTF client), meshopt (EXT_meshopt_compression: fast, heights within 0.12 mm), draco, quantize")
        ->check(CLI::IsMember({"auto", "none", "meshopt", "draco", "quantize"}))->excludes(draco_opt)->excludes(quantize_opt);
    run_cmd->add_option("--fps", run.fps, "frames per second (overrides the scene's)")->check(positive);
    run_cmd->add_flag("-q,--quiet", run.quiet, "no progress bar and no report on stdout");
    CLI::Option* resume_opt = run_cmd->add_flag("--resume", run.resume, "files form: continue an interrupted run — keep the frames whose files match the index (size and SHA-256), compute the rest");
    run_cmd->add_flag("--overwrite", run.overwrite, "remove every output an earlier run left in the folder (all reports' files, index.json, frames/) before writing; without it a rerun still removes what its predecessor wrote and it does not write again (e.g. animation.bin after a switch to glb)")->excludes(resume_opt);
    run_cmd->add_flag("--preview", run.preview, "also write preview.png: four frames rendered by the preview ray caster");
    run_cmd->add_option("--max-memory-gb", run.max_memory_gb, "refuse animations whose per-frame arrays would exceed this (GB)")
        ->check(positive)->capture_default_str();
    run_cmd->add_flag("--view", run.view, "then show the output in the browser viewer (wave view): opened when a display is available, the URL printed otherwise");
    run_cmd->add_option("--threads", run.threads, "worker threads (default: all cores); the outputs are the same for any count")
        ->check(positive);

    cli::BatchArgs batch;
    std::string batch_form, batch_frames, batch_container;
    double batch_fps = 0.0;
    bool batch_draco = false, batch_quantize = false;
    int batch_threads = 0;
    auto* batch_cmd = app.add_subcommand("batch", "Run many scenes (files, folders of *.json, glob patterns), each into OUT/<name>, with a summary");
    batch_cmd->add_option("inputs", batch.inputs, "scene files, folders or patterns")->required();
    batch_cmd->add_option("-o,--out", batch.out_dir, "output folder (default: wave-out/batch)");
    batch_cmd->add_option("-j,--jobs", batch.jobs, "scenes run at the same time (default 1)")->check(positive);
    batch_cmd->add_option("--form", batch_form, "as for run")->check(CLI::IsMember(form_names()));
    batch_cmd->add_option("--frames", batch_frames, "as for run");
    batch_cmd->add_option("--container", batch_container, "as for run")->check(CLI::IsMember({"glb", "gltf"}));
    batch_cmd->add_option("--fps", batch_fps, "as for run")->check(positive);
    batch_cmd->add_flag("--draco", batch_draco, "as for run");
    bool batch_no_draco = false;
    batch_cmd->add_flag("--no-draco", batch_no_draco, "as for run");
    batch_cmd->add_flag("--quantize", batch_quantize, "as for run");
    bool batch_no_quantize = false;
    batch_cmd->add_flag("--no-quantize", batch_no_quantize, "as for run");
    std::string batch_codec;
    batch_cmd->add_option("--codec", batch_codec, "as for run")->check(CLI::IsMember({"auto", "none", "meshopt", "draco", "quantize"}));
    batch_cmd->add_option("--threads", batch_threads, "worker threads of each scene's run")->check(positive);
    batch_cmd->add_flag("-q,--quiet", batch.quiet, "no line per scene");
    batch_cmd->add_flag("--json", batch.json, "print the summary as JSON");

    cli::ConvertArgs convert;
    auto* convert_cmd = app.add_subcommand("convert", "Re-encode an output of wave run (a .glb/.gltf, or the files form's index.json) in another form or compression, without recomputing");
    convert_cmd->add_option("input", convert.input, "animation.glb / .gltf, a frame file, or index.json")->required();
    convert_cmd->add_option("-o,--out", convert.out_dir, "output folder")->required();
    convert_cmd->add_option("--form", convert.form, "as for run (default morph)")->check(CLI::IsMember(form_names()));
    convert_cmd->add_option("--container", convert.container, "glb (default) or gltf")->check(CLI::IsMember({"glb", "gltf"}));
    convert_cmd->add_flag("--draco", convert.draco, "Draco-compress (morph: the base mesh)");
    convert_cmd->add_flag("--quantize", convert.quantize, "KHR_mesh_quantization");
    convert_cmd->add_flag("--meshopt", convert.meshopt, "EXT_meshopt_compression (fast; heights within 0.12 mm)");
    convert_cmd->add_flag("-q,--quiet", convert.quiet, "print nothing");
    convert_cmd->add_flag("--json", convert.json, "print a JSON summary");

    cli::PreviewArgs prev;
    auto* prev_cmd = app.add_subcommand("preview", "Render one frame of a scene to PNG (the sunset ray caster: sun glitter, Fresnel sky and deep water)");
    prev_cmd->add_option("scene", prev.scene, "scene file (JSON); none = the built-in default scene");
    prev_cmd->add_option("--frame", prev.frame, "frame of the loop (default 0)");
    prev_cmd->add_option("-o,--output", prev.output, "PNG file")->capture_default_str();
    prev_cmd->add_option("--width", prev.width, "pixels (default: the scene's /preview/image)")->check(positive);
    prev_cmd->add_option("--height", prev.height, "pixels")->check(positive);
    prev_cmd->add_option("--sun-azimuth", prev.sun_azimuth, "degrees from +x towards +y");
    prev_cmd->add_option("--sun-elevation", prev.sun_elevation, "degrees above the horizon");
    prev_cmd->add_flag("-q,--quiet", prev.quiet, "print nothing");

    cli::MergeArgs merge;
    auto* merge_cmd = app.add_subcommand("merge", "Rebuild the files form's index.json from the frame files present (after slices ran on several machines)");
    merge_cmd->add_option("out", merge.out_dir, "the output folder holding frames/")->required();
    merge_cmd->add_flag("--partial", merge.partial, "index the frames present even if some of the loop are missing");
    merge_cmd->add_flag("-q,--quiet", merge.quiet, "print nothing");

    cli::ViewArgs view;
    auto* view_cmd = app.add_subcommand("view", "Play an output of wave run in the browser: a local three.js page on 127.0.0.1 (morph, nodes and files forms; plain, quantised or Draco)");
    view_cmd->add_option("path", view.path, "output folder (e.g. wave-out/default), a .glb/.gltf, or index.json")->required();
    auto* port_opt = view_cmd->add_option("--port", view.port, "TCP port (0 = any free port; a busy default falls back to a free one)")
        ->capture_default_str()->check(CLI::Range(0, 65535));
    view_cmd->add_option("--host", view.host, "address to listen on")->capture_default_str();
    view_cmd->add_flag("!--no-open", view.open, "only print the URL, even when a display is available");

    std::string validate_scene;
    bool validate_json = false;
    auto* validate_cmd = app.add_subcommand("validate", "Check a scene file (keys, values, seafloor, camera) without running it");
    validate_cmd->add_option("scene", validate_scene, "scene file (JSON)")->required();
    validate_cmd->add_flag("--json", validate_json, "print the result as JSON");
    double validate_max_memory_gb = cli::RunArgs{}.max_memory_gb;
    validate_cmd->add_option("--max-memory-gb", validate_max_memory_gb, "the limit `wave run --max-memory-gb` would apply (GB)")
        ->check(positive)->capture_default_str();
    auto* schema_cmd = app.add_subcommand("schema", "Print the scene file's JSON Schema");

    cli::FieldArgs field;
    auto* field_cmd = app.add_subcommand("field", "Solve a scene's refraction-diffraction wave field (wave heights behind shoals, islands, breakwaters): a GeoTIFF and/or a plot");
    field_cmd->add_option("scene", field.scene, "scene file (JSON); none = the built-in default scene");
    field_cmd->add_option("-o,--output", field.output, "GeoTIFF: bands H/H0, phase (rad), direction (degrees from +x)");
    field_cmd->add_option("--png", field.png, "PNG plot of H/H0 with the depth contours and a labelled colour scale");
    field_cmd->add_option("--train", field.train, "which wave train of /waves (default 0)");
    field_cmd->add_flag("--json", field.json, "print a JSON summary");
    field_cmd->add_option("--max-memory-gb", field.max_memory_gb, "refuse a grid that would need more memory (GB, default 2), before it is allocated")
        ->check(CLI::Range(0.001, 1e6));

    cli::InspectArgs inspect;
    auto* inspect_cmd = app.add_subcommand("inspect", "Check an output of wave run as a renderer meets it, every frame: folds and overturning lips, slivers, long edges, boundary loops, unreferenced vertices, vertex speeds");
    inspect_cmd->add_option("path", inspect.path, "output folder, a .glb/.gltf, or index.json")->required();
    inspect_cmd->add_option("--sliver-angle", inspect.options.sliver_angle_deg, "smallest angle (degrees) below which a triangle is a sliver")
        ->capture_default_str()->check(CLI::Range(0.0, 60.0));
    inspect_cmd->add_option("--lip-foam", inspect.options.lip_foam, "foam from which a triangle facing down is an overturning lip, not a fold")
        ->capture_default_str()->check(CLI::Range(0.0, 1.0));
    inspect_cmd->add_option("--long-edge", inspect.options.long_edge_ratio, "edge length over the local spacing counted as long")
        ->capture_default_str()->check(CLI::Range(1.0, 1e6));
    inspect_cmd->add_option("--scene", inspect.scene, "SCENE: the scene the output was run from; its breakers tell the lips they draw overturned from folds (instead of --lip-foam)");
    inspect_cmd->add_flag("--json", inspect.json, "print everything as JSON, every frame included");
    inspect_cmd->add_option("--against", inspect.against, "REF: compare the positions with REF, a float run of the same scene (--codec none): the largest height and horizontal errors per frame, and the distinct heights of the domain (terraces)");

    cli::TraceArgs trace;
    auto* trace_cmd = app.add_subcommand("trace", "Trace a scene's wave trains: rays or fronts as CSV, ray strips as PLY, a summary");
    trace_cmd->add_option("scene", trace.scene, "scene file (JSON)")->required();
    trace_cmd->add_option("-o,--output", trace.output, "CSV of the traced points: fronts (ray strips) or Ts'o rays (height field)");
    trace_cmd->add_option("--mesh-out", trace.mesh_out, "PLY of the ray strips with per-vertex properties (ray, step, phase, k, amplitude, ...)");
    trace_cmd->add_flag("--json", trace.json, "print a JSON summary (initial_rays, inserted_rays, rays_aground, steps, vertices, triangles)");

    cli::DispersionArgs disp;
    auto* disp_cmd = app.add_subcommand("dispersion", "Linear wave quantities for a period and a depth");
    disp_cmd->add_option("-T,--period", disp.period, "wave period (s)")->required()->check(positive);
    disp_cmd->add_option("-d,--depth", disp.depth, "water depth (m, positive down; <= 0 is dry)")->required()->check(CLI::Number);
    disp_cmd->add_option("--capillary-length", disp.capillary_length, "capillary length L (m) of Tessendorf eq. 16")
        ->check(non_negative);
    disp_cmd->add_option("--deep-height", disp.deep_height, "deep-water wave height H0 (m): also report the shoaled height and breaking")
        ->check(non_negative);
    disp_cmd->add_flag("--json", disp.json, "print JSON");

    cli::SeafloorArgs sea;
    auto* sea_cmd = app.add_subcommand("seafloor", "Seafloor tools");
    sea_cmd->require_subcommand(1);
    auto* info_cmd = sea_cmd->add_subcommand("info", "Size, extent, cell size, depth range, land fraction, NODATA count");
    std::string names;
    for (const auto& n : procedural_seafloor_names()) names += (names.empty() ? "" : ", ") + n;
    info_cmd->add_option("source", sea.source, "a grid/mesh/contour file, or a procedural seafloor: " + names)->required();
    info_cmd->add_flag("--json", sea.json, "print JSON");
    add_reader_options(*info_cmd, sea);

    cli::ContoursArgs cont;
    auto* cont_cmd = app.add_subcommand("contours", "Slice a seafloor into depth contours (isobaths) and write them");
    cont_cmd->add_option("source", cont.seafloor.source, "a grid/mesh/contour file, or a procedural seafloor")->required();
    auto* levels_opt = cont_cmd->add_option("--levels", cont.levels, "depth levels (m, positive down), e.g. 1,2,5")->delimiter(',');
    auto* spacing_opt = cont_cmd->add_option("--level-spacing", cont.level_spacing, "a level every S metres of depth")
        ->check(positive);
    levels_opt->excludes(spacing_opt);
    cont_cmd->add_flag("--no-shoreline", cont.no_shoreline, "do not add the shoreline (depth 0)");
    cont_cmd->add_option("--smooth", cont.smooth_samples, "Beta-spline smoothing: samples per span (0 = off)")
        ->check(non_negative);
    cont_cmd->add_option("--beta1", cont.beta1, "Beta-spline bias (> 0)")->capture_default_str();
    cont_cmd->add_option("--beta2", cont.beta2, "Beta-spline tension (>= 0)")->capture_default_str();
    cont_cmd->add_option("-o,--output", cont.output, "output file: .json (libwave contours) or .obj (polylines)")->required();
    add_reader_options(*cont_cmd, cont.seafloor);

    try {
        app.parse(argc, argv);
        if (*run_cmd) {
            const int rc = cli::run_job(run);
            if (rc != 0 || !run.view) return rc;
            view.path = cli::run_out_dir(run);
            return cli::run_view(view);
        }
        if (*view_cmd) {
            view.port_given = port_opt->count() > 0;
            return cli::run_view(view);
        }
        if (*convert_cmd) return cli::run_convert(convert);
        if (*merge_cmd) return cli::run_merge(merge);
        if (*prev_cmd) return cli::run_preview(prev);
        if (*batch_cmd) {
            const auto pass = [&](const char* flag, const std::string& value) {
                if (!value.empty()) batch.run_args.insert(batch.run_args.end(), {flag, value});
            };
            pass("--form", batch_form);
            pass("--frames", batch_frames);
            pass("--container", batch_container);
            if (batch_fps > 0) pass("--fps", std::to_string(batch_fps));
            if (batch_threads > 0) pass("--threads", std::to_string(batch_threads));
            if (batch_draco) batch.run_args.push_back("--draco");
            if (batch_no_draco) batch.run_args.push_back("--no-draco");
            if (batch_quantize) batch.run_args.push_back("--quantize");
            if (batch_no_quantize) batch.run_args.push_back("--no-quantize");
            if (!batch_codec.empty()) batch.run_args.insert(batch.run_args.end(), {"--codec", batch_codec});
            return cli::run_batch(batch);
        }
        if (*validate_cmd) return cli::run_validate(validate_scene, validate_json, validate_max_memory_gb);
        if (*schema_cmd) return cli::run_schema();
        if (*trace_cmd) return cli::run_trace(trace);
        if (*field_cmd) return cli::run_field(field);
        if (*inspect_cmd) return cli::run_inspect(inspect);
        if (*disp_cmd) return cli::run_dispersion(disp);
        if (*info_cmd) return cli::run_seafloor_info(sea);
        if (*cont_cmd) return cli::run_contours(cont);
        return 2;
    } catch (const CLI::Success& e) {  // --help, --help-all, --version
        return app.exit(e);
    } catch (const CLI::ParseError& e) {  // messages show names as escapes, never as terminal commands
        std::cerr << "error: " << wave::printable(e.what()) << "\n(run 'wave --help' for usage)\n";
        return 2;
    } catch (const wave::InputError& e) {
        std::cerr << "error: " << wave::printable(e.what()) << '\n';
        return 2;
    } catch (const wave::InternalError& e) {  // a bug, not the input's fault
        std::cerr << "error: internal: " << wave::printable(e.what())
                  << " (a libwave bug: please report it with the scene and the command)\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "error: " << wave::printable(e.what()) << '\n';
        return 1;
    }
}
