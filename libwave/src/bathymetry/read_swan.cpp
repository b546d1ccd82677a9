// SWAN bottom files (.bot): a bare free-format list of numbers; the grid geometry is
// not in the file (SWAN's INPGRID command gives it), so the caller supplies it.
#include "grid_fill.h"
#include "libwave/bathymetry.h"
#include "libwave/errors.h"
#include "core/files.h"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace wave {

Seafloor read_swan_bot(const std::string& path, const ReadOptions& o) {
    if (o.swan_nx == 0 || o.swan_ny == 0 || !(o.swan_dx > 0.0))
        throw InputError(path + ": a SWAN .bot file does not say its grid; give the nodes per "
                                "row, the rows and the spacing (ReadOptions::swan_nx/swan_ny/"
                                "swan_dx, CLI --swan-grid NX,NY --swan-spacing DX[,DY])");
    if (o.swan_dy < 0.0) throw InputError(path + ": swan_dy must be >= 0 (0 = same as dx)");
    detail::require_input_file(path);
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot open the file");
    const std::size_t nx = o.swan_nx, ny = o.swan_ny;
    detail::check_grid_size(path, nx, ny, o);
    std::vector<double> values;
    values.reserve(nx * ny);

    // SWAN reads free format: numbers separated by blanks or commas, any line breaks.
    std::string line;
    std::size_t line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        for (char& c : line)
            if (c == ',') c = ' ';
        std::istringstream tokens(line);
        std::string tok;
        while (tokens >> tok) {
            double v = 0.0;
            const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
            if (ec != std::errc() || end != tok.data() + tok.size())
                throw InputError(path + ": line " + std::to_string(line_no) + ": '" + tok +
                                 "' is not a number");
            if (values.size() == nx * ny)
                throw InputError(path + ": more values than the " + std::to_string(nx) + " x " +
                                 std::to_string(ny) + " grid given (line " +
                                 std::to_string(line_no) + "); check --swan-grid");
            values.push_back(v);
        }
    }
    if (values.size() < nx * ny)
        throw InputError(path + ": truncated: expected " + std::to_string(nx) + " x " +
                         std::to_string(ny) + " = " + std::to_string(nx * ny) +
                         " values, found " + std::to_string(values.size()));

    // values are in file order: first row at y0, rows towards +y (SWAN idla = 3).
    const auto where = [&](std::size_t i, std::size_t j) {
        return "row " + std::to_string(j + 1) + ", value " + std::to_string(i + 1);
    };
    Seafloor out;
    out.source = path;
    out.frame = "local metres (SWAN computational grid)";
    out.nodata_count = detail::convert_to_elevation(values, o.nodata_value, {}, ValueSign::depth,
                                                    o, path, where, nx);
    ElevationGrid& g = out.grid;
    g.nx = nx;
    g.ny = ny;
    g.dx = o.swan_dx * o.horizontal_scale;
    g.dy = (o.swan_dy > 0.0 ? o.swan_dy : o.swan_dx) * o.horizontal_scale;
    g.x0 = o.swan_x0 * o.horizontal_scale;
    g.y0 = o.swan_y0 * o.horizontal_scale;
    g.z = std::move(values);
    return out;
}

}  // namespace wave
