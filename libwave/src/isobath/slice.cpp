// Isobaths by slicing the seafloor surface with horizontal planes (CGAL), and
// Beta-spline smoothing of contour polylines (Ts'o–Barsky §3.2.2).
#include "libwave/beta_spline.h"
#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/isobath.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace wave {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

std::string fmt(double v) { return detail::format_number(v); }

// The source mesh when there is one (slicing the original, not its resampling),
// otherwise the grid with two triangles per cell.
Mesh seafloor_mesh(const Seafloor& s) {
    Mesh mesh;
    if (!s.mesh.triangles.empty()) {
        std::vector<Mesh::Vertex_index> v;
        v.reserve(s.mesh.xyz.size() / 3);
        for (std::size_t i = 0; i < s.mesh.xyz.size(); i += 3)
            v.push_back(mesh.add_vertex(Point(s.mesh.xyz[i], s.mesh.xyz[i + 1], s.mesh.xyz[i + 2])));
        for (std::size_t t = 0; t < s.mesh.triangles.size(); t += 3)
            mesh.add_face(v[s.mesh.triangles[t]], v[s.mesh.triangles[t + 1]], v[s.mesh.triangles[t + 2]]);
        return mesh;
    }
    const ElevationGrid& g = s.grid;
    std::vector<Mesh::Vertex_index> v(g.nx * g.ny);
    for (std::size_t j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < g.nx; ++i)
            v[j * g.nx + i] = mesh.add_vertex(Point(g.x0 + static_cast<double>(i) * g.dx,
                                                    g.y0 + static_cast<double>(j) * g.dy, g.at(i, j)));
    for (std::size_t j = 0; j + 1 < g.ny; ++j)
        for (std::size_t i = 0; i + 1 < g.nx; ++i) {
            const auto a = v[j * g.nx + i], b = v[j * g.nx + i + 1];
            const auto c = v[(j + 1) * g.nx + i + 1], d = v[(j + 1) * g.nx + i];
            mesh.add_face(a, b, c);
            mesh.add_face(a, c, d);
        }
    return mesh;
}

std::vector<double> chosen_levels(const IsobathOptions& o, double depth_min, double depth_max) {
    std::vector<double> levels = o.levels;
    if (levels.empty()) {
        if (!(o.spacing > 0.0) || !std::isfinite(o.spacing))
            throw InputError("isobaths: give depth levels or a level spacing > 0 m");
        // Positive multiples of the spacing strictly inside the depth range.
        const double first = std::max(1.0, std::floor(depth_min / o.spacing) + 1.0);
        // Each level is a slice of the whole seafloor: bounded before any is made (a
        // seafloor scaled to 50 km of depth gave 200 000 levels at the default spacing).
        if ((depth_max - first * o.spacing) / o.spacing > kMaxIsobathLevels)
            throw LimitError("isobaths: a spacing of " + fmt(o.spacing) + " m over depths up to " + fmt(depth_max) +
                             " m gives more than " + fmt(kMaxIsobathLevels) +
                             " levels; raise /isobaths/spacing (IsobathOptions::spacing) or give /isobaths/levels");
        for (double n = first; n * o.spacing < depth_max; n += 1.0) levels.push_back(n * o.spacing);
    }
    for (double h : levels) {
        if (!std::isfinite(h)) throw InputError("isobaths: level " + fmt(h) + " is not a finite depth");
        if (!(h > depth_min && h < depth_max))
            throw InputError("isobaths: level " + fmt(h) + " m lies outside the seafloor's depth range (" +
                             fmt(depth_min) + " .. " + fmt(depth_max) + " m); valid levels lie strictly inside it");
    }
    if (o.include_shoreline && depth_min < 0.0 && depth_max > 0.0) levels.push_back(0.0);
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    return levels;
}

}  // namespace

