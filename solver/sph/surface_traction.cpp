#include "solver/sph/surface_traction.hpp"

#include "solver/core/error.hpp"
#include "solver/sph/kernel.hpp"
#include "solver/sph/neighbour_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace sphfem {

namespace {

// Σ over the listed neighbours b of a within 2 h_ab of visit(b, x_ab, ∂W/∂r / r).
template <class Visit>
void for_each_pair(const Model& model, const std::vector<Index>& band, const NeighbourList& list,
                   Index a, Visit visit) {
  const Index i = band[a];
  for (Index b : list.of(a)) {
    const Index j = band[b];
    const Vec3 x_ij = model.x_p[i] - model.x_p[j];
    const double r = x_ij.norm();
    const double h_ij = 0.5 * (model.h_p[i] + model.h_p[j]);
    if (r < 2.0 * h_ij && r > 0.0)
      visit(b, x_ij, kernel_dW(r, h_ij) / r);
  }
}

} // namespace

TractionWeights surface_traction_weights(const Model& model, int body, const ParticleFace& face,
                                         bool gradient_correction) {
  SPHFEM_CHECK(!face.particles.empty(), "a loaded particle face has no particles");
  const Vec3 n = face.normal;
  double plane = -std::numeric_limits<double>::infinity();
  for (Index i : face.particles)
    plane = std::max(plane, n.dot(model.x_p[i]));
  double h_max = 0;
  for (Index i = 0; i < model.particle_count(); ++i)
    if (model.body_p[i] == body)
      h_max = std::max(h_max, model.h_p[i]);
  // Depth below the face's outer layer. The correction C differs from the identity within 2h
  // of the face, so a corrected pair sum can be non-zero down to 4h: those particles carry the
  // load. Their sums need C of particles down to 6h, and those C's their neighbours to 8h.
  const auto depth = [&](Index i) { return plane - n.dot(model.x_p[i]); };
  const double loaded = 4.0 * h_max, corrected = 6.0 * h_max, searched = 8.0 * h_max;
  std::vector<Index> band;
  std::vector<Vec3> x;
  std::vector<double> h;
  for (Index i = 0; i < model.particle_count(); ++i)
    if (model.body_p[i] == body && depth(i) < searched) {
      band.push_back(i);
      x.push_back(model.x_p[i]);
      h.push_back(model.h_p[i]);
    }
  NeighbourSearch search;
  search.build(x, h, 0.0);
  const NeighbourList& list = search.list();
  const Index count = static_cast<Index>(band.size());

  // C = M⁻¹, M = −(1/ρ_i) Σ_j m_j x_ij ⊗ ∇W, as sph_kinematics computes it.
  std::vector<Mat3> C(count, Mat3::Identity());
  if (gradient_correction)
    for (Index a = 0; a < count; ++a) {
      if (depth(band[a]) >= corrected)
        continue;
      Mat3 M = Mat3::Zero();
      for_each_pair(model, band, list, a, [&](Index b, const Vec3& x_ij, double dW_r) {
        M -= (model.m_p[band[b]] / model.rho_p[band[a]] * dW_r) * x_ij * x_ij.transpose();
      });
      C[a] = sphfem::gradient_correction(M, true);
    }

  // w_i = −n · g_i. Shares can be negative (with the correction, the third and fourth layers
  // pull outwards a little): they are part of the distribution that holds the uniform state.
  TractionWeights weights;
  const double face_area = std::accumulate(face.area.begin(), face.area.end(), 0.0);
  const double negligible = 1e-12 * face_area / static_cast<double>(face.particles.size());
  for (Index a = 0; a < count; ++a) {
    const Index i = band[a];
    if (depth(i) >= loaded)
      continue;
    const double rho_i = model.rho_p[i];
    Vec3 g = Vec3::Zero();
    for_each_pair(model, band, list, a, [&](Index b, const Vec3& x_ij, double dW_r) {
      const double rho_j = model.rho_p[band[b]];
      const Mat3 pair = C[a].transpose() / (rho_i * rho_i) + C[b].transpose() / (rho_j * rho_j);
      g += (model.m_p[i] * model.m_p[band[b]] * dW_r) * (pair * x_ij);
    });
    const double w = -n.dot(g);
    if (std::abs(w) > negligible) {
      weights.particles.push_back(i);
      weights.area.push_back(w);
    }
  }
  const double sum = std::accumulate(weights.area.begin(), weights.area.end(), 0.0);
  SPHFEM_CHECK(sum > 0, "a loaded particle face carries no SPH surface weight");
  weights.scale = face_area / sum;
  for (double& w : weights.area)
    w *= weights.scale;
  return weights;
}

} // namespace sphfem
