/// \file
/// libwave — core: the uniform cubic Beta-spline basis (Barsky & Beatty 1983), shared
/// by isobath smoothing and the height-field surface (Ts'o & Barsky 1987 §3.2.2, §3.3).
#pragma once

namespace wave {

/// Weights of the control vertices i−2, i−1, i, i+1 of span i at u ∈ [0, 1], for bias
/// β1 > 0 and tension β2 >= 0. They sum to 1; β1 = 1, β2 = 0 is the uniform cubic
/// B-spline; growing β2 pulls the curve towards the control polygon.
void beta_spline_basis(double u, double beta1, double beta2, double weights[4]) noexcept;

}  // namespace wave
