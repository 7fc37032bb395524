// The element phase of an explicit step for all hexahedra (METHOD.md §3, §5, §7): strain
// rate and spin from v^{n+½} on the mid-step geometry, constitutive update to σ^{n+1} with
// bulk viscosity (material_point.hpp for Johnson–Cook materials), internal and Flanagan–Belytschko
// hourglass forces on x^{n+1}, and each element's stable step. One OpenMP loop over elements; each
// writes only its own slots. Verified by tests/fem/hex8_test.cpp and tests/fem/wave_test.cpp.
#pragma once

#include "solver/core/types.hpp"
#include "solver/io/case.hpp"
#include "solver/material/material.hpp"
#include "solver/state/hex_elements.hpp"

#include <vector>

namespace sphfem {

// x^{n+1} and v^{n+½} of the nodes; the mid-step geometry is x^{n+1} − ½Δt v^{n+½}.
struct HexStepInput {
  const std::vector<Vec3>& x_new;
  const std::vector<Vec3>& v_half;
  double dt; // 0: forces and stable step only, no stress update
  // The elements to advance, ascending (a distributed run's share, parallel/subdomain.hpp);
  // null: all.
  const std::vector<Index>* only = nullptr;
};

// Advances the elements and returns the smallest stable element step: the least of the
// wave's L_e/(Q + √(Q² + c²)) and the hourglass resistance's own limit on nodes of mass
// m = m_e/8 (a lower bound on a node's mass), 2m/(c_hg λ) for the viscous form (explicit
// damping) and 2√(m/(k_hg λ)) for the stiffness form (a spring), λ the largest eigenvalue of
// Σ_α γ_α γ_αᵀ. On a cube (λ = 8) these are 1.25 and 1.58 L_e/c at the default coefficient
// 0.1, so they bind only distorted elements, whose hourglass vectors grow and couple.
// A failed element of an eroding material is removed (HexElements::eroded_e).
double update_hex_elements(const HexStepInput& in, const std::vector<Material>& materials,
                           const FemSpec& fem, HexElements& e);

} // namespace sphfem
