// Contours as files: our JSON contour format (read back by read_contour_file) and OBJ
// polylines for DCC tools.
#include "libwave/isobath.h"

#include <nlohmann/json.hpp>

#include <sstream>

namespace wave {

std::string contours_to_json(const DepthContours& c) {
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t p = 0; p < c.size(); ++p) {
        nlohmann::json points = nlohmann::json::array();
        for (std::size_t k = c.offsets[p]; k < c.offsets[p + 1]; ++k)
            points.push_back({c.xy[2 * k], c.xy[2 * k + 1]});
        list.push_back({{"depth", c.depth[p]}, {"closed", c.closed[p] != 0}, {"points", std::move(points)}});
    }
    return nlohmann::json{{"sign", "depth"}, {"contours", std::move(list)}}.dump() + "\n";
}

std::string contours_to_obj(const DepthContours& c) {
    std::ostringstream out;
    out.precision(17);
    out << "# libwave isobaths: " << c.size() << " polylines, z = -depth (m), z up\n";
    for (std::size_t p = 0; p < c.size(); ++p) {
        out << "o isobath_" << p << "_depth_" << c.depth[p] << '\n';
        for (std::size_t k = c.offsets[p]; k < c.offsets[p + 1]; ++k)
            out << "v " << c.xy[2 * k] << ' ' << c.xy[2 * k + 1] << ' ' << 0.0 - c.depth[p] << '\n';
    }
    for (std::size_t p = 0; p < c.size(); ++p) {
        out << 'l';
        for (std::size_t k = c.offsets[p]; k < c.offsets[p + 1]; ++k) out << ' ' << k + 1;  // OBJ is 1-based
        if (c.closed[p]) out << ' ' << c.offsets[p] + 1;
        out << '\n';
    }
    return out.str();
}

}  // namespace wave
