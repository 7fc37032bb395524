#include "solver/material/mie_gruneisen.hpp"

namespace sphfem {

double MieGruneisen::pressure(double rho0, double mu, double E) const {
  const double thermal = (gamma0 + a * mu) * E;
  if (mu <= 0)
    return rho0 * c0 * c0 * mu + thermal;
  const double denominator = 1.0 - (s - 1.0) * mu;
  return rho0 * c0 * c0 * mu * (1.0 + (1.0 - 0.5 * gamma0) * mu - 0.5 * a * mu * mu) /
             (denominator * denominator) +
         thermal;
}

double MieGruneisen::pressure_slope(double rho0, double mu, double E) const {
  if (mu <= 0)
    return rho0 * c0 * c0 + a * E;
  const double b = 1.0 - 0.5 * gamma0;
  const double numerator = mu * (1.0 + b * mu - 0.5 * a * mu * mu);
  const double numerator_slope = 1.0 + 2.0 * b * mu - 1.5 * a * mu * mu;
  const double denominator = 1.0 - (s - 1.0) * mu;
  return rho0 * c0 * c0 *
             (numerator_slope / (denominator * denominator) +
              2.0 * (s - 1.0) * numerator / (denominator * denominator * denominator)) +
         a * E;
}

double MieGruneisen::bulk_sound_speed_squared(double rho0, double mu, double E) const {
  const double rho = rho0 * (1.0 + mu);
  return pressure_slope(rho0, mu, E) / rho0 +
         pressure(rho0, mu, E) * rho0 * (gamma0 + a * mu) / (rho * rho);
}

} // namespace sphfem
