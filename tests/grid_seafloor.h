// A seafloor on a regular grid from a depth function (tests only): nodes every
// `spacing` metres over width × height from (0, 0), elevation z = −depth(x, y).
#pragma once

#include "libwave/bathymetry.h"

#include <cmath>
#include <functional>

namespace wave::test {

inline Seafloor grid_seafloor(double width, double height, double spacing, const std::function<double(double, double)>& depth) {
    Seafloor s;
    ElevationGrid& g = s.grid;
    g.nx = static_cast<std::size_t>(std::llround(width / spacing)) + 1;
    g.ny = static_cast<std::size_t>(std::llround(height / spacing)) + 1;
    g.dx = g.dy = spacing;
    g.z.resize(g.nx * g.ny);
    for (std::size_t j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < g.nx; ++i)
            g.z[j * g.nx + i] = -depth(static_cast<double>(i) * spacing, static_cast<double>(j) * spacing);
    s.source = "test grid";
    return s;
}

}  // namespace wave::test
