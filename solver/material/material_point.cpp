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

// What the flow stress of one return does not vary with Δp: damage and temperature stay at the
// step's start, so (1 − D)(1 − T*^m) is computed once, not once per Newton iteration.
struct ReturnPoint {
  double intact;         // 1 − D
  double damaged_strain; // r at the step's start
  double rate_per_dp;    // ṙ*/Δp = (1 − D)/(Δt ṗ0)
  double scale;          // (1 − D)(1 − T*^m)
};

ReturnPoint return_point(const JohnsonCook& jc, const MaterialPoint& point, double dt) {
  const double intact = 1.0 - point.damage;
  return {intact, point.damaged_strain, intact / (dt * jc.reference_strain_rate),
          intact * jc.thermal_term(point.temperature)};
}

// Two power evaluations: rⁿ gives its own slope n rⁿ/r, the rate term gives its own.
Yield damaged_flow_stress(const JohnsonCook& jc, const ReturnPoint& at, double dp) {
  const double r = at.damaged_strain + at.intact * dp;
  const double rn = std::pow(r, jc.n);
  const double hardening = jc.A + jc.B * rn;
  const double hardening_slope = r > 0 ? jc.B * jc.n * (rn / r) * at.intact : 0.0;
  const RateTerm rate = rate_term_and_slope(jc.rate_form, jc.C, at.rate_per_dp * dp);
  return {at.scale * hardening * rate.value,
          at.scale * (hardening_slope * rate.value + hardening * rate.slope * at.rate_per_dp)};
}

// The Δp that puts σ_trial − 3GΔp on the yield surface; the yield stress there is returned
// through `flow`. g(Δp) decreases monotonically, g(0) > 0 and g(upper) ≤ 0.
double return_increment(const JohnsonCook& jc, const ReturnPoint& at, double shear, double trial,
                        double initial_yield, double& flow) {
  constexpr double tolerance = 1e-10;
  constexpr int max_iterations = 60;
  double lo = 0, hi = (trial - initial_yield) / (3.0 * shear);
  double dp = hi;
  for (int k = 0; k < max_iterations; ++k) {
    const Yield y = damaged_flow_stress(jc, at, dp);
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

bool yielding(const Material& m, const Mat3& S, const MaterialPoint& point) {
  if (point.failed || !m.strength)
    return false;
  // At Δp = 0 the rate term is its static value whatever the step. A point returned onto the
  // surface without rate hardening lies on it to the return's tolerance, hence the margin.
  constexpr double margin = 1e-6;
  const ReturnPoint at = return_point(*m.strength, point, 1.0);
  return equivalent_stress(S) >= (1.0 - margin) * damaged_flow_stress(*m.strength, at, 0.0).stress;
}

double update_point(const Material& m, const Mat3& D, const Mat3& W, double dt, double rho,
                    double& pressure, Mat3& S, MaterialPoint& point, double band_width) {
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
  const ReturnPoint at = return_point(jc, point, dt);
  const double initial_yield = damaged_flow_stress(jc, at, 0.0).stress;
  if (trial <= initial_yield)
    return 0;
  double flow = initial_yield;
  const double dp = return_increment(jc, at, m.elastic.shear, trial, initial_yield, flow);
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
                                           jc.homologous_temperature(T_start)) *
                         d.size_factor(band_width);
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
