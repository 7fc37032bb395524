#include "solver/material/elastic.hpp"

#include "solver/io/case.hpp"
#include "solver/material/jaumann.hpp"

namespace sphfem {

ElasticConstants ElasticConstants::from(const MaterialSpec& m) {
  const double E = m.youngs_modulus, nu = m.poisson_ratio;
  return {m.density, E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
}

void elastic_deviator_update(const ElasticConstants& c, const Mat3& D, const Mat3& W, double dt,
                             Mat3& S) {
  const Mat3 deviatoric = D - (D.trace() / 3.0) * Mat3::Identity();
  S = jaumann_rotate(S, W, dt) + (2.0 * c.shear * dt) * deviatoric;
}

void elastic_update(const ElasticConstants& c, const Mat3& D, const Mat3& W, double dt, Mat3& S,
                    double& p) {
  elastic_deviator_update(c, D, W, dt, S);
  p -= c.bulk * D.trace() * dt;
}

} // namespace sphfem
