// The element phase of an explicit step for all hexahedra (METHOD.md §3, §5, §7): strain
// rate and spin from v^{n+½} on the mid-step geometry, constitutive update to σ^{n+1} with
// bulk viscosity (material_point.hpp for Johnson–Cook materials), internal and Flanagan–Belytschko
// hourglass forces on x^{n+1}, and each element's stable step. One OpenMP loop over elements; each
// writes only its own slots. Verified by tests/fem/hex_update_test.cpp and tests/fem/wave_test.cpp.
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
};

// Advances the elements and returns the smallest stable element step, L_e/(Q + √(Q² + c²)).
// A failed element of an eroding material is removed (HexElements::eroded_e).
double update_hex_elements(const HexStepInput& in, const std::vector<Material>& materials,
                           const FemSpec& fem, HexElements& e);

} // namespace sphfem
