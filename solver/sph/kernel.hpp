// Cubic B-spline kernel in 3-D with support 2h (METHOD.md §2):
//   W(r, h) = 1/(π h³) · {1 − 1.5q² + 0.75q³ (q < 1); 0.25(2 − q)³ (1 ≤ q < 2); 0},  q = r/h,
// and its radial derivative ∂W/∂r, so ∇_i W_ij = (x_ij / r) ∂W/∂r; and the gradient correction
// matrix built from these gradients.
// Verified by tests/sph/kernel_test.cpp (normalisation, gradient consistency).
#pragma once

#include "solver/core/types.hpp"

#include <cmath>
#include <numbers>

namespace sphfem {

// The kernel's shape in q = r/h: w(q) = π h³ W and w'(q) = π h⁴ ∂W/∂r. A pair loop takes
// 1/h once and evaluates W = w(q)/(π h³), ∂W/∂r = w'(q)/(π h⁴) without further divisions.
inline double kernel_shape(double q) {
  if (q < 1.0)
    return 1.0 - 1.5 * q * q + 0.75 * q * q * q;
  if (q < 2.0) {
    const double t = 2.0 - q;
    return 0.25 * t * t * t;
  }
  return 0.0;
}

// w'(q) ≤ 0.
inline double kernel_shape_slope(double q) {
  if (q < 1.0)
    return -3.0 * q + 2.25 * q * q;
  if (q < 2.0) {
    const double t = 2.0 - q;
    return -0.75 * t * t;
  }
  return 0.0;
}

inline double kernel_W(double r, double h) {
  return kernel_shape(r / h) / (std::numbers::pi * h * h * h);
}

// ∂W/∂r (1/m⁴), ≤ 0.
inline double kernel_dW(double r, double h) {
  return kernel_shape_slope(r / h) / (std::numbers::pi * h * h * h * h);
}

// The kernel terms of one pair at squared distance r2, 0 < r2 < 4h² (the caller tests that
// first, without a square root): W, the factor ∂W/∂r / r that turns x_ij into ∇_i W, q and
// 1/h; one division for 1/h and one for 1/r.
struct PairKernel {
  double W;
  double grad_scale;
  double q;
  double inv_h;
};
inline PairKernel pair_kernel(double r2, double h) {
  const double r = std::sqrt(r2), inv_h = 1.0 / h, q = r * inv_h;
  const double norm = inv_h * inv_h * inv_h * std::numbers::inv_pi;
  return {norm * kernel_shape(q), norm * inv_h * kernel_shape_slope(q) / r, q, inv_h};
}

inline bool within_support(double r2, double h) {
  return r2 < 4.0 * h * h && r2 > 0.0;
}

// The gradient correction C = M⁻¹ (Randles & Libersky; Bonet & Lok) of a particle's moment
// matrix M = −(1/ρ_i) Σ_j m_j x_ij ⊗ ∇W, or the identity where the correction is off or M is
// too degenerate to invert (a nearly isolated particle).
inline Mat3 gradient_correction(const Mat3& M, bool on) {
  return on && M.determinant() > 1e-3 ? Mat3(M.inverse()) : Mat3(Mat3::Identity());
}

} // namespace sphfem
