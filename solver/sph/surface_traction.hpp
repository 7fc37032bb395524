// How a pressure on a flat face of an SPH body is shared among its particles, consistently
// with the SPH momentum equation (METHOD.md §2).
//
// A particle within 2h of a free surface has a cut kernel support, so under a uniform stress σ
// the symmetric momentum sum Σ_j m_i m_j (σ/ρ_i² + σ/ρ_j²) ∇_i W_ij does not vanish there: it
// is the discrete form of the surface traction σ n, spread over the layers within 2h of the
// face. The distribution that holds the surface state σ = −p n ⊗ n in equilibrium is therefore
// the force p (n · g_i) n on each particle i within 4h of the face, with
//   g_i = Σ_j m_i m_j (C_iᵀ/ρ_i² + C_jᵀ/ρ_j²) ∇_i W_ij   (an area, m²),
// C the gradient correction (identity when off).
// Putting all of p A on the outermost layer instead (tributary areas) balances only at
// σ ≈ 1.7 p there (node lattice), which crushes and heats the loaded end.
// The weights are taken in the initial configuration and scaled so that they sum to the face's
// area (the sum of the tributary areas), so the load's resultant is exactly p A.
// Verified by tests/sph/surface_traction_test.cpp and the bar_pressed_sph case.
#pragma once

#include "solver/state/model.hpp"

#include <vector>

namespace sphfem {

struct TractionWeights {
  std::vector<Index> particles; // indices into the model's particle arrays
  std::vector<double> area;     // share of the face area each carries, m² (sums to the face's)
  double scale = 1;             // face area / Σ w_i: 1 + O(h/L) for a body of length L
};

// The weights for the face of `body` (a body id) given by `face`'s normal and particle layer,
// with the gradient correction C of the momentum equation when it is on.
TractionWeights surface_traction_weights(const Model& model, int body, const ParticleFace& face,
                                         bool gradient_correction);

} // namespace sphfem
