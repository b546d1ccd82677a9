// The wave field resampled on a regular raster over the seafloor, and a PNG plot of
// H/H0 with the depth contours and a labelled colour scale (stb): the core component.
#include "libwave/field.h"

#include "core/format.h"
#include "libwave/errors.h"

#include "libwave/io.h"

#include <stb/stb_easy_font.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace wave {

FieldRaster rasterize_wave_field(const WaveField& field, const Seafloor& seafloor) {
    const ElevationGrid& g = seafloor.grid;
    FieldRaster r;
    r.spacing = std::min(field.dx, field.dy);
    r.x0 = g.x0;
    r.y0 = g.y0;
    r.nx = static_cast<std::size_t>(std::floor((g.x_max() - g.x0) / r.spacing)) + 1;
    r.ny = static_cast<std::size_t>(std::floor((g.y_max() - g.y0) / r.spacing)) + 1;
    r.incident_height = field.incident_height;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    r.height_ratio.assign(r.nx * r.ny, nan);
    r.phase.assign(r.nx * r.ny, nan);
    r.direction_deg.assign(r.nx * r.ny, nan);
    for (std::size_t j = 0; j < r.ny; ++j)
        for (std::size_t i = 0; i < r.nx; ++i) {
            const double x = r.x0 + static_cast<double>(i) * r.spacing, y = r.y0 + static_cast<double>(j) * r.spacing;
            const FieldSample s = sample_wave_field(field, x, y);
            if (!s.wet || depth_at(g, x, y) <= 0.0) continue;
            const std::size_t n = j * r.nx + i;
            r.height_ratio[n] = static_cast<float>(2.0 * std::abs(s.eta) / field.incident_height);
            r.phase[n] = static_cast<float>(std::arg(s.eta));
            r.direction_deg[n] = static_cast<float>(std::atan2(s.dir_y, s.dir_x) * 180.0 / std::numbers::pi);
            r.ratio_max = std::max(r.ratio_max, r.height_ratio[n]);
        }
    return r;
}

namespace {

// A perceptual blue → yellow → red ramp for H/H0 in [0, top].
std::array<std::uint8_t, 3> ramp(double v, double top) {
    static constexpr std::array<std::array<double, 3>, 5> stops{
        {{0.19, 0.07, 0.42}, {0.13, 0.45, 0.74}, {0.35, 0.78, 0.45}, {0.99, 0.86, 0.25}, {0.80, 0.10, 0.15}}};
    const double t = std::clamp(v / top, 0.0, 1.0) * 4.0;
    const std::size_t k = std::min<std::size_t>(3, static_cast<std::size_t>(t));
    const double f = t - static_cast<double>(k);
    std::array<std::uint8_t, 3> c{};
    for (std::size_t i = 0; i < 3; ++i)
        c[i] = static_cast<std::uint8_t>(std::lround(255.0 * (stops[k][i] * (1.0 - f) + stops[k + 1][i] * f)));
    return c;
}

struct Canvas {
    int w, h;
    std::vector<std::uint8_t> rgb;
    void dot(int x, int y, std::array<std::uint8_t, 3> c) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        std::copy(c.begin(), c.end(), &rgb[static_cast<std::size_t>(y * w + x) * 3]);
    }
    void text(int x, int y, const std::string& s, int scale) {
        static thread_local std::vector<char> buffer(99999);
        const int quads = stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, buffer.data(), static_cast<int>(buffer.size()));
        const float* v = reinterpret_cast<const float*>(buffer.data());
        for (int q = 0; q < quads; ++q) {
            const float* quad = v + q * 16;  // 4 vertices of x, y, z, colour
            for (int yy = static_cast<int>(quad[1]) * scale; yy < static_cast<int>(quad[9]) * scale; ++yy)
                for (int xx = static_cast<int>(quad[0]) * scale; xx < static_cast<int>(quad[4]) * scale; ++xx)
                    dot(x + xx, y + yy, {0, 0, 0});
        }
    }
};

}  // namespace

