// `wave field`: a scene's refraction–diffraction wave field as a GeoTIFF and a plot.
#include "commands.h"
#include "outputs.h"

#include "libwave/errors.h"
#include "libwave/field.h"
#include "libwave/io.h"
#include "libwave/scene.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>

namespace wave::cli {

int run_field(const FieldArgs& a) {
    if (a.output.empty() && a.png.empty() && !a.json)
        throw InputError("field: nothing to do; give -o GEOTIFF, --png PLOT and/or --json");
    Scene scene = a.scene.empty() ? default_scene() : read_scene(a.scene);
    scene.field.max_bytes = a.max_memory_gb * 1e9;
    if (surface_kind_traces(scene.surface_kind) == Traced::nothing)
        throw InputError(a.scene + ": the " + std::string(surface_kind_name(scene.surface_kind)) +
                         " surface has no seafloor to solve a wave field over");
    if (a.train >= scene.waves.size())
        throw InputError("field: --train " + std::to_string(a.train) + ": the scene has " + std::to_string(scene.waves.size()) +
                         " wave train(s) in /waves");
    for (const std::string& path : {a.output, a.png}) {
        if (path.empty()) continue;
        if (std::filesystem::is_directory(path)) throw InputError(path + ": a folder; -o and --png name files");
        const std::string folder = std::filesystem::path(path).parent_path().string();
        check_out_dir(folder);
        std::error_code ec;
        if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
            throw InputError(path + ": its folder " + folder + " does not exist; -o and --png name files in an existing folder");
    }
    const Seafloor seafloor = scene_seafloor(scene);
    const auto t0 = std::chrono::steady_clock::now();
    const WaveField field = solve_wave_field(seafloor, scene.waves[a.train], scene.field);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const FieldRaster raster = rasterize_wave_field(field, seafloor);
    if (!a.output.empty()) write_file_atomic(a.output, field_geotiff(raster, seafloor));
    if (!a.png.empty()) {
        const DepthContours iso = extract_isobaths(seafloor, scene.isobaths);
        char title[160];
        std::snprintf(title, sizeof title, ": H/H0 of wave train %zu (T = %g s, A = %g m)", a.train, scene.waves[a.train].period,
                      scene.waves[a.train].amplitude);
        write_file_atomic(a.png, field_plot_png(raster, iso, scene.name + title));
    }
    const nlohmann::json summary{{"scene", scene.name},
                                 {"train", a.train},
                                 {"grid", {{"along", field.nx}, {"across", field.ny}, {"spacing_m", field.dx}}},
                                 {"incident_height_m", field.incident_height},
                                 {"height_ratio_max", raster.ratio_max},
                                 {"broken_nodes", field.broken_nodes},
                                 {"solve_ms", ms}};
    if (a.json) {
        std::cout << summary.dump(2) << '\n';
        return 0;
    }
    std::cout << std::setprecision(4) << "field      " << field.nx << " x " << field.ny << " nodes, " << field.dx
              << " m apart (wide-angle parabolic mild-slope, marched along the swell) in " << ms << " ms\n"
              << "heights    H0 " << field.incident_height << " m; H/H0 up to " << raster.ratio_max << "; "
              << field.broken_nodes << " nodes in the surf zone (breaking: onset H > γh, stop H < Γh)\n";
    if (!a.output.empty()) std::cout << "wrote      " << a.output << " (bands H/H0, phase, direction)\n";
    if (!a.png.empty()) std::cout << "wrote      " << a.png << '\n';
    return 0;
}

}  // namespace wave::cli
