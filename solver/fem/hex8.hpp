// Hex8: the 8-node trilinear hexahedron as pure functions on its node arrays (METHOD.md §3).
// Uniform-gradient (Flanagan–Belytschko 1981) one-point operators: b_I = ∂V/∂x_I in closed
// form from the exact volume of the trilinear map; hourglass shape vectors γ_αI;
// characteristic length V / largest face area.
// Node order: gmsh hexahedron (solver/core/types.hpp). Units: SI.
// Verified by tests/fem/hex8_test.cpp (b_I against Gauss quadrature of ∫ ∂N_I/∂x dV, patch
// test, hourglass orthogonality).
#pragma once

#include "solver/core/types.hpp"

#include <array>

namespace sphfem {

using HexPoints = std::array<Vec3, 8>;

struct Hex8Gradient {
  double volume = 0;     // m³
  std::array<Vec3, 8> b; // b_I = ∂V/∂x_I (m²); the uniform gradient is B_I = b_I / V
};

Hex8Gradient hex8_gradient(const HexPoints& x);

// Velocity gradient L_ij = ∂v_i/∂x_j averaged over the element: (1/V) Σ_I v_I ⊗ b_I.
Mat3 hex8_velocity_gradient(const Hex8Gradient& g, const HexPoints& v);

// Hourglass base vectors Γ_α (α = 1..4) in node order (METHOD.md §3).
inline constexpr std::array<std::array<double, 8>, 4> hourglass_base{{
    {1, 1, -1, -1, -1, -1, 1, 1},
    {1, -1, -1, 1, -1, 1, 1, -1},
    {1, -1, 1, -1, 1, -1, 1, -1},
    {-1, 1, -1, 1, 1, -1, 1, -1},
}};

// Flanagan–Belytschko shape vectors γ_αI = Γ_αI − (1/V)(Σ_J x_J Γ_αJ)·b_I: orthogonal to
// every linear field, so hourglass forces vanish for a patch-test motion on a distorted mesh.
std::array<std::array<double, 8>, 4> hex8_hourglass_shape(const HexPoints& x,
                                                          const Hex8Gradient& g);

// L_e = V / (largest face area), the length in the critical step L_e / c.
double hex8_characteristic_length(const HexPoints& x, double volume);

} // namespace sphfem
