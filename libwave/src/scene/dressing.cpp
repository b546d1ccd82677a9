// Dressing the single-file forms: the rest texture coordinates, the seafloor mesh with
// its colours and the apron under the far field, camera, sun and material.
#include "libwave/scene.h"

#include "core/memory.h"
#include "pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <utility>
#include <vector>

namespace wave::detail {

// TEXCOORD_0: the rest position over the seafloor's rectangle (the patch for the
// ocean: it tiles), u along +x, v down (glTF's image origin is top-left).
void rest_texcoords(const ScenePlan& plan, const Refinement* refined, SceneAnimation& a) {
    const std::size_t n = a.vertex_count;
    std::vector<double> fine_x, fine_y;
    if (refined) {
        fine_x.resize(n);
        fine_y.resize(n);
        apply_refinement(*refined, std::span<const double>(plan.rest_x), 1, fine_x);
        apply_refinement(*refined, std::span<const double>(plan.rest_y), 1, fine_y);
    }
    size_for_overwrite(a.texcoords, 2 * n);
    domain_texcoords(plan.seafloor.grid, refined ? fine_x : plan.rest_x, refined ? fine_y : plan.rest_y, a.texcoords);
}

namespace {

// What colours the dressing's seafloor: its greatest depth, and the top of the beach.
struct FloorPalette {
    double depth_max = 1e-9;  // m
    double beach_top = 0.0;   // m above still water: sand below, grass above
};

// The beach's top: the highest wave's height (2 A) above still water, about where its
// swash reaches. The colours are per vertex and blend across a grid cell, so a grass line
// at the waterline itself drew the grid's diagonals into the water's edge: green teeth a
// cell apart in every close-up of the shore. Sand on both sides of the edge keeps it clean.
FloorPalette floor_palette(const Scene& scene, const Seafloor& seafloor) {
    FloorPalette p;
    p.depth_max = std::max(1e-9, seafloor_stats(seafloor).depth_max);
    for (const WaveTrain& t : scene.waves) p.beach_top = std::max(p.beach_top, 2.0 * t.amplitude);
    return p;
}

// A seafloor colour for an elevation z (m): pale sand up to the beach's top, darkening
// with depth below the waterline (the water itself adds the blue), turning to grass over
// as much height again above the beach (a gradient over several cells, not a grass line
// along the grid's diagonals) (linear RGB).
std::array<float, 3> seafloor_colour(double z, const FloorPalette& p) {
    const double wet = std::clamp(-z / p.depth_max, 0.0, 1.0);
    const double grass = p.beach_top > 0.0 ? std::clamp(z / p.beach_top - 1.0, 0.0, 1.0) : (z > 0.0 ? 1.0 : 0.0);
    const auto mix = [&](double sand, double deep, double green) {
        return static_cast<float>((1.0 - grass) * (sand + (deep - sand) * wet) + grass * green);
    };
    return {mix(0.6, 0.25, 0.16), mix(0.5, 0.2, 0.2), mix(0.32, 0.12, 0.08)};
}

// Under the far field's skirt: the terrain beyond the data (terrain_elevation) from the
// grid's border nodes out to the skirt's far rectangle, so that the water beyond the
// domain lies over a bottom and the land goes on to the horizon. The grid's nodes are
// the first cols × rows of `a`'s seafloor vertices. Rings of the grid's rectangle
// offset by d, a cell (`cell`) apart near the border and 1.25 × further out each, up
// to `reach`, their vertices about a tenth of d apart (a cell near the border), so
// that the hills the terrain draws stay resolved and the far ranges' crests (four
// vertices each) break the skyline. Before, two rings extruded each border node's elevation and colour to the
// far rectangle: whatever the border held ran on unchanged to the horizon — behind the
// bay's head, the low sand-coloured land where the bay cuts deepest drew a pale wedge,
// a road from the beach to the horizon.
//
// Rings are zipped by a parameter tau that gives a point beyond a side the place of its
// foot on that side (side + kCorner + (1 − 2 kCorner) · the foot's fraction), and the
// corner's quadrant the kCorner either side of the corner: a line out from the border
// (a side's node, or the skirt's cut where the shoreline meets the border, a vertex on
// every ring) is then a chain of mesh edges, and no triangle of the far rings spans the
// land beside a cut and the sea beyond it (one 1.25 km across, 5 km out, dipped the
// bay's land below still water where no water lies).
void add_seafloor_apron(const ElevationGrid& g, double cell, double reach, std::size_t cols, std::size_t rows,
                        const FloorPalette& palette, SceneAnimation& a) {
    constexpr double kCorner = 0.02;
    const TerrainBeyond terrain = plan_terrain_beyond(g);
    const bool mapped = !a.seafloor_texcoords.empty();
    const double x0 = a.seafloor_positions[0], y0 = a.seafloor_positions[1];
    const double x1 = a.seafloor_positions[3 * (cols * rows - 1)], y1 = a.seafloor_positions[3 * (cols * rows - 1) + 1];
    const double length[4] = {x1 - x0, y1 - y0, x1 - x0, y1 - y0};
    struct Node {
        std::uint32_t index;
        double tau;
    };
    // Ring 0: the grid's border nodes counter-clockwise, each corner once (just before its
    // side's tau, so that the corner's quadrant fans from it).
    std::vector<Node> inner;
    const auto at = [cols](std::size_t c, std::size_t r) { return static_cast<std::uint32_t>(r * cols + c); };
    const double fc = static_cast<double>(cols - 1), fr = static_cast<double>(rows - 1);
    const auto main_tau = [](int side, double fraction) { return side + kCorner + (1.0 - 2.0 * kCorner) * fraction; };
    for (int side = 0; side < 4; ++side) {
        const std::size_t count = side % 2 == 0 ? cols - 1 : rows - 1;
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t v = side == 0 ? at(k, 0) : side == 1 ? at(cols - 1, k) : side == 2 ? at(cols - 1 - k, rows - 1) : at(0, rows - 1 - k);
            inner.push_back({v, k == 0 ? side - 0.5 * kCorner : main_tau(side, static_cast<double>(k) / (side % 2 == 0 ? fc : fr))});
        }
    }
    // Where the shoreline meets each side (the skirt's cuts): a fraction of the side.
    std::array<std::vector<double>, 4> cuts;
    const double side_start[4] = {0.0, length[0], length[0] + length[1], 2.0 * length[0] + length[1]};
    for (const double c : terrain.shore)
        for (int side = 0; side < 4; ++side)
            if (c > side_start[side] && c < side_start[side] + length[side]) cuts[static_cast<std::size_t>(side)].push_back((c - side_start[side]) / length[side]);
    // Inner ring → outer ring, both closed and ordered by tau: advance the one whose
    // next node comes first (triangles counter-clockwise, as the grid's).
    const auto zip = [&](std::vector<Node> in, std::vector<Node> out) {
        in.push_back({in.front().index, in.front().tau + 4.0});
        out.push_back({out.front().index, out.front().tau + 4.0});
        std::size_t i = 0, o = 0;
        while (i + 1 < in.size() || o + 1 < out.size()) {
            if (o + 1 < out.size() && (i + 1 == in.size() || out[o + 1].tau <= in[i + 1].tau)) {
                a.seafloor_triangles.insert(a.seafloor_triangles.end(), {in[i].index, out[o].index, out[o + 1].index});
                ++o;
            } else {
                a.seafloor_triangles.insert(a.seafloor_triangles.end(), {in[i].index, out[o].index, in[i + 1].index});
                ++i;
            }
        }
    };
    double d = 0.0;
    while (d < reach) {
        d = std::min(reach, std::max(1.25 * d, d + cell));
        const double spacing = std::max(cell, 0.1 * d);
        const double corner[5][2] = {{x0 - d, y0 - d}, {x1 + d, y0 - d}, {x1 + d, y1 + d}, {x0 - d, y1 + d}, {x0 - d, y0 - d}};
        std::vector<Node> outer;
        for (int side = 0; side < 4; ++side) {
            // Along the side from its corner: the corner piece [0, d), the foot's piece
            // [d, d + L) and the next corner's piece [d + L, L + 2d), at (a, tau).
            const double L = length[side];
            std::vector<std::pair<double, double>> points;
            const auto corner_pieces = static_cast<std::size_t>(std::ceil(d / spacing));
            const auto main_pieces = static_cast<std::size_t>(std::max(1.0, std::ceil(L / spacing)));
            for (std::size_t j = 0; j < corner_pieces; ++j) {
                const double f = static_cast<double>(j) / static_cast<double>(corner_pieces);
                points.push_back({d * f, side + kCorner * f});
                points.push_back({d + L + d * f, side + 1.0 - kCorner + kCorner * f});
            }
            for (std::size_t j = 0; j < main_pieces; ++j) {
                const double f = static_cast<double>(j) / static_cast<double>(main_pieces);
                points.push_back({d + L * f, main_tau(side, f)});
            }
            for (const double f : cuts[static_cast<std::size_t>(side)]) points.push_back({d + L * f, main_tau(side, f)});
            std::sort(points.begin(), points.end(), [](const auto& p, const auto& q) { return p.second < q.second; });
            points.erase(std::unique(points.begin(), points.end(), [](const auto& p, const auto& q) { return q.second - p.second < 1e-12; }),
                         points.end());
            const double ax = corner[side][0], ay = corner[side][1], bx = corner[side + 1][0], by = corner[side + 1][1];
            const double span = L + 2.0 * d;
            for (const auto& [along, tau] : points) {
                const double x = ax + (bx - ax) * along / span, y = ay + (by - ay) * along / span;
                const double z = terrain_elevation(terrain, x, y, spacing);
                a.seafloor_positions.insert(a.seafloor_positions.end(), {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
                const auto colour = seafloor_colour(z, palette);
                a.seafloor_colors.insert(a.seafloor_colors.end(), colour.begin(), colour.end());
                if (mapped)  // the caustic maps' edge texels stretch outwards
                    a.seafloor_texcoords.insert(a.seafloor_texcoords.end(),
                                                {static_cast<float>(std::clamp((x - g.x0) / (g.x_max() - g.x0), 0.0, 1.0)),
                                                 static_cast<float>(1.0 - std::clamp((y - g.y0) / (g.y_max() - g.y0), 0.0, 1.0))});
                outer.push_back({static_cast<std::uint32_t>(a.seafloor_positions.size() / 3 - 1), tau});
            }
        }
        zip(std::move(inner), outer);
        inner = std::move(outer);
    }
}

}  // namespace

// The seafloor mesh (at most 256 nodes a side), camera, sun and material settings the
// single-file forms carry beside the water (/outputs/seafloor, camera, sun, material).
void dress_animation(const Scene& scene, const ScenePlan& plan, SceneAnimation& a) {
    SceneDressing d;
    d.water_material = scene.dress_material;
    const PreviewOptions view = scene_preview(scene, plan.seafloor);
    if (scene.dress_camera) {
        d.camera = true;
        d.camera_position = view.camera;
        d.camera_rotation = gltf_look_rotation(view.camera, view.look_at);
        d.camera_yfov = view.vertical_fov_degrees * std::numbers::pi / 180.0;
        d.camera_aspect = static_cast<double>(view.width) / static_cast<double>(view.height);
    }
    if (scene.dress_sun) {
        const double az = view.sun_azimuth_degrees * std::numbers::pi / 180.0, el = view.sun_elevation_degrees * std::numbers::pi / 180.0;
        d.sun = true;  // shining from the sun's direction towards the origin
        d.sun_rotation = gltf_look_rotation({std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)}, {0.0, 0.0, 0.0});
    }
    const ElevationGrid& g = plan.seafloor.grid;
    if (scene.dress_seafloor && surface_kind_traces(scene.surface_kind) != Traced::nothing && g.nx >= 2 && g.ny >= 2) {
        const std::size_t step = std::max<std::size_t>(1, (std::max(g.nx, g.ny) + 255) / 256);
        const std::size_t cols = (g.nx - 1) / step + 1, rows = (g.ny - 1) / step + 1;
        const FloorPalette palette = floor_palette(scene, plan.seafloor);
        for (std::size_t r = 0; r < rows; ++r)
            for (std::size_t c = 0; c < cols; ++c) {
                const std::size_t i = std::min(g.nx - 1, c * step), j = std::min(g.ny - 1, r * step);
                const double z = g.z[j * g.nx + i];
                a.seafloor_positions.insert(a.seafloor_positions.end(),
                                            {static_cast<float>(g.x0 + static_cast<double>(i) * g.dx),
                                             static_cast<float>(g.y0 + static_cast<double>(j) * g.dy), static_cast<float>(z)});
                const auto colour = seafloor_colour(z, palette);
                a.seafloor_colors.insert(a.seafloor_colors.end(), colour.begin(), colour.end());
            }
        a.seafloor_triangles = grid_triangles(cols, rows);
        if (!a.caustics.empty()) {  // the caustic maps' frame: the grid's rectangle, row 0 at its top
            const std::size_t count = a.seafloor_positions.size() / 3;
            a.seafloor_texcoords.resize(2 * count);
            for (std::size_t v = 0; v < count; ++v) {
                a.seafloor_texcoords[2 * v] = static_cast<float>((a.seafloor_positions[3 * v] - g.x0) / (g.x_max() - g.x0));
                a.seafloor_texcoords[2 * v + 1] = static_cast<float>(1.0 - (a.seafloor_positions[3 * v + 1] - g.y0) / (g.y_max() - g.y0));
            }
            d.caustic_images = kCausticImages;
            d.caustic_frames = a.loop_frames;
            d.caustic_fps = scene.fps;
            d.caustic_full_scale = scene.underwater->full_scale;
        }
        if (!a.sunbeams.empty()) {
            d.sunbeam_volumes = kSunbeamVolumes;
            d.sunbeam_frames = a.loop_frames;
            d.sunbeam_attenuation = scene.underwater->attenuation;
            const CausticOptions o = scene_caustic_options(scene, plan);
            d.sunbeam_direction = refracted_beam(o.sun, o.water_index);
            d.sunbeam_fps = scene.fps;
        }
        if (plan.skirt.vertex_count() > 0)
            add_seafloor_apron(g, static_cast<double>(step) * std::min(g.dx, g.dy), plan.skirt.reach, cols, rows, palette, a);
    }
    a.dressing = d;
}

}  // namespace wave::detail
