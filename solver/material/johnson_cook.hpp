// Johnson–Cook flow stress of the undamaged material (METHOD.md §5, Børvik et al. 2001):
//   σ_Y(r, ṙ, T) = [A + B rⁿ] [rate term of ṙ/ṗ0] [1 − T*^m],  T* = (T − T0)/(Tm − T0).
// Damage coupling, the factor (1 − D), is applied by the stress update (material_point.hpp).
#pragma once

#include "solver/material/rate_form.hpp"

namespace sphfem {

struct JohnsonCook {
  double A = 0; // yield stress, Pa
  double B = 0; // hardening modulus, Pa
  double n = 1; // hardening exponent
  double C = 0; // strain-rate sensitivity
  RateForm rate_form = RateForm::Power;
  double reference_strain_rate = 1.0; // ṗ0, 1/s
  double m = 1;                       // thermal softening exponent
  double melting_temperature = 1800;  // Tm, K
  double reference_temperature = 293; // T0, K (also the initial temperature)

  // T* clamped to [0, 1].
  double homologous_temperature(double T) const {
    return std::clamp((T - reference_temperature) / (melting_temperature - reference_temperature),
                      0.0, 1.0);
  }
  // 1 − T*^m.
  double thermal_term(double T) const {
    const double t = homologous_temperature(T);
    return t > 0 ? 1.0 - std::pow(t, m) : 1.0;
  }
  // σ_Y (Pa) at damage-accumulated plastic strain r ≥ 0, its rate ṙ ≥ 0 (1/s), temperature T (K).
  double flow_stress(double r, double rate, double T) const {
    return (A + B * std::pow(r, n)) * rate_term(rate_form, C, rate / reference_strain_rate) *
           thermal_term(T);
  }
};

} // namespace sphfem
