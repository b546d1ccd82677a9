// Draws Gonzato's vertical-section profile (eq. 7) of one swell at several depths on a
// 1:10 beach, as docs/gonzato-profile.png: each row is one wavelength of the surface at
// one depth (rest level in grey, the section in blue, Gerstner's deep-water trochoid of
// the same R and k dashed), so the steepening, the running crest and the plunging lip
// can be compared with the paper's figures 6 and 8.
//
//   profile_plot [out.png]
#include <libwave/motion.h>
#include <libwave/physics.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#include <stb/stb_easy_font.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

namespace {

constexpr int width = 1400, row_height = 150;

struct Canvas {
    int w, h;
    std::vector<unsigned char> rgb;
    Canvas(int w_, int h_) : w(w_), h(h_), rgb(static_cast<std::size_t>(w_ * h_ * 3), 255) {}
    void dot(int x, int y, const unsigned char c[3]) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        for (int i = 0; i < 3; ++i) rgb[static_cast<std::size_t>((y * w + x) * 3 + i)] = c[i];
    }
    void line(double x0, double y0, double x1, double y1, const unsigned char c[3], int thick = 2, bool dashed = false) {
        const int n = static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
        for (int i = 0; i <= n; ++i) {
            if (dashed && (i / 6) % 2) continue;
            const double t = static_cast<double>(i) / n;
            const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))), y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
            for (int a = 0; a < thick; ++a)
                for (int b = 0; b < thick; ++b) dot(x + a, y + b, c);
        }
    }
    void text(int x, int y, const std::string& s, int scale = 2) {
        static char buffer[60000];
        const int quads = stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, buffer, sizeof buffer);
        const unsigned char black[3] = {0, 0, 0};
        const float* v = reinterpret_cast<const float*>(buffer);
        for (int q = 0; q < quads; ++q) {
            const float* p = v + q * 16;  // 4 vertices of x, y, z, colour
            for (int yy = static_cast<int>(p[1] * scale); yy < static_cast<int>(p[9] * scale); ++yy)
                for (int xx = static_cast<int>(p[0] * scale); xx < static_cast<int>(p[4] * scale); ++xx) dot(x + xx, y + yy, black);
        }
    }
};

}  // namespace

int main(int argc, char** argv) {
    const std::string out = argc > 1 ? argv[1] : "gonzato-profile.png";
    const double period = 5.0, deep_amplitude = 0.3, beach_slope = 0.1;
    const double omega = 2.0 * std::numbers::pi / period;
    const std::vector<double> depths = {12.0, 6.0, 3.0, 2.0, 1.5, 1.1, 0.8};
    const double metres_to_px = 52.0;  // same scale on both axes
    Canvas c(width, row_height * static_cast<int>(depths.size()) + 40);
    c.text(10, 8, "Gonzato eq. 7, T = 5 s, A_inf = 0.3 m, beach 1:10, default parameters; blue: profile, dashed: Gerstner (same R, k)");
    const unsigned char grey[3] = {170, 170, 170}, blue[3] = {20, 70, 200}, red[3] = {200, 40, 40};
    const wave::GonzatoProfileOptions options;
    for (std::size_t row = 0; row < depths.size(); ++row) {
        const double h = depths[row];
        const wave::LinearWave w = wave::linear_wave(omega, h);
        const double R = std::min(deep_amplitude * w.shoaling, 0.5 * wave::kBreakerIndex * h);
        const wave::ProfileShape s = wave::gonzato_shape(R, w.k, h, beach_slope, options);
        const double base_y = 40.0 + row_height * (static_cast<double>(row) + 0.55);
        char label[160];
        std::snprintf(label, sizeof label, "h = %.1f m   H = %.2f m   L = %.1f m   R Sx = %.2f (1/k = %.2f)", h, 2 * R,
                      w.wavelength, s.major, 1.0 / w.k);
        c.text(10, static_cast<int>(base_y) - row_height / 2 + 6, label);
        c.line(0, base_y, width, base_y, grey, 1);
        // The section: x = x0 + forward(φ = k x0), z = up(φ); crest at the middle.
        const double span = width / metres_to_px;
        double px = 0, py = 0, gx = 0, gy = 0;
        for (int i = 0; i <= 3000; ++i) {
            const double x0 = -0.5 * span + span * i / 3000.0;
            const double phi = w.k * x0 + s.trough_phase + std::numbers::pi;
            const wave::ProfileOffset d = wave::gonzato_offset(s, phi);
            const double x = (x0 + 0.5 * span + d.forward) * metres_to_px, y = base_y - d.up * metres_to_px;
            const double gxn = (x0 + 0.5 * span + R * std::sin(phi)) * metres_to_px, gyn = base_y + R * std::cos(phi) * metres_to_px;
            if (i > 0) {
                c.line(gx, gy, gxn, gyn, red, 1, true);
                c.line(px, py, x, y, blue, 2);
            }
            px = x, py = y, gx = gxn, gy = gyn;
        }
    }
    if (!stbi_write_png(out.c_str(), c.w, c.h, 3, c.rgb.data(), c.w * 3)) {
        std::fprintf(stderr, "error: cannot write %s\n", out.c_str());
        return 1;
    }
    std::printf("wrote %s\n", out.c_str());
    return 0;
}
