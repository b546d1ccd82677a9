// Gonzato's ray-strip surface (§3.3, fig. 11): the fronts of the adaptive tracer
// tessellated into the flat arrays the per-frame evaluators read; the OpenMesh TriMesh
// with the per-vertex properties is built from them where it is asked for (the PLY).
#include "libwave/errors.h"
#include "libwave/io.h"
#include "libwave/surface.h"

// MeshIO before the mesh headers (docs/build-notes.md).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cmath>
#include <sstream>

namespace wave {
namespace detail {

// Rest positions in double: float would make thin cells near the shore collinear and
// lose the phase's precision over a long ray.
struct StripTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
};

struct RayStripTriMesh {
    OpenMesh::TriMesh_ArrayKernelT<StripTraits> mesh;
    // Names are the PLY property names; the properties are persistent so that the
    // PLY writer emits them (Options::Custom).
    OpenMesh::VPropHandleT<int> ray, step;
    OpenMesh::VPropHandleT<double> phase, k, omega, amplitude, depth, slope, rise, dir_x, dir_y;
    OpenMesh::VPropHandleT<unsigned char> flag, caustic;

    RayStripTriMesh() {
        const auto add = [&](auto& handle, const char* name) {
            mesh.add_property(handle, name);
            mesh.property(handle).set_persistent(true);
        };
        add(ray, "ray");
        add(step, "step");
        add(phase, "phase");
        add(k, "k");
        add(omega, "omega");
        add(amplitude, "amplitude");
        add(depth, "depth");
        add(slope, "slope");
        add(rise, "rise");
        add(dir_x, "dir_x");
        add(dir_y, "dir_y");
        add(flag, "flag");
        add(caustic, "caustic");
    }
};

}  // namespace detail

namespace {

double squared_distance(const FrontSet& f, std::size_t a, std::size_t b) {
    const double dx = f.x[a] - f.x[b], dy = f.y[a] - f.y[b];
    return dx * dx + dy * dy;
}

// Twice the signed area of triangle (a, b, c) at rest.
double doubled_area(const FrontSet& f, std::size_t a, std::size_t b, std::size_t c) {
    return (f.x[b] - f.x[a]) * (f.y[c] - f.y[a]) - (f.y[b] - f.y[a]) * (f.x[c] - f.x[a]);
}

}  // namespace

RayStrips build_ray_strips(const FrontSet& f) {
    // The flat arrays the evaluators read: one vertex per front point, in order.
    const std::size_t n = f.x.size();
    RayStrips out;
    out.omega = f.omega;
    out.ray.assign(f.ray.begin(), f.ray.end());
    out.step.resize(n);
    for (std::size_t fr = 0; fr < f.front_count(); ++fr)
        for (std::size_t i = f.front_offsets[fr]; i < f.front_offsets[fr + 1]; ++i) out.step[i] = static_cast<std::uint32_t>(fr);
    out.x = f.x;
    out.y = f.y;
    out.dir_x = f.dir_x;
    out.dir_y = f.dir_y;
    out.phase = f.phase;
    out.k = f.k;
    out.amplitude = f.amplitude;
    out.depth = f.depth;
    out.slope = f.slope;
    out.rise = f.rise;
    out.flag = f.flag;
    out.caustic = f.caustic;
    out.entry_break_phase = f.entry_break_phase;
    out.triangles.reserve(6 * n);

    const auto add_face = [&](std::size_t a, std::size_t b, std::size_t c) {
        // Zero area at rest: rays that met (on the shore) — no surface there.
        const double area2 = doubled_area(f, a, b, c);
        const double scale = squared_distance(f, a, b) + squared_distance(f, b, c) + squared_distance(f, c, a);
        if (!(std::abs(area2) > 1e-9 * scale)) {
            ++out.degenerate_skipped;
            return;
        }
        out.triangles.insert(out.triangles.end(), {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                                                   static_cast<std::uint32_t>(c)});
    };

    // Rays are ordered along e = (−d_y, d_x), left of the travel direction d, so for a
    // cell P_j P_j+1 (previous front) C_i C_i+1 (this front) the counter-clockwise
    // triangles are (P_j, C_i, P_j+1) and (P_j, C_i, C_i+1).
    std::uint32_t max_id = 0;
    for (const std::uint32_t id : f.ray) max_id = std::max(max_id, id);
    std::vector<std::int64_t> index_in_previous(std::size_t{max_id} + 1, -1);
    // Zips P[p0..p1] with C[c0..c1] by the shorter diagonal.
    const auto zip = [&](std::size_t p, std::size_t p1, std::size_t c, std::size_t c1) {
        while (p < p1 || c < c1) {
            const bool advance_previous =
                c == c1 || (p < p1 && squared_distance(f, p + 1, c) <= squared_distance(f, p, c + 1));
            if (advance_previous) {
                add_face(p, c, p + 1);
                ++p;
            } else {
                add_face(p, c, c + 1);
                ++c;
            }
        }
    };
    for (std::size_t fr = 1; fr < f.front_count(); ++fr) {
        const std::size_t p_begin = f.front_offsets[fr - 1], p_end = f.front_offsets[fr];
        const std::size_t c_begin = f.front_offsets[fr], c_end = f.front_offsets[fr + 1];
        if (p_begin == p_end || c_begin == c_end) continue;
        for (std::size_t i = p_begin; i < p_end; ++i) index_in_previous[f.ray[i]] = static_cast<std::int64_t>(i);
        // Rays present in both fronts anchor the zipper (ray order is kept along a front).
        std::size_t p = p_begin, c = c_begin;
        for (std::size_t i = c_begin; i < c_end; ++i) {
            const std::int64_t j = index_in_previous[f.ray[i]];
            if (j < 0) continue;
            zip(p, static_cast<std::size_t>(j), c, i);
            p = static_cast<std::size_t>(j);
            c = i;
        }
        zip(p, p_end - 1, c, c_end - 1);
        for (std::size_t i = p_begin; i < p_end; ++i) index_in_previous[f.ray[i]] = -1;
    }
    return out;
}

