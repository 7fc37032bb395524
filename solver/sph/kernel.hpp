// Cubic B-spline kernel in 3-D with support 2h (METHOD.md §2):
//   W(r, h) = 1/(π h³) · {1 − 1.5q² + 0.75q³ (q < 1); 0.25(2 − q)³ (1 ≤ q < 2); 0},  q = r/h,
// and its radial derivative ∂W/∂r, so ∇_i W_ij = (x_ij / r) ∂W/∂r; and the gradient correction
// matrix built from these gradients.
// Verified by tests/sph/kernel_test.cpp (normalisation, gradient consistency).
#pragma once

#include "solver/core/types.hpp"

#include <numbers>

namespace sphfem {

inline double kernel_W(double r, double h) {
  const double q = r / h;
  const double sigma = 1.0 / (std::numbers::pi * h * h * h);
  if (q < 1.0)
    return sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return sigma * 0.25 * t * t * t;
  }
  return 0.0;
}

// ∂W/∂r (1/m⁴), ≤ 0.
inline double kernel_dW(double r, double h) {
  const double q = r / h;
  const double sigma = 1.0 / (std::numbers::pi * h * h * h * h);
  if (q < 1.0)
    return sigma * (-3.0 * q + 2.25 * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return -sigma * 0.75 * t * t;
  }
  return 0.0;
}

// The gradient correction C = M⁻¹ (Randles & Libersky; Bonet & Lok) of a particle's moment
// matrix M = −(1/ρ_i) Σ_j m_j x_ij ⊗ ∇W, or the identity where the correction is off or M is
// too degenerate to invert (a nearly isolated particle).
inline Mat3 gradient_correction(const Mat3& M, bool on) {
  return on && M.determinant() > 1e-3 ? Mat3(M.inverse()) : Mat3(Mat3::Identity());
}

} // namespace sphfem
