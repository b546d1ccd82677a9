// The `wave` subcommands: parse nothing, compute nothing themselves — they call
// libwave and print what it returns.
#include "commands.h"

#include "libwave/errors.h"
#include "libwave/io.h"
#include "libwave/isobath.h"
#include "libwave/physics.h"
#include "libwave/version.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numbers>

namespace wave::cli {

using nlohmann::json;

int run_dispersion(const DispersionArgs& a) {
    DispersionOptions opt;
    opt.capillary_length = a.capillary_length;
    const double omega = 2.0 * std::numbers::pi / a.period;
    const LinearWave w = linear_wave(omega, a.depth, opt);
    const double deep_wavelength = kGravity * a.period * a.period / (2.0 * std::numbers::pi);
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

Seafloor load_seafloor(const SeafloorArgs& a) {
    const auto& names = procedural_seafloor_names();
    if (!std::filesystem::exists(a.source) &&
        std::find(names.begin(), names.end(), a.source) != names.end())
        return make_named_seafloor(a.source);
    return read_seafloor(a.source, a.read);
}

int run_seafloor_info(const SeafloorArgs& a) {
    const Seafloor s = load_seafloor(a);
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
    const Seafloor sea = load_seafloor(a.seafloor);
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

int run_default_job(const RunArgs& a) {
    // The built-in default scene: Gonzato's bay with a 5 s, 0.6 m swell from the open
    // sea along y = 0. Until the tracing, surface and export stages land, the job
    // shoals the swell along every cross-shore line of the bay and finds the surf zone.
    const double period = 5.0, deep_height = 0.6;
    const double omega = 2.0 * std::numbers::pi / period;
    const Seafloor sea = make_gonzato_bay();
    const ElevationGrid& g = sea.grid;

    json lines = json::array();
    std::vector<double> depth(g.ny);
    std::size_t breaking_lines = 0;
    std::array<std::size_t, 4> type_count{};
    double break_depth_sum = 0.0, break_height_sum = 0.0;
    for (std::size_t i = 0; i < g.nx; i += 10) {
        const double x = g.x0 + static_cast<double>(i) * g.dx;
        for (std::size_t j = 0; j < g.ny; ++j)
            depth[j] = depth_at(g, x, g.y0 + static_cast<double>(j) * g.dy);
        const ShoalingProfile p = shoal_profile(omega, deep_height, depth, g.dy);
        json line{{"x_m", x}};
        if (p.break_index >= 0) {
            ++breaking_lines;
            ++type_count[static_cast<std::size_t>(p.type)];
            break_depth_sum += p.break_depth;
            break_height_sum += p.break_height;
            line["break_y_m"] = g.y0 + static_cast<double>(p.break_index) * g.dy;
            line["break_depth_m"] = p.break_depth;
            line["break_height_m"] = p.break_height;
            line["iribarren"] = p.iribarren;
            line["breaker"] = to_string(p.type);
        }
        lines.push_back(line);
    }
    const SeafloorStats st = seafloor_stats(sea);
    const LinearWave offshore = linear_wave(omega, depth_at(g, g.x0 + 0.5 * (g.x_max() - g.x0), g.y0));
    json report{{"libwave", version()},
                {"scene", "default: Gonzato's bay with a swell"},
                {"seafloor", {{"source", sea.source}, {"nodes", {st.nx, st.ny}}, {"depth_range_m", {st.depth_min, st.depth_max}}}},
                {"swell", {{"period_s", period}, {"deep_height_m", deep_height}, {"direction", "+y"}}},
                {"offshore", {{"depth_m", offshore.depth}, {"wavelength_m", offshore.wavelength},
                              {"celerity_m_per_s", offshore.celerity}, {"shoaling", offshore.shoaling}}},
                {"cross_shore_lines", lines},
                {"stages_done", {"physics", "bathymetry"}},
                {"stages_pending", {"isobath", "trace", "surface", "motion", "shade", "export"}}};

    std::filesystem::create_directories(a.out_dir);
    const std::string path = (std::filesystem::path(a.out_dir) / "surf-zone.json").string();
    write_file_atomic(path, report.dump(2) + "\n");

    if (a.json) {
        std::cout << report.dump(2) << '\n';
        return 0;
    }
    std::cout << std::setprecision(4)
              << "scene     default: Gonzato's bay (" << st.nx << " x " << st.ny << " nodes, depth "
              << st.depth_min << " .. " << st.depth_max << " m)\n"
              << "swell     T = " << period << " s, H0 = " << deep_height << " m, towards +y; offshore L = "
              << offshore.wavelength << " m, C = " << offshore.celerity << " m/s\n"
              << "shoaled   " << lines.size() << " cross-shore lines; " << breaking_lines << " break";
    if (breaking_lines) {
        std::cout << " at mean depth " << break_depth_sum / static_cast<double>(breaking_lines) << " m, mean height "
                  << break_height_sum / static_cast<double>(breaking_lines) << " m (";
        const char* sep = "";
        for (std::size_t t = 0; t < type_count.size(); ++t)
            if (type_count[t]) {
                std::cout << sep << type_count[t] << " " << to_string(static_cast<BreakerType>(t));
                sep = ", ";
            }
        std::cout << ")";
    }
    std::cout << "\nwrote     " << path << '\n'
              << "pending   isobath, trace, surface, motion, shade, export stages (no animated .glb yet)\n";
    return 0;
}

}  // namespace wave::cli
