// Prints L/L0, C, C_g and K_s against d/L0 — the classic table of linear wave theory
// — and the surf zone of a planar beach, using only libwave's public API.
#include <libwave/bathymetry.h>
#include <libwave/physics.h>
#include <libwave/version.h>

#include <cstdio>
#include <numbers>
#include <vector>

int main() {
    const double period = 8.0, omega = 2.0 * std::numbers::pi / period;
    const double L0 = wave::kGravity * period * period / (2.0 * std::numbers::pi);
    std::printf("libwave %s — linear waves, T = %.1f s, L0 = %.2f m\n", wave::version(), period, L0);
    std::printf("%8s %8s %9s %9s %7s\n", "d/L0", "L/L0", "C (m/s)", "Cg (m/s)", "Ks");
    for (double r : {0.01, 0.02, 0.05, 0.1, 0.2, 0.5}) {
        const wave::LinearWave w = wave::linear_wave(omega, r * L0);
        std::printf("%8.3f %8.4f %9.3f %9.3f %7.4f\n", r, w.wavelength / L0, w.celerity,
                    w.group_velocity, w.shoaling);
    }
    // Shoal a 1 m swell up the default planar beach, along the line x = 100 m.
    const wave::Seafloor beach = wave::make_planar_beach();
    std::vector<double> depth;
    for (double y = 0.0; y <= 200.0; y += 0.5) depth.push_back(wave::depth_at(beach.grid, 100.0, y));
    const wave::ShoalingProfile p = wave::shoal_profile(omega, 1.0, depth, 0.5);
    std::printf("planar beach: breaks at depth %.2f m, height %.2f m, xi0 = %.2f (%s)\n",
                p.break_depth, p.break_height, p.iribarren, wave::to_string(p.type));
    return 0;
}
