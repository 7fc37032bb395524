#include "solver/coupling/background_particles.hpp"

#include "solver/core/parallel.hpp"
#include "solver/fem/nodal_stress.hpp"

namespace sphfem {

void BackgroundParticles::fill(const Nodes& nodes, const HexElements& elements,
                               const NodeGather& around, Particles& p) const {
  const Index count = size();
#pragma omp parallel for schedule(static) if (count > parallel_min_items)
  for (Index k = 0; k < count; ++k) {
    const Index b = p.real + k, i = nodes_[k];
    const Mat3 sigma = nodal_stress(elements, around, i);
    double mass = 0, volume = 0;
    for (Index entry : around.around(i)) {
      if (elements.eroded_e[entry / 8])
        continue;
      mass += elements.mass_e[entry / 8];
      volume += elements.V_e[entry / 8];
    }
    p.x_p[b] = nodes.x_n[i];
    p.v_p[b] = p.u_p[b] = nodes.v_n[i];
    p.m_p[b] = nodes.m_n[i];
    if (volume > 0) // else every element around the node is eroded: the density stays
      p.rho_p[b] = mass / volume;
    p.p_p[b] = -sigma.trace() / 3.0;
    p.S_p[b] = sigma + p.p_p[b] * Mat3::Identity();
    p.f_p[b] = nodes.f_int_n[i];
  }
}

void BackgroundParticles::return_forces(const Particles& p, std::vector<Vec3>& f_nodes) const {
  // Each node has at most one background particle: no two slots write the same node.
  const Index count = size();
#pragma omp parallel for schedule(static) if (count > parallel_min_items)
  for (Index k = 0; k < count; ++k)
    f_nodes[nodes_[k]] += p.f_p[p.real + k];
}

} // namespace sphfem
