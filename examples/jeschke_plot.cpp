// Draws Jeschke's wave shape (§4, table 1 as libwave reads it) through its life cycle,
// as docs/jeschke-profiles.png: one column per phase (round, breaking, collapsing —
// figure 3's a, b, c), one row per time t of the phase; the wave runs to the right,
// the back half in blue, the front half in red, the lip (s = 0.5) marked. A last row
// shows the breaking phase with the spilling curl (0.3) for comparison.
//
// The second image (docs/jeschke-outer.png) draws, at a real breaker's proportions
// (5H/W = 0.2: height and width to the same scale), the paper's curve in grey and the
// outer section the mesh takes (breakers.lip "outer") in blue, with the points of a mesh
// of 16 vertices a wavelength on it, through the breaking and collapsing phases.
//
//   jeschke_plot [profiles.png] [outer.png] [curl.png]
#include <libwave/motion.h>

#include "plot_canvas.h"

#include <cstdio>
#include <string>
#include <utility>
#include <vector>
#include <algorithm>

namespace {

// A section to scale in blue (x from `left`, z up from `base`, `px` pixels a wavelength),
// with every `step`-th label marked in red: 16 mesh points a wavelength.
void draw_section(plot::Canvas& c, const std::vector<wave::BreakerSectionPoint>& section, double ratio, double left, double base,
                  double px, std::size_t step) {
    const unsigned char blue[3] = {20, 70, 200}, red[3] = {210, 30, 30};
    const auto at = [&](std::size_t m) { return std::pair{left + section[m].x * px, base - ratio * section[m].z * px}; };
    for (std::size_t m = 1; m < section.size(); ++m) {
        const auto [x0, y0] = at(m - 1);
        const auto [x1, y1] = at(m);
        c.line(x0, y0, x1, y1, blue, 2);
    }
    for (std::size_t m = 0; m < section.size(); m += step) {
        const auto [x, y] = at(m);
        for (int d = -2; d <= 2; ++d) c.line(x - 2, y + d, x + 2, y + d, red, 1);
    }
}

int draw_outer(const std::string& out) {
    constexpr double ratio = 0.2, px = 1100.0;
    constexpr int row_h = 120, top = 40, left = 40;
    const double lives[] = {0.3, 0.6, 0.8, 1.0, 1.2, 1.5};
    plot::Canvas c(1200, top + 6 * row_h);
    c.text(10, 8, "5H/W = 0.2, to scale; grey: the paper's curve; blue: the outer section; red: 16 mesh points a wavelength");
    const unsigned char grey[3] = {170, 170, 170};
    std::vector<wave::BreakerSectionPoint> section;
    for (int row = 0; row < 6; ++row) {
        const double life = lives[row];
        const bool breaking = life < 1.0;
        const double t = breaking ? life : life - 1.0;
        const wave::BreakerPhase ph = breaking ? wave::BreakerPhase::breaking : wave::BreakerPhase::collapsing;
        const wave::BreakerConstants back = wave::jeschke_constants(ph, t, false), front = wave::jeschke_constants(ph, t, true);
        const double fade = std::min(1.0, 1.25 * back.k[7]), base = top + row * row_h + 0.8 * row_h;
        char label[64];
        std::snprintf(label, sizeof label, "%s t = %.1f", breaking ? "breaking" : "collapsing", t);
        c.text(left, top + row * row_h + 4, label);
        double lx = 0, ly = 0;
        for (int i = 0; i <= 4000; ++i) {
            const double s = i / 4000.0;
            const wave::BreakerShapePoint p = wave::jeschke_shape(s, back, front, 1.0);
            const double x = left + (s + fade * (1.0 - p.y - s)) * px, y = base - ratio * p.z * px;
            if (i > 0) c.line(lx, ly, x, y, grey, 1);
            lx = x, ly = y;
        }
        wave::outer_section(life, 1.0, ratio, {}, 512, section);
        draw_section(c, section, ratio, left, base, px, 32);
    }
    return plot::write_png(c, out) ? 0 : 1;
}

// The curl section (breakers.lip "curl") of a plunging crest at 5H/W = 0.2, to scale,
// through its life: the back at the wavelength's scale, the front at the breaker's own.
int draw_curl(const std::string& out) {
    constexpr double ratio = 0.2, px = 1100.0;
    constexpr int row_h = 110, top = 40, left = 40;
    const double lives[] = {0.15, 0.3, 0.45, 0.6, 0.75, 0.9, 1.1, 1.4};
    plot::Canvas c(1200, top + 8 * row_h);
    c.text(10, 8, "5H/W = 0.2, to scale; blue: the curl section of a plunging crest (curl 1); red: 16 mesh points a wavelength");
    std::vector<wave::BreakerSectionPoint> section;
    for (int row = 0; row < 8; ++row) {
        const double life = lives[row];
        const double base = top + row * row_h + 0.8 * row_h;
        char label[64];
        std::snprintf(label, sizeof label, "%s t = %.2f", life < 1.0 ? "breaking" : "collapsing", life < 1.0 ? life : life - 1.0);
        c.text(left, top + row * row_h + 4, label);
        wave::curl_section(life, 1.0, ratio, {}, 1024, section);
        draw_section(c, section, ratio, left, base, px, 64);
    }
    return plot::write_png(c, out) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string out = argc > 1 ? argv[1] : "jeschke-profiles.png";
    const double ts[] = {0.0, 0.25, 0.5, 0.75, 1.0};
    constexpr int panel_w = 460, panel_h = 150, top = 40;
    const wave::BreakerPhase phases[] = {wave::BreakerPhase::round, wave::BreakerPhase::breaking,
                                         wave::BreakerPhase::collapsing};
    const char* names[] = {"(a) round", "(b) breaking", "(c) collapsing"};
    plot::Canvas c(3 * panel_w, top + 6 * panel_h);
    c.text(10, 8, "Jeschke et al. 2003, table 1 (constants blended over each phase, breaking k5 = t^1.5); wave runs right; "
                  "blue back half, red front half");
    const unsigned char grey[3] = {170, 170, 170}, blue[3] = {20, 70, 200}, red[3] = {200, 40, 40}, black[3] = {0, 0, 0};
    const double px = 400.0;  // pixels per unit of the shape, both axes
    for (int row = 0; row < 6; ++row)
        for (int col = 0; col < 3; ++col) {
            const bool spilling = row == 5;
            if (spilling && col != 1) continue;
            const double t = spilling ? 1.0 : ts[row];
            const double curl = spilling ? 0.3 : 1.0;
            const wave::BreakerPhase ph = phases[col];
            const wave::BreakerConstants back = wave::jeschke_constants(ph, t, false);
            const wave::BreakerConstants front = wave::jeschke_constants(ph, t, true);
            const double x0 = col * panel_w + 30.0, base = top + row * panel_h + 0.75 * panel_h;
            char label[96];
            std::snprintf(label, sizeof label, "%s  t = %.2f%s", names[col], t, spilling ? "  spilling (curl 0.3)" : "");
            c.text(static_cast<int>(x0), top + row * panel_h + 4, label);
            c.line(x0 - 20, base, x0 + px + 20, base, grey, 1);
            double lx = 0, ly = 0;
            for (int i = 0; i <= 2000; ++i) {
                const double s = i / 2000.0;
                const wave::BreakerShapePoint p = wave::jeschke_shape(s, back, front, curl);
                // Travel is towards −y: draw 1 − y to the right.
                const double x = x0 + (1.0 - p.y) * px, y = base - p.z * px;
                if (i > 0) c.line(lx, ly, x, y, s < 0.5 ? blue : red, 2);
                if (i == 1000) c.line(x - 3, y - 3, x + 3, y + 3, black, 2);
                lx = x, ly = y;
            }
        }
    if (!plot::write_png(c, out)) return 1;
    if (argc > 2 && draw_outer(argv[2]) != 0) return 1;
    return argc > 3 ? draw_curl(argv[3]) : 0;
}
