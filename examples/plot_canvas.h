// A small RGB canvas for the example plots: lines, dots and stb_easy_font text,
// written as PNG by stb_image_write (libstb-dev). Include in one file per program.
#pragma once

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#include <stb/stb_easy_font.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace plot {

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

// Writes the canvas; false (and a message on stderr) when the file cannot be written.
inline bool write_png(const Canvas& c, const std::string& path) {
    if (!stbi_write_png(path.c_str(), c.w, c.h, 3, c.rgb.data(), c.w * 3)) {
        std::fprintf(stderr, "error: cannot write %s\n", path.c_str());
        return false;
    }
    std::printf("wrote %s\n", path.c_str());
    return true;
}

}  // namespace plot