DepthContours extract_isobaths(const Seafloor& seafloor, const IsobathOptions& o) {
    double depth_min = HUGE_VAL, depth_max = -HUGE_VAL;
    if (!seafloor.mesh.triangles.empty()) {
        for (std::size_t i = 2; i < seafloor.mesh.xyz.size(); i += 3) {
            depth_min = std::min(depth_min, -seafloor.mesh.xyz[i]);
            depth_max = std::max(depth_max, -seafloor.mesh.xyz[i]);
        }
    } else {
        const SeafloorStats st = seafloor_stats(seafloor);
        depth_min = st.depth_min;
        depth_max = st.depth_max;
    }
    const std::vector<double> levels = chosen_levels(o, depth_min, depth_max);

    const Mesh mesh = seafloor_mesh(seafloor);
    CGAL::Polygon_mesh_slicer<Mesh, Kernel> slicer(mesh);
    DepthContours out;
    out.offsets.push_back(0);
    for (double h : levels) {
        std::vector<std::vector<Point>> polylines;
        slicer(Kernel::Plane_3(0, 0, 1, h), std::back_inserter(polylines));  // plane z = −h
        for (auto& line : polylines) {
            bool closed = line.size() > 2 && line.front() == line.back();
            if (closed) line.pop_back();  // the slicer repeats the first point of a ring
            if (line.size() < 2) continue;
            for (const Point& p : line) {
                out.xy.push_back(p.x());
                out.xy.push_back(p.y());
            }
            out.depth.push_back(h);
            out.closed.push_back(closed ? 1 : 0);
            out.offsets.push_back(out.xy.size() / 2);
        }
    }
    if (o.smoothing_samples > 0)
        return smooth_isobaths(out, o.smoothing_samples, o.smoothing_beta1, o.smoothing_beta2);
    return out;
}

DepthContours smooth_isobaths(const DepthContours& c, int samples, double b1, double b2) {
    if (samples < 1) throw InputError("isobath smoothing: samples per span must be >= 1, got " + std::to_string(samples));
    if (!(b1 > 0.0) || !(b2 >= 0.0))
        throw InputError("isobath smoothing: need bias beta1 > 0 and tension beta2 >= 0, got " + fmt(b1) + ", " + fmt(b2));
    // The basis at each sample depends on (β1, β2) only: computed once, and refused when
    // it is not finite (a β1 near 1e100 overflows the basis's β1³ and every point became NaN).
    std::vector<std::array<double, 4>> basis(static_cast<std::size_t>(samples) + 1);
    for (int k = 0; k <= samples; ++k) {
        beta_spline_basis(static_cast<double>(k) / samples, b1, b2, basis[static_cast<std::size_t>(k)].data());
        for (double w : basis[static_cast<std::size_t>(k)])
            if (!std::isfinite(w))
                throw InputError("isobath smoothing: beta1 = " + fmt(b1) + ", beta2 = " + fmt(b2) +
                                 " give no finite curve (scene keys /isobaths/smoothing/beta1, beta2)");
    }
    DepthContours out;
    out.offsets.push_back(0);
    for (std::size_t p = 0; p < c.size(); ++p) {
        const std::size_t begin = c.offsets[p], n = c.offsets[p + 1] - begin;
        const bool closed = c.closed[p] && n > 2;
        // Control vertices: a ring wraps around; an open line triples its end
        // vertices so that the curve starts and ends on them.
        std::vector<std::array<double, 2>> v;
        const auto vertex = [&](std::size_t k) { return std::array<double, 2>{c.xy[2 * (begin + k)], c.xy[2 * (begin + k) + 1]}; };
        if (closed) {
            for (std::size_t k = 0; k < n + 3; ++k) v.push_back(vertex(k % n));
        } else {
            v.push_back(vertex(0));
            v.push_back(vertex(0));
            for (std::size_t k = 0; k < n; ++k) v.push_back(vertex(k));
            v.push_back(vertex(n - 1));
            v.push_back(vertex(n - 1));
        }
        const std::size_t spans = v.size() - 3;
        for (std::size_t s = 0; s < spans; ++s) {
            const int last = (!closed && s + 1 == spans) ? samples : samples - 1;  // an open end gets its last point
            for (int k = 0; k <= last; ++k) {
                const auto& w = basis[static_cast<std::size_t>(k)];
                double x = 0, y = 0;
                for (int r = 0; r < 4; ++r) {
                    x += w[r] * v[s + static_cast<std::size_t>(r)][0];
                    y += w[r] * v[s + static_cast<std::size_t>(r)][1];
                }
                out.xy.push_back(x);
                out.xy.push_back(y);
            }
        }
        out.depth.push_back(c.depth[p]);
        out.closed.push_back(closed ? 1 : 0);
        out.offsets.push_back(out.xy.size() / 2);
    }
    return out;
}

}  // namespace wave
