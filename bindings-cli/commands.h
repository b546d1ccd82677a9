// The `wave` subcommands, free of CLI11 so that only main.cpp pays its compile time.
#pragma once

#include "libwave/bathymetry.h"

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
/// Loads a file, or a procedural seafloor when `source` is one of its names and no
/// such file exists.
Seafloor load_seafloor(const SeafloorArgs& a);

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

struct RunArgs {
    std::string out_dir = "wave-out/default";
    bool json = false;
};
int run_default_job(const RunArgs& a);

}  // namespace wave::cli
