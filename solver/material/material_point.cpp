#include "solver/material/material_point.hpp"

#include "solver/material/material.hpp"

#include <algorithm>
#include <cmath>

namespace sphfem {

namespace {

// Flow stress (1 − D) σ_Y and its slope d/dΔp along the return, at plastic increment Δp.
struct Yield {
  double stress;
  double slope;
};

Yield damaged_flow_stress(const JohnsonCook& jc, const MaterialPoint& point, double dp, double dt) {
  const double intact = 1.0 - point.damage;
  const double r = point.damaged_strain + intact * dp;
  const double ratio = intact * dp / (dt * jc.reference_strain_rate);
  const double hardening = jc.A + jc.B * std::pow(r, jc.n);
  const double hardening_slope = r > 0 ? jc.B * jc.n * std::pow(r, jc.n - 1.0) * intact : 0.0;
  const double rate = rate_term(jc.rate_form, jc.C, ratio);
  const double rate_slope =
      rate_term_slope(jc.rate_form, jc.C, ratio) * intact / (dt * jc.reference_strain_rate);
  const double scale = intact * jc.thermal_term(point.temperature);
  return {scale * hardening * rate, scale * (hardening_slope * rate + hardening * rate_slope)};
}

// The Δp that puts σ_trial − 3GΔp on the yield surface; the yield stress there is returned
// through `flow`. g(Δp) decreases monotonically, g(0) > 0 and g(upper) ≤ 0.
double return_increment(const JohnsonCook& jc, const MaterialPoint& point, double shear,
                        double trial, double initial_yield, double dt, double& flow) {
  constexpr double tolerance = 1e-10;
  constexpr int max_iterations = 60;
  double lo = 0, hi = (trial - initial_yield) / (3.0 * shear);
  double dp = hi;
  for (int k = 0; k < max_iterations; ++k) {
    const Yield y = damaged_flow_stress(jc, point, dp, dt);
    const double g = trial - 3.0 * shear * dp - y.stress;
    flow = y.stress;
    if (std::abs(g) <= tolerance * trial)
      break;
    (g > 0 ? lo : hi) = dp;
    const double newton = dp + g / (3.0 * shear + y.slope);
    dp = (newton > lo && newton < hi && std::isfinite(newton)) ? newton : 0.5 * (lo + hi);
  }
  return dp;
}

} // namespace

MaterialPoint MaterialPoint::initial(const Material& m) {
  MaterialPoint point;
  point.temperature = m.initial_temperature();
  return point;
}

double equivalent_stress(const Mat3& S) {
  return std::sqrt(1.5 * S.squaredNorm());
}

double update_point(const Material& m, const Mat3& D, const Mat3& W, double dt, double rho,
                    double& pressure, Mat3& S, MaterialPoint& point) {
  if (point.failed) {
    S.setZero();
    pressure = std::max(pressure, 0.0);
    return 0;
  }
  elastic_deviator_update(m.elastic, D, W, dt, S);
  if (!m.strength || !(dt > 0))
    return 0;
  const JohnsonCook& jc = *m.strength;
  const double trial = equivalent_stress(S);
  const double initial_yield = damaged_flow_stress(jc, point, 0.0, dt).stress;
  if (trial <= initial_yield)
    return 0;
  double flow = initial_yield;
  const double dp = return_increment(jc, point, m.elastic.shear, trial, initial_yield, dt, flow);
  S *= (trial - 3.0 * m.elastic.shear * dp) / trial;
  const double p_old = point.plastic_strain;
  point.plastic_strain += dp;
  point.damaged_strain += (1.0 - point.damage) * dp;
  const double T_start = point.temperature;
  if (m.heating)
    point.temperature += m.heating->temperature_rise(flow * dp, rho);
  if (m.damage) {
    const DuctileDamage& d = *m.damage;
    const double active = point.plastic_strain - std::max(p_old, d.threshold_strain);
    if (active > 0) {
      // A melted point (T* = 1) has no flow stress left: count it as at zero triaxiality.
      const double triaxiality = flow > 0 ? -pressure / flow : 0.0;
      const double p_f = d.fracture_strain(triaxiality, dp / (dt * jc.reference_strain_rate),
                                           jc.homologous_temperature(T_start));
      const double span = p_f - d.threshold_strain;
      point.damage =
          span > 0 ? point.damage + d.critical_damage * active / span : d.critical_damage;
      if (point.damage >= d.critical_damage) {
        point.damage = d.critical_damage;
        point.failed = true;
        S.setZero();
        pressure = std::max(pressure, 0.0);
      }
    }
  }
  return dp;
}

} // namespace sphfem
