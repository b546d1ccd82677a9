// Draws Gonzato's vertical-section profile (eq. 7) of one swell at several depths on a
// 1:10 beach, as docs/gonzato-profile.png: each row is one wavelength of the surface at
// one depth (rest level in grey, the section in blue, Gerstner's deep-water trochoid of
// the same R and k dashed), so the steepening, the running crest and the plunging lip
// can be compared with the paper's figures 6 and 8. That is eq. 7 as drawn
// (motion.min_packing 0); in green, the default section, whose offset along the ray is
// scaled so that it packs no rest spacing below 0.6. Black dots: the points of a water
// mesh 16 vertices to the local wavelength (its default) on eq. 7's section; each label
// ends with how close each section packs them: the shortest surface distance between
// neighbours as a share of their rest spacing, and over what share of a wavelength
// eq. 7's is below a half (printed to stdout too).
//
//   profile_plot [out.png]
#include <libwave/motion.h>
#include <libwave/physics.h>

#include "plot_canvas.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr int width = 1400, row_height = 150;
using plot::Canvas;

}  // namespace

int main(int argc, char** argv) {
    const std::string out = argc > 1 ? argv[1] : "gonzato-profile.png";
    const double period = 5.0, deep_amplitude = 0.3, beach_slope = 0.1;
    const double omega = 2.0 * std::numbers::pi / period;
    const std::vector<double> depths = {12.0, 6.0, 3.0, 2.0, 1.5, 1.1, 0.8};
    const double metres_to_px = 52.0;  // same scale on both axes
    Canvas c(width, row_height * static_cast<int>(depths.size()) + 40);
    c.text(10, 8, "Gonzato eq. 7, T = 5 s, A_inf = 0.3 m, beach 1:10; blue: eq. 7, green: default (min_packing 0.6), dashed: Gerstner");
    const unsigned char grey[3] = {170, 170, 170}, blue[3] = {20, 70, 200}, red[3] = {200, 40, 40}, green[3] = {30, 150, 60};
    wave::GonzatoProfileOptions options;
    options.min_packing = 0.0;  // eq. 7 as drawn
    const wave::GonzatoProfileOptions defaults;
    for (std::size_t row = 0; row < depths.size(); ++row) {
        const double h = depths[row];
        const wave::LinearWave w = wave::linear_wave(omega, h);
        const double R = std::min(deep_amplitude * w.shoaling, 0.5 * wave::kBreakerIndex * h);
        const wave::ProfileShape s = wave::gonzato_shape(R, w.k, h, beach_slope, options);
        const wave::ProfileShape bounded = wave::gonzato_shape(R, w.k, h, beach_slope, defaults);
        const double base_y = 40.0 + row_height * (static_cast<double>(row) + 0.55);
        // The section (x, z) at rest position x0, the crest at x0 = 0.
        const auto section_of = [&](const wave::ProfileShape& shape, double x0) {
            const wave::ProfileOffset d = wave::gonzato_offset(shape, w.k * x0 + shape.trough_phase + std::numbers::pi);
            return std::pair{x0 + d.forward, d.up};
        };
        const auto section = [&](double x0) { return section_of(s, x0); };
        // The surface per unit of rest length, |d(x, z)/dx0|, over one wavelength: its
        // smallest value, and the share of the wavelength where it is below a half.
        const auto packing = [&](const wave::ProfileShape& shape) {
            constexpr int samples = 20000;
            double packed = 1e9;
            int below_half = 0;
            for (int i = 0; i < samples; ++i) {
                const double x0 = w.wavelength * i / samples, dx0 = w.wavelength / samples;
                const auto [xa, za] = section_of(shape, x0);
                const auto [xb, zb] = section_of(shape, x0 + dx0);
                const double stretch = std::hypot(xb - xa, zb - za) / dx0;
                packed = std::min(packed, stretch);
                below_half += stretch < 0.5 ? 1 : 0;
            }
            return std::pair{packed, 100.0 * below_half / samples};
        };
        const auto [packed, share] = packing(s);
        const double packed_bounded = packing(bounded).first;
        char label[220];
        std::snprintf(label, sizeof label, "h = %.1f m  H = %.2f m  L = %.1f m  R Sx = %.2f (1/k = %.2f)  eq. 7 packs to %.2f (< 0.5 over %.0f %%), default %.2f",
                      h, 2 * R, w.wavelength, s.major, 1.0 / w.k, packed, share, packed_bounded);
        std::printf("h = %.1f m: eq. 7 packs the rest spacing to %.3f at least, below 0.5 over %.1f %% of a wavelength; "
                    "the default (min_packing %.1f) to %.3f\n",
                    h, packed, share, defaults.min_packing, packed_bounded);
        c.text(10, static_cast<int>(base_y) - row_height / 2 + 6, label);
        c.line(0, base_y, width, base_y, grey, 1);
        // The section: x = x0 + forward(φ = k x0), z = up(φ); crest at the middle.
        const double span = width / metres_to_px;
        double px = 0, py = 0, gx = 0, gy = 0, bx = 0, by = 0;
        for (int i = 0; i <= 3000; ++i) {
            const double x0 = -0.5 * span + span * i / 3000.0;
            const double phi = w.k * x0 + s.trough_phase + std::numbers::pi;
            const wave::ProfileOffset d = wave::gonzato_offset(s, phi);
            const double x = (x0 + 0.5 * span + d.forward) * metres_to_px, y = base_y - d.up * metres_to_px;
            const double gxn = (x0 + 0.5 * span + R * std::sin(phi)) * metres_to_px, gyn = base_y + R * std::cos(phi) * metres_to_px;
            const wave::ProfileOffset db = wave::gonzato_offset(bounded, phi);
            const double bxn = (x0 + 0.5 * span + db.forward) * metres_to_px, byn = base_y - db.up * metres_to_px;
            if (i > 0) {
                c.line(gx, gy, gxn, gyn, red, 1, true);
                c.line(bx, by, bxn, byn, green, 2);
                c.line(px, py, x, y, blue, 2);
            }
            px = x, py = y, gx = gxn, gy = gyn, bx = bxn, by = byn;
        }
        const unsigned char black[3] = {0, 0, 0};
        const double spacing = w.wavelength / 16.0;
        for (double x0 = -std::floor(0.5 * span / spacing) * spacing; x0 < 0.5 * span; x0 += spacing) {
            const auto [x, z] = section(x0);
            const int cx = static_cast<int>(std::lround((x + 0.5 * span) * metres_to_px));
            const int cy = static_cast<int>(std::lround(base_y - z * metres_to_px));
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx)
                    if (dx * dx + dy * dy <= 5) c.dot(cx + dx, cy + dy, black);
        }
    }
    return plot::write_png(c, out) ? 0 : 1;
}
