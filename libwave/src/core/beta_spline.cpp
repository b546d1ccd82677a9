#include "libwave/beta_spline.h"

namespace wave {

void beta_spline_basis(double u, double b1, double b2, double w[4]) noexcept {
    // Barsky & Beatty (1983), uniformly shaped cubic Beta-spline, δ normalises.
    const double u2 = u * u, u3 = u2 * u, v = 1.0 - u;
    const double b1_2 = b1 * b1, b1_3 = b1_2 * b1;
    const double delta = 2 * b1_3 + 4 * b1_2 + 4 * b1 + b2 + 2;
    w[0] = 2 * b1_3 * v * v * v / delta;
    w[1] = (2 * b1_3 * u * (u2 - 3 * u + 3) + 2 * b1_2 * (u3 - 3 * u2 + 2) + 2 * b1 * (u3 - 3 * u + 2) +
            b2 * (2 * u3 - 3 * u2 + 1)) / delta;
    w[2] = (2 * b1_2 * u2 * (-u + 3) + 2 * b1 * u * (-u2 + 3) + b2 * u2 * (-2 * u + 3) + 2 * (-u3 + 1)) / delta;
    w[3] = 2 * u3 / delta;
}

}  // namespace wave
