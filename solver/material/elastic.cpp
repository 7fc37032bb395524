#include "solver/material/elastic.hpp"

#include "solver/io/case.hpp"
#include "solver/material/jaumann.hpp"

namespace sphfem {

ElasticConstants ElasticConstants::from(const MaterialSpec& m) {
  const double E = m.youngs_modulus, nu = m.poisson_ratio;
  return {m.density, E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
}

void elastic_update(const ElasticConstants& c, const Mat3& D, const Mat3& W, double dt, Mat3& S,
                    double& p) {
  const double volumetric = D.trace();
  const Mat3 deviatoric = D - (volumetric / 3.0) * Mat3::Identity();
  S = jaumann_rotate(S, W, dt) + (2.0 * c.shear * dt) * deviatoric;
  p -= c.bulk * volumetric * dt;
}

} // namespace sphfem