std::string field_plot_png(const FieldRaster& r, const DepthContours& isobaths, const std::string& title) {
    if (r.nx == 0 || r.ny == 0) throw InputError("wave field: an empty raster has no plot");
    const double scale = std::min(900.0 / static_cast<double>(r.nx), 700.0 / static_cast<double>(r.ny));
    const int pw = std::max(1, static_cast<int>(std::lround(scale * static_cast<double>(r.nx))));
    const int ph = std::max(1, static_cast<int>(std::lround(scale * static_cast<double>(r.ny))));
    const int left = 20, top = 40, bar = 150;
    Canvas c{pw + left + bar, ph + top + 30, {}};
    c.rgb.assign(static_cast<std::size_t>(c.w * c.h) * 3, 255);
    // H/H0 up to the next half above the largest value (at least 2).
    const double top_value = std::max(2.0, std::ceil(2.0 * static_cast<double>(r.ratio_max)) / 2.0);
    for (int py = 0; py < ph; ++py)
        for (int px = 0; px < pw; ++px) {
            const std::size_t i = std::min(r.nx - 1, static_cast<std::size_t>(px / scale));
            const std::size_t j = std::min(r.ny - 1, static_cast<std::size_t>((ph - 1 - py) / scale));
            const float v = r.height_ratio[j * r.nx + i];
            c.dot(left + px, top + py, std::isnan(v) ? std::array<std::uint8_t, 3>{150, 140, 120} : ramp(v, top_value));
        }
    // The depth contours, white.
    const double x1 = r.x0 + r.spacing * static_cast<double>(r.nx - 1), y1 = r.y0 + r.spacing * static_cast<double>(r.ny - 1);
    for (std::size_t l = 0; l < isobaths.size(); ++l)
        for (std::size_t p = isobaths.offsets[l]; p + 1 < isobaths.offsets[l + 1]; ++p) {
            const double ax = isobaths.xy[2 * p], ay = isobaths.xy[2 * p + 1], bx = isobaths.xy[2 * p + 2], by = isobaths.xy[2 * p + 3];
            const int steps = 1 + static_cast<int>(std::hypot(bx - ax, by - ay) * scale / r.spacing);
            for (int s = 0; s <= steps; ++s) {
                const double t = static_cast<double>(s) / steps, x = ax + t * (bx - ax), y = ay + t * (by - ay);
                if (x < r.x0 || x > x1 || y < r.y0 || y > y1) continue;
                c.dot(left + static_cast<int>((x - r.x0) / r.spacing * scale),
                      top + ph - 1 - static_cast<int>((y - r.y0) / r.spacing * scale), {255, 255, 255});
            }
        }
    // The colour scale with its labels.
    const int bx = left + pw + 25;
    for (int py = 0; py < ph; ++py)
        for (int px = 0; px < 24; ++px) c.dot(bx + px, top + py, ramp(top_value * (1.0 - static_cast<double>(py) / (ph - 1)), top_value));
    for (double v = 0.0; v <= top_value + 1e-9; v += 0.5) {
        const int py = top + static_cast<int>(std::lround((1.0 - v / top_value) * (ph - 1)));
        for (int px = 0; px < 6; ++px) c.dot(bx + 24 + px, py, {0, 0, 0});
        c.text(bx + 34, py - 6, detail::format_number(v), 2);
    }
    c.text(bx, top + ph + 8, "H/H0", 2);
    c.text(left, 8, title, title.size() * 12 > static_cast<std::size_t>(c.w - left) ? 1 : 2);
    char extent[200];
    std::snprintf(extent, sizeof extent, "x %.4g .. %.4g m, y %.4g .. %.4g m; white: depth contours; grey: land", r.x0, x1, r.y0, y1);
    c.text(left, top + ph + 8, extent, 1);
    return png_bytes(Image{.width = static_cast<std::size_t>(c.w), .height = static_cast<std::size_t>(c.h), .rgb = std::move(c.rgb)});
}

}  // namespace wave
