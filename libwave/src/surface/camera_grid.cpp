// Hinsinger, Neyret & Cani's view-dependent sampling (used by Jeschke §5): the surface
// is sampled where pixels look, so the cost follows the screen, not the scene.
#include "libwave/errors.h"
#include "libwave/surface.h"

#include <cmath>
#include <numbers>
#include <string>

namespace wave {

CameraGrid camera_grid(const GridCamera& c) {
    const auto fail = [](const std::string& what) { throw InputError("camera grid: " + what); };
    if (!(c.position[2] > 0.0)) fail("the camera must be above the water (z > 0), got z = " + std::to_string(c.position[2]));
    if (!(c.vertical_fov_degrees > 0.0 && c.vertical_fov_degrees < 170.0))
        fail("vertical_fov_degrees must be in (0, 170), got " + std::to_string(c.vertical_fov_degrees));
    if (c.image_width < 2 || c.image_height < 2 || c.pixel_step < 1 || c.pixel_step > std::min(c.image_width, c.image_height) / 2)
        fail("needs an image of at least 2 x 2 pixels and 1 <= pixel_step <= half its smaller side");
    if (!(c.max_distance > 0.0)) fail("max_distance must be > 0");
    // The view frame: forward f, right r = f × z, up u = r × f (no roll).
    double f[3] = {c.look_at[0] - c.position[0], c.look_at[1] - c.position[1], c.look_at[2] - c.position[2]};
    const double fl = std::hypot(f[0], f[1], f[2]);
    if (!(fl > 0.0)) fail("look_at equals the position");
    for (double& v : f) v /= fl;
    double r[3] = {f[1], -f[0], 0.0};
    const double rl = std::hypot(r[0], r[1]);
    if (!(rl > 1e-9)) fail("the camera looks straight up or down: give look_at a horizontal offset");
    for (double& v : r) v /= rl;
    const double u[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    const double tan_v = std::tan(c.vertical_fov_degrees * std::numbers::pi / 360.0);
    const double tan_h = tan_v * static_cast<double>(c.image_width) / static_cast<double>(c.image_height);

    // Every pixel_step-th pixel centre; rows from the top of the image (far) down (near).
    CameraGrid g;
    for (std::size_t py = 0; py < c.image_height; py += c.pixel_step) ++g.rows;
    for (std::size_t px = 0; px < c.image_width; px += c.pixel_step) ++g.columns;
    std::size_t kept_rows = 0;
    for (std::size_t row = 0; row < g.rows; ++row) {
        const double ny = 1.0 - 2.0 * (static_cast<double>(row * c.pixel_step) + 0.5) / static_cast<double>(c.image_height);
        // With no roll a pixel row is a horizontal line: all of it sees the water or none.
        bool row_ok = true;
        std::vector<double> rx(g.columns), ry(g.columns);
        for (std::size_t col = 0; col < g.columns && row_ok; ++col) {
            const double nx = 2.0 * (static_cast<double>(col * c.pixel_step) + 0.5) / static_cast<double>(c.image_width) - 1.0;
            const double d[3] = {f[0] + nx * tan_h * r[0] + ny * tan_v * u[0], f[1] + nx * tan_h * r[1] + ny * tan_v * u[1],
                                 f[2] + nx * tan_h * r[2] + ny * tan_v * u[2]};
            if (!(d[2] < 0.0)) {
                row_ok = false;
                break;
            }
            const double t = -c.position[2] / d[2];
            rx[col] = c.position[0] + t * d[0];
            ry[col] = c.position[1] + t * d[1];
            if (std::hypot(rx[col] - c.position[0], ry[col] - c.position[1]) > c.max_distance) row_ok = false;
        }
        if (!row_ok) continue;
        g.x.insert(g.x.end(), rx.begin(), rx.end());
        g.y.insert(g.y.end(), ry.begin(), ry.end());
        ++kept_rows;
    }
    g.rows = kept_rows;
    if (g.rows < 2) fail("fewer than two pixel rows see the water within max_distance: aim the camera lower");
    g.triangles = grid_triangles(g.columns, g.rows);
    // Screen rows run towards the camera; make the triangles counter-clockwise from +z.
    const auto area2 = [&](std::size_t t) {
        const std::uint32_t a = g.triangles[3 * t], b = g.triangles[3 * t + 1], e = g.triangles[3 * t + 2];
        return (g.x[b] - g.x[a]) * (g.y[e] - g.y[a]) - (g.x[e] - g.x[a]) * (g.y[b] - g.y[a]);
    };
    if (area2(0) < 0.0)
        for (std::size_t t = 0; t < g.triangles.size() / 3; ++t) std::swap(g.triangles[3 * t + 1], g.triangles[3 * t + 2]);
    return g;
}

}  // namespace wave
