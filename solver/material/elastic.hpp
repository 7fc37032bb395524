// Linear hypo-elastic material (METHOD.md §5): pressure rate −K tr(D), deviator rate 2G D′
// on top of the Jaumann rotation. Stress convention: σ = S − p I, tension positive.
// Verified by tests/fem/elastic_test.cpp and the plane-wave test.
#pragma once

#include "solver/core/types.hpp"

namespace sphfem {

struct MaterialSpec;

struct ElasticConstants {
  double density = 0; // reference density ρ0, kg/m³
  double bulk = 0;    // K, Pa
  double shear = 0;   // G, Pa

  static ElasticConstants from(const MaterialSpec& m);
  // P-wave modulus K + 4G/3 (Pa): sets the longitudinal wave speed.
  double p_wave_modulus() const { return bulk + 4.0 * shear / 3.0; }
};

// Advances the deviatoric stress S (Pa) over dt with strain rate D and spin W.
void elastic_deviator_update(const ElasticConstants& c, const Mat3& D, const Mat3& W, double dt,
                             Mat3& S);
// Advances S and the pressure p (Pa, rate form −K tr D) over dt: the hexahedra's update.
void elastic_update(const ElasticConstants& c, const Mat3& D, const Mat3& W, double dt, Mat3& S,
                    double& p);
// Pressure from density, p = K (ρ/ρ0 − 1): the particles' update (they carry ρ).
inline double elastic_pressure(const ElasticConstants& c, double rho) {
  return c.bulk * (rho / c.density - 1.0);
}

} // namespace sphfem
