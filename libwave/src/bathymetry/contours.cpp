// Depth-tagged contour polylines (Ts'o–Barsky's input) and their gridding.
#include "grid_fill.h"
#include "libwave/bathymetry.h"
#include "libwave/errors.h"
#include "core/files.h"
#include "core/json_input.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace wave {
namespace {

using nlohmann::json;

double number_at(const json& v, const std::string& path, const std::string& pointer,
                 const char* what) {
    if (!v.is_number())
        throw InputError(path + ": " + pointer + ": expected a number (" + what + "), got " +
                         detail::brief_json(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw InputError(path + ": " + pointer + ": value is not finite");
    return d;
}

// Offset from p to the nearest point of a polyline, and its squared length.
struct Nearest {
    double dx = 0.0, dy = 0.0;
    double dist2 = std::numeric_limits<double>::infinity();
};

void closer_to_segment(double px, double py, const double* a, const double* b, Nearest& n) {
    const double ux = b[0] - a[0], uy = b[1] - a[1];
    const double len2 = ux * ux + uy * uy;
    const double t = len2 > 0.0 ? std::clamp(((px - a[0]) * ux + (py - a[1]) * uy) / len2, 0.0, 1.0) : 0.0;
    const double dx = a[0] + t * ux - px, dy = a[1] + t * uy - py;
    const double d2 = dx * dx + dy * dy;
    if (d2 < n.dist2) n = {dx, dy, d2};
}

}  // namespace

Seafloor read_contour_file(const std::string& path, const ReadOptions& o) {
    detail::require_input_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the file");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw InputError(path + ": cannot read the file");
    const json doc = detail::parse_json_input(text, path);
    if (!doc.is_object() || !doc.contains("contours") || !doc["contours"].is_array())
        throw InputError(path + ": /contours: expected an array of {\"depth\": …, \"points\": [[x, y], …]}");
    ValueSign sign = o.sign.value_or(ValueSign::depth);
    if (doc.contains("sign")) {
        const json& sv = doc["sign"];
        if (sv == "depth") sign = ValueSign::depth;
        else if (sv == "elevation") sign = ValueSign::elevation;
        else throw InputError(path + ": /sign: expected \"depth\" or \"elevation\", got " + detail::brief_json(sv));
    }
    const json& list = doc["contours"];
    if (list.empty()) throw InputError(path + ": /contours: the list is empty");

    Seafloor out;
    out.source = path;
    out.frame = "local metres (the contour file's own x/y)";
    DepthContours& c = out.contours;
    c.offsets.push_back(0);
    for (std::size_t n = 0; n < list.size(); ++n) {
        const std::string at = "/contours/" + std::to_string(n);
        const json& item = list[n];
        if (!item.is_object() || !item.contains("depth") || !item.contains("points"))
            throw InputError(path + ": " + at + ": expected an object with \"depth\" and \"points\"");
        const double value = number_at(item["depth"], path, at + "/depth", "metres");
        const double metres = value * o.vertical_scale + o.vertical_offset;
        c.depth.push_back(sign == ValueSign::depth ? metres : -metres);
        const json& pts = item["points"];
        if (!pts.is_array() || pts.size() < 2)
            throw InputError(path + ": " + at + "/points: expected at least two [x, y] points");
        for (std::size_t k = 0; k < pts.size(); ++k) {
            const std::string pk = at + "/points/" + std::to_string(k);
            if (!pts[k].is_array() || pts[k].size() != 2)
                throw InputError(path + ": " + pk + ": expected [x, y], got " + detail::brief_json(pts[k]));
            c.xy.push_back(number_at(pts[k][0], path, pk + "/0", "metres") * o.horizontal_scale);
            c.xy.push_back(number_at(pts[k][1], path, pk + "/1", "metres") * o.horizontal_scale);
        }
        bool closed = false;
        if (item.contains("closed")) {
            if (!item["closed"].is_boolean())
                throw InputError(path + ": " + at + "/closed: expected true or false");
            closed = item["closed"].get<bool>();
        }
        c.closed.push_back(closed ? 1 : 0);
        c.offsets.push_back(c.xy.size() / 2);
    }
    out.grid = grid_from_contours(c, o.resample_spacing, o.max_nodes);
    return out;
}

ElevationGrid grid_from_contours(const DepthContours& c, double spacing, std::size_t max_nodes) {
    if (c.size() == 0 || c.xy.size() < 4)
        throw InputError("contours: the set is empty; at least one polyline of two points is needed");
    double x_lo = HUGE_VAL, x_hi = -HUGE_VAL, y_lo = HUGE_VAL, y_hi = -HUGE_VAL;
    for (std::size_t k = 0; k + 1 < c.xy.size(); k += 2) {
        x_lo = std::min(x_lo, c.xy[k]);
        x_hi = std::max(x_hi, c.xy[k]);
        y_lo = std::min(y_lo, c.xy[k + 1]);
        y_hi = std::max(y_hi, c.xy[k + 1]);
    }
    if (!(x_hi > x_lo && y_hi > y_lo))
        throw InputError("contours: the polylines span no area (all on one line)");
    if (!(spacing > 0.0)) spacing = std::max(x_hi - x_lo, y_hi - y_lo) / 256.0;
    ElevationGrid g;
    ReadOptions limits;
    limits.max_nodes = max_nodes;
    g.nx = detail::nodes_along("contours", x_hi - x_lo, spacing, 1, limits);
    g.ny = detail::nodes_along("contours", y_hi - y_lo, spacing, 1, limits);
    detail::check_grid_size("contours", g.nx, g.ny, limits);
    g.x0 = x_lo;
    g.y0 = y_lo;
    g.dx = g.dy = spacing;
    g.z.resize(g.nx * g.ny);

    const std::size_t lines = c.size();
    std::vector<Nearest> near(lines);
    for (std::size_t j = 0; j < g.ny; ++j) {
        for (std::size_t i = 0; i < g.nx; ++i) {
            const double x = g.x0 + static_cast<double>(i) * g.dx;
            const double y = g.y0 + static_cast<double>(j) * g.dy;
            std::size_t first = 0;
            for (std::size_t p = 0; p < lines; ++p) {
                Nearest n;
                const std::size_t begin = c.offsets[p], end = c.offsets[p + 1];
                for (std::size_t k = begin; k + 1 < end; ++k)
                    closer_to_segment(x, y, &c.xy[2 * k], &c.xy[2 * k + 2], n);
                if (c.closed[p] && end - begin > 2)
                    closer_to_segment(x, y, &c.xy[2 * (end - 1)], &c.xy[2 * begin], n);
                near[p] = n;
                if (n.dist2 < near[first].dist2) first = p;
            }
            // The node lies in the band between its nearest isobath and the nearest
            // isobath of another depth on the opposite side (the two nearest points in
            // opposite directions); depth is linear in distance across that band.
            // Beyond the outermost isobath no such partner exists: depth stays constant.
            const Nearest& a = near[first];
            std::size_t second = lines;
            for (std::size_t p = 0; p < lines; ++p) {
                const Nearest& b = near[p];
                if (c.depth[p] == c.depth[first] || a.dx * b.dx + a.dy * b.dy >= 0.0) continue;
                if (second == lines || b.dist2 < near[second].dist2) second = p;
            }
            double h = c.depth[first];
            if (second != lines && a.dist2 > 0.0) {
                const double d1 = std::sqrt(a.dist2), d2 = std::sqrt(near[second].dist2);
                h = (c.depth[first] * d2 + c.depth[second] * d1) / (d1 + d2);
            }
            g.at(i, j) = -h;
        }
    }
    return g;
}

}  // namespace wave
