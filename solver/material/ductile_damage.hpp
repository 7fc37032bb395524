// Ductile damage of the modified Johnson–Cook model (METHOD.md §5, Børvik et al. 2001):
//   Ḋ = 0 for p < p_d,  Ḋ = D_C ṗ / (p_f − p_d) for p ≥ p_d,
//   p_f = [D1 + D2 exp(D3 σ*)] [rate term with D4 of ṗ/ṗ0] [1 + D5 T*],  σ* = σ_m/σ_eq.
// The point fails when D reaches D_C.
// Regularisation (an option beyond METHOD.md): strain localises into a band as wide as the
// discretisation resolves — 2h for an SPH particle, one element for a hexahedron — so the work
// to cut a unit of band area, ∝ p_f × width, grows with the particle spacing. With a length L,
// p_f is multiplied by (L / width)^β: with β = 1 (the default) the work is that of a band L wide
// at every resolution; a band that narrows more slowly than the discretisation's width (the
// punch test of docs/calibration.md measures how fast) wants β < 1 (p_d is not scaled).
// Without L (0), and for a point without a size, p_f is as calibrated.
#pragma once

#include "solver/material/rate_form.hpp"

#include <cmath>

namespace sphfem {

struct DuctileDamage {
  double D1 = 0, D2 = 0, D3 = 0, D4 = 0, D5 = 0;
  RateForm rate_form = RateForm::Power; // form of the D4 term
  double critical_damage = 1.0;         // D_C
  double threshold_strain = 0.0;        // p_d
  double regularisation_length = 0.0;   // L, m; 0: p_f is not scaled
  double regularisation_exponent = 1.0; // β

  // Fracture strain p_f at triaxiality σ*, dimensionless plastic strain rate ṗ* and
  // homologous temperature T*.
  double fracture_strain(double triaxiality, double rate_ratio, double homologous_T) const {
    return (D1 + D2 * std::exp(D3 * triaxiality)) * rate_term(rate_form, D4, rate_ratio) *
           (1.0 + D5 * homologous_T);
  }

  // The factor (L / width)^β on p_f for a point whose band is `width` (m) wide; 1 without L
  // or without a width.
  double size_factor(double width) const {
    if (!(regularisation_length > 0 && width > 0))
      return 1.0;
    const double ratio = regularisation_length / width;
    return regularisation_exponent == 1.0 ? ratio : std::pow(ratio, regularisation_exponent);
  }
};

} // namespace sphfem
