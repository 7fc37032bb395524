#include "solver/coupling/kernel_contact.hpp"

#include "solver/core/parallel.hpp"
#include "solver/sph/kernel.hpp"

#include <cmath>

namespace sphfem {

KernelContact::KernelContact(const Case& c) : bodies_(static_cast<int>(c.bodies.size())) {
  pair_of_.assign(static_cast<std::size_t>(bodies_) * bodies_, -1);
  for (const ContactSpec& spec : c.contacts) {
    if (spec.model != ContactModel::Kernel)
      continue;
    const int a = c.body_index(spec.bodies[0]), b = c.body_index(spec.bodies[1]);
    pair_of_[a * bodies_ + b] = pair_of_[b * bodies_ + a] = static_cast<int>(pairs_.size());
    pairs_.push_back({spec.penalty, spec.exponent});
  }
  in_contact_.assign(bodies_, 0);
  for (int a = 0; a < bodies_; ++a)
    for (int b = 0; b < bodies_; ++b)
      in_contact_[a] |= pair_of_[a * bodies_ + b] >= 0 ? 1 : 0;
}

void KernelContact::apply(Particles& p, const NeighbourList& list,
                          const std::vector<Index>* only) const {
  // Each row (real and background particles) gathers its own forces (race-free); each pair's
  // energy is counted once per row, so halved. A pair with a mirror image (no row of its own)
  // then counts half: its mirror pair, the other half, lies outside the modelled part.
  const IndexRange rows = IndexRange::of(only, p.rows());
#pragma omp parallel for schedule(static,                                                          \
                                  interleave_chunk) if (rows.count > parallel_min_items / 16)
  for (Index k = 0; k < rows.count; ++k) {
    const Index i = rows[k];
    if (!in_contact_[p.body_p[i]])
      continue;
    const int row = p.body_p[i] * bodies_;
    const Vec3 xi = p.x_p[i];
    const double V_i = p.m_p[i] / p.rho_p[i];
    Vec3 f = Vec3::Zero();
    double phi = 0;
    for (Index j : list.of(i)) {
      const int pair_k = pair_of_[row + p.body_p[j]];
      if (pair_k < 0)
        continue;
      const Vec3 x_ij = xi - p.x_p[j];
      const double r = x_ij.norm();
      const double h_ij = 0.5 * (p.h_p[i] + p.h_p[j]);
      if (r >= 2.0 * h_ij || r == 0.0)
        continue;
      const Pair& pair = pairs_[pair_k];
      const double V_j = p.m_p[j] / p.rho_p[j];
      const double V_ij = 2.0 * V_i * V_j / (V_i + V_j);
      const double W0 = kernel_W(0.5 * (p.dp_p[i] + p.dp_p[j]), h_ij);
      const double ratio = kernel_W(r, h_ij) / W0;
      const double scaled = std::pow(ratio, pair.exponent - 1.0);
      phi += pair.penalty * V_ij * scaled * ratio;
      const Vec3 f_ij =
          -(pair.penalty * V_ij * pair.exponent * scaled * kernel_dW(r, h_ij) / (r * W0)) * x_ij;
      f += f_ij;
      if (j >= p.rows())
        p.fm_p[i] += f_ij; // contact with a mirror image: part of the planes' reaction
    }
    p.fc_p[i] += f;
    p.f_p[i] += f;
    p.phi_p[i] += 0.5 * phi;
  }
}

} // namespace sphfem
