// libwave from a raw grid in memory: no file reader, no GDAL (components core and export).
//
//   raw_grid OUT.glb
//
// Builds a plane beach as an array of elevations — 1:20, the shoreline at x = 150 m, 5 m
// deep offshore — the way a pipeline hands libwave a terrain it already holds, makes a
// Seafloor of it (seafloor_from_grid: node (0, 0) at the origin, a node, not a cell's
// corner), and checks what a hand-made grid gets wrong: the depth between the nodes and
// the shoreline's isobath, which must cross at x = 150 m exactly (half a cell off is 1 m
// here). Then it traces a 6 s swell over it, tessellates the ray strips, meshes the water,
// moves it with Gonzato's profile for 12 frames at 12 frames/s and writes them as one
// animated .glb (morph targets). Exit 0 when every check holds, 1 when one does not, 2 on
// bad input.
#include <libwave/bathymetry.h>
#include <libwave/errors.h>
#include <libwave/export.h>
#include <libwave/isobath.h>
#include <libwave/motion.h>
#include <libwave/shade.h>
#include <libwave/surface.h>
#include <libwave/trace.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <span>
#include <string>
#include <vector>

namespace {

constexpr double kSlope = 0.05, kShore = 150.0, kDeep = 5.0;

double elevation(double x) { return std::clamp(kSlope * (x - kShore), -kDeep, 2.0); }

bool check(bool ok, const char* what) {
    if (!ok) std::printf("check failed: %s\n", what);
    return ok;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s OUT.glb\n", argv[0]);
        return 2;
    }
    try {
        // The caller's array: 121 × 41 nodes 2 m apart from (0, 0), row after row.
        wave::ElevationGrid g;
        g.nx = 121;
        g.ny = 41;
        g.dx = g.dy = 2.0;
        g.z.resize(g.nx * g.ny);
        for (std::size_t j = 0; j < g.ny; ++j)
            for (std::size_t i = 0; i < g.nx; ++i) g.at(i, j) = elevation(g.x0 + g.dx * static_cast<double>(i));
        const wave::Seafloor seafloor = wave::seafloor_from_grid(g, {}, {}, "plane beach in memory");

        // Where the nodes are: the depth between them is the plane's, and the shoreline
        // (depth 0) crosses at x = 150 m.
        bool ok = true;
        double worst = 0.0;
        for (double x = 0.5; x < 238.0; x += 3.7)
            if (elevation(x) > -kDeep + 0.1 && elevation(x) < 1.9)
                worst = std::max(worst, std::abs(wave::depth_at(seafloor.grid, x, 37.3) + elevation(x)));
        ok = check(worst < 1e-9, "the depth between the nodes is the plane's") && ok;
        wave::IsobathOptions levels;
        levels.levels = {2.0};  // and the shoreline (include_shoreline)
        const wave::DepthContours isobaths = wave::extract_isobaths(seafloor, levels);
        double shore_error = 0.0, two_metre_error = 0.0;
        std::size_t shore_points = 0, two_metre_points = 0;
        for (std::size_t p = 0; p < isobaths.size(); ++p)
            for (std::size_t k = isobaths.offsets[p]; k < isobaths.offsets[p + 1]; ++k) {
                const double expected = kShore - isobaths.depth[p] / kSlope;
                const bool shore = isobaths.depth[p] == 0.0;
                double& e = shore ? shore_error : two_metre_error;
                e = std::max(e, std::abs(isobaths.xy[2 * k] - expected));
                ++(shore ? shore_points : two_metre_points);
            }
        ok = check(shore_points >= 2 && two_metre_points >= 2, "the shoreline and the 2 m isobath") && ok;
        ok = check(shore_error < 1e-6 && two_metre_error < 1e-6, "the isobaths cross where the plane does") && ok;

        // A 6 s swell from the open sea (−x) to the beach, its fronts, strips and water mesh.
        const wave::WaveTrain swell{.period = 6.0, .amplitude = 0.3, .direction_x = 1.0, .direction_y = 0.0};
        wave::FrontOptions fronts;
        fronts.ray_spacing = 2.0;
        fronts.step = 1.0;
        fronts.split_distance = 4.0;
        const wave::FrontSet traced = wave::trace_fronts(seafloor, swell, fronts, &isobaths);
        const wave::RayStrips strips = wave::build_ray_strips(traced);
        const wave::WaterMesh mesh = wave::mesh_water(seafloor, wave::wavelength_edge_size(seafloor, swell, 12.0));
        const wave::RayStrips on_mesh = wave::resample_ray_strips(strips, seafloor, mesh.x, mesh.y, mesh.triangles);
        const wave::GonzatoMotionPlan motion = wave::plan_gonzato_motion(on_mesh);
        const std::size_t n = mesh.vertex_count();
        ok = check(n > 1000, "a water mesh") && ok;
        double wettest = -1e9;
        for (std::size_t v = 0; v < n; ++v) wettest = std::max(wettest, mesh.x[v]);
        ok = check(wettest <= kShore + 1e-6, "the water ends at the shoreline") && ok;

        // 12 frames into caller-owned buffers, then one animated .glb.
        constexpr std::size_t frames = 12;
        const wave::VertexFaces adjacency = wave::vertex_faces(n, mesh.triangles);
        std::vector<float> positions(3 * n * frames), normals(3 * n * frames), texcoords(2 * n);
        float highest = 0.0f;
        for (std::size_t f = 0; f < frames; ++f) {
            const std::span<float> p(&positions[3 * n * f], 3 * n);
            wave::evaluate_gonzato_motion(motion, static_cast<double>(f) / 12.0, p);
            wave::vertex_normals(p, mesh.triangles, adjacency, std::span<float>(&normals[3 * n * f], 3 * n));
            for (std::size_t v = 0; v < n; ++v) highest = std::max(highest, p[3 * v + 2]);
        }
        ok = check(highest > 0.2f && highest < 1.5f, "crests about the swell's height") && ok;
        wave::domain_texcoords(seafloor.grid, mesh.x, mesh.y, texcoords);
        wave::MorphAnimationView view;
        view.triangles = mesh.triangles;
        view.vertex_count = n;
        view.frame_count = frames;
        view.positions = positions;
        view.normals = normals;
        view.texcoords = texcoords;
        view.fps = 12.0;
        const std::string glb = wave::gltf_morph_glb(view);
        std::ofstream out(argv[1], std::ios::binary);
        out.write(glb.data(), static_cast<std::streamsize>(glb.size()));
        if (!out.flush()) {
            std::fprintf(stderr, "error: could not write %s\n", argv[1]);
            return 2;
        }
        std::printf("raw grid %zu x %zu nodes: isobaths at x = 150 m and 110 m (errors %.2g, %.2g m), %zu rays, "
                    "water mesh %zu vertices, %zu frames written to %s\n",
                    g.nx, g.ny, shore_error, two_metre_error, traced.initial_rays + traced.inserted_rays, n, frames, argv[1]);
        return ok ? 0 : 1;
    } catch (const wave::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
