// Adiabatic heating by plastic work (METHOD.md §5): ΔT = χ σ_eq Δp / (ρ C_p).
#pragma once

namespace sphfem {

struct AdiabaticHeating {
  double taylor_quinney = 0.9; // χ, the fraction of plastic work turned into heat
  double specific_heat = 0;    // C_p, J/(kg K)

  // Temperature rise (K) for the plastic work σ_eq Δp (J/m³) at density ρ (kg/m³).
  double temperature_rise(double plastic_work, double rho) const {
    return taylor_quinney * plastic_work / (rho * specific_heat);
  }
};

} // namespace sphfem
