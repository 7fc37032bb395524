// Ductile damage of the modified Johnson–Cook model (METHOD.md §5, Børvik et al. 2001):
//   Ḋ = 0 for p < p_d,  Ḋ = D_C ṗ / (p_f − p_d) for p ≥ p_d,
//   p_f = [D1 + D2 exp(D3 σ*)] [rate term with D4 of ṗ/ṗ0] [1 + D5 T*],  σ* = σ_m/σ_eq.
// The point fails when D reaches D_C.
#pragma once

#include "solver/material/rate_form.hpp"

namespace sphfem {

struct DuctileDamage {
  double D1 = 0, D2 = 0, D3 = 0, D4 = 0, D5 = 0;
  RateForm rate_form = RateForm::Power; // form of the D4 term
  double critical_damage = 1.0;         // D_C
  double threshold_strain = 0.0;        // p_d

  // Fracture strain p_f at triaxiality σ*, dimensionless plastic strain rate ṗ* and
  // homologous temperature T*.
  double fracture_strain(double triaxiality, double rate_ratio, double homologous_T) const {
    return (D1 + D2 * std::exp(D3 * triaxiality)) * rate_term(rate_form, D4, rate_ratio) *
           (1.0 + D5 * homologous_T);
  }
};

} // namespace sphfem
