// The exact wave over libwave's planar beach (tests only): straight contours along x,
// the depth falling along y, 8 m at the up-wave corner (0, 0). A swell whose direction
// there has x-component sin_theta keeps k_x = k(8 m) sin θ everywhere (Snell), with
// k_y = √(k² − k_x²) and phase k_x x + ∫ k_y dy from the corner, integrated by the
// midpoint rule on 1 cm steps. Beyond the domain's sides the seafloor is the side's own
// continued outwards (the apron), so the same wave holds there.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/physics.h"
#include "libwave/trace.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace wave::test {

struct BeachWave {
    double omega, sin_theta, kx;
    ElevationGrid grid;
    std::vector<double> phase_at_y;  // ∫ k_y dy at y = 0, 0.01, 0.02, … m

    BeachWave(const Seafloor& beach, double omega_, double sin_theta_)
        : omega(omega_), sin_theta(sin_theta_), kx(linear_wave(omega_, 8.0).k * sin_theta_), grid(beach.grid) {
        phase_at_y.push_back(0.0);
        for (double y = 0.005; y < 200.0; y += 0.01) {
            const double h = depth(y);
            const double k = h > 0.0 ? linear_wave(omega, h).k : kx;
            phase_at_y.push_back(phase_at_y.back() + 0.01 * std::sqrt(std::max(0.0, k * k - kx * kx)));
        }
    }
    double depth(double y) const { return depth_at(grid, 100.0, y); }
    double phase(double x, double y) const {
        const double u = y / 0.01;
        const auto i = std::min(static_cast<std::size_t>(std::max(u, 0.0)), phase_at_y.size() - 2);
        return kx * x + phase_at_y[i] + (u - static_cast<double>(i)) * (phase_at_y[i + 1] - phase_at_y[i]);
    }
    // Where the wave breaks (2 A∞ K_s K_r >= γ h, K_r = √(cos θ(8 m) / cos θ)): the first
    // 1 cm step from the deep edge.
    double break_y(double amplitude) const {
        const double cos0 = std::sqrt(1.0 - sin_theta * sin_theta);
        for (double y = 0.005; y < 200.0; y += 0.01) {
            const LinearWave w = linear_wave(omega, depth(y));
            const double ky = std::sqrt(std::max(0.0, w.k * w.k - kx * kx));
            if (2.0 * amplitude * w.shoaling * std::sqrt(cos0 / (ky / w.k)) >= kBreakerIndex * depth(y)) return y;
        }
        return 200.0;
    }
    // The phase a ray reaching (0, y) had at y_b, over the apron: phase(0, y) − ∫ k² / k_y dy.
    double phase_back_to(double y_b, double y) const {
        double sum = 0.0;
        for (double u = y_b + 0.005; u < y; u += 0.01) {
            const double k = linear_wave(omega, depth(u)).k;
            sum += 0.01 * k * k / std::sqrt(k * k - kx * kx);
        }
        return phase(0.0, y) - sum;
    }
};

// The breaking beach's trace (examples/breaking-beach.json): the planar beach, an 8 s
// swell from (0.34, 0.94), rays 2 m apart, steps of 0.5 m.
inline FrontSet breaking_beach_fronts() {
    FrontOptions o;
    o.ray_spacing = 2.0;
    o.step = 0.5;
    o.split_distance = 3.0;
    return trace_fronts(make_planar_beach(), {.period = 8.0, .amplitude = 0.4, .direction_x = 0.34, .direction_y = 0.94}, o);
}

}  // namespace wave::test
