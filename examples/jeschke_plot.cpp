// Draws Jeschke's wave shape (§4, table 1 as libwave reads it) through its life cycle,
// as docs/jeschke-profiles.png: one column per phase (round, breaking, collapsing —
// figure 3's a, b, c), one row per time t of the phase; the wave runs to the right,
// the back half in blue, the front half in red, the lip (s = 0.5) marked. A last row
// shows the breaking phase with the spilling curl (0.3) for comparison.
//
//   jeschke_plot [out.png]
#include <libwave/motion.h>

#include "plot_canvas.h"

#include <cstdio>
#include <string>

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
    return plot::write_png(c, out) ? 0 : 1;
}
