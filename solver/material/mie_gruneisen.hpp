// Mie–Grüneisen equation of state with a linear U_s–u_p Hugoniot (METHOD.md §5):
//   μ > 0: p = ρ0 c0² μ [1 + (1 − γ0/2) μ − (a/2) μ²] / [1 − (s − 1) μ]² + (γ0 + a μ) E
//   μ ≤ 0: p = ρ0 c0² μ + (γ0 + a μ) E
// μ = ρ/ρ0 − 1, E internal energy per initial volume (J/m³), p compression positive (Pa).
#pragma once

namespace sphfem {

struct MieGruneisen {
  double c0 = 0;     // bulk sound speed, m/s
  double s = 0;      // slope of U_s(u_p)
  double gamma0 = 0; // Grüneisen coefficient
  double a = 0;      // first-order volume correction to γ0

  double pressure(double rho0, double mu, double E) const;
  // ∂p/∂μ at constant E, Pa.
  double pressure_slope(double rho0, double mu, double E) const;
  // Square of the bulk sound speed dp/dρ along an isentrope, m²/s²: ∂p/∂ρ|_E + (p/ρ²) ∂p/∂e|_ρ
  // with e = E/ρ0 the specific internal energy. Not clamped (it can be negative deep in tension).
  double bulk_sound_speed_squared(double rho0, double mu, double E) const;
};

} // namespace sphfem