namespace {

// The strips as an OpenMesh TriMesh with the per-vertex properties (the PLY's):
// vertices and faces in the arrays' order. RuntimeError if OpenMesh rejects a face.
void fill_trimesh(const RayStrips& s, detail::RayStripTriMesh& tri) {
    auto& m = tri.mesh;
    const std::size_t n = s.vertex_count();
    m.reserve(n, 3 * n, s.triangle_count());
    std::vector<OpenMesh::VertexHandle> vh(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto v = m.add_vertex({s.x[i], s.y[i], 0.0});
        vh[i] = v;
        m.property(tri.ray, v) = static_cast<int>(s.ray[i]);
        m.property(tri.step, v) = static_cast<int>(s.step[i]);
        m.property(tri.phase, v) = s.phase[i];
        m.property(tri.k, v) = s.k[i];
        m.property(tri.omega, v) = s.omega;
        m.property(tri.amplitude, v) = s.amplitude[i];
        m.property(tri.depth, v) = s.depth[i];
        m.property(tri.slope, v) = s.slope[i];
        m.property(tri.rise, v) = s.rise[i];
        m.property(tri.dir_x, v) = s.dir_x[i];
        m.property(tri.dir_y, v) = s.dir_y[i];
        m.property(tri.flag, v) = static_cast<unsigned char>(s.flag[i]);
        m.property(tri.caustic, v) = s.caustic[i];
    }
    for (std::size_t t = 0; t + 2 < s.triangles.size(); t += 3) {
        const std::uint32_t a = s.triangles[t], b = s.triangles[t + 1], c = s.triangles[t + 2];
        if (!m.add_face(vh[a], vh[b], vh[c]).is_valid())
            throw InternalError("ray strips: OpenMesh rejected a face between fronts " + std::to_string(s.step[a]) +
                               " and " + std::to_string(s.step[c]) + " (a non-manifold strip)");
    }
}

}  // namespace

void write_ray_strips_ply(const RayStrips& strips, const std::string& path) {
    detail::RayStripTriMesh tri;
    fill_trimesh(strips, tri);
    std::ostringstream bytes(std::ios::binary);
    const OpenMesh::IO::Options options = OpenMesh::IO::Options::Binary | OpenMesh::IO::Options::LSB |
                                          OpenMesh::IO::Options::Custom;
    if (!OpenMesh::IO::write_mesh(tri.mesh, bytes, ".ply", options))
        throw RuntimeError(path + ": OpenMesh could not encode the ray strips as PLY");
    write_file_atomic(path, bytes.view());
}

}  // namespace wave
