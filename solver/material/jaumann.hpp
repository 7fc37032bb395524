// Objective rotation of a stress tensor over one step with the Jaumann rate
// dS/dt = Ω S − S Ω (METHOD.md §2), integrated with the Hughes–Winget rotation
// Q = (I − ½ΔtΩ)⁻¹ (I + ½ΔtΩ), which is exactly orthogonal, so a rigid rotation rotates the
// stress without changing its invariants. Verified by tests/fem/hex8_test.cpp (rigid rotation).
#pragma once

#include "solver/core/types.hpp"

#include <Eigen/LU>

namespace sphfem {

// Ω: spin, skew(L) = ½(L − Lᵀ) (1/s).
inline Mat3 jaumann_rotate(const Mat3& S, const Mat3& spin, double dt) {
  const Mat3 half = 0.5 * dt * spin;
  const Mat3 Q = (Mat3::Identity() - half).inverse() * (Mat3::Identity() + half);
  return Q * S * Q.transpose();
}

} // namespace sphfem
