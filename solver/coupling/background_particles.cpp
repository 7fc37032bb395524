#include "solver/coupling/background_particles.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"
#include "solver/fem/nodal_stress.hpp"

namespace sphfem {

void BackgroundParticles::initialise(const Case& c, const Model& model,
                                     const std::vector<Material>& materials, Particles& p) const {
  const std::vector<int> group = c.body_groups();
  for (Index k = 0; k < size(); ++k) {
    const Index b = p.background_row(k), node = nodes_[k];
    const int body = model.body_n[node];
    SPHFEM_CHECK(body >= 0 && body < static_cast<int>(c.bodies.size()), "model.h5: particle ", b,
                 " has body id ", body);
    const double density = materials[body].elastic.density; // mass and density: fill()
    p.start_row(b, {model.x_n[node], c.bodies[body].velocity, 0.0, density, model.h_background[k],
                    model.spacing_background[k], body, group[body], -1,
                    MaterialPoint::initial(materials[body])});
  }
}

void BackgroundParticles::fill(const Nodes& nodes, const HexElements& elements,
                               const NodeGather& around, Particles& p,
                               const std::vector<Index>* only) const {
  const IndexRange filled = IndexRange::of(only, size());
#pragma omp parallel for schedule(static) if (filled.count > parallel_min_items)
  for (Index m = 0; m < filled.count; ++m) {
    const Index k = filled[m], b = p.background_row(k), i = nodes_[k];
    const Mat3 sigma = nodal_stress(elements, around, i);
    double mass = 0, volume = 0;
    for (Index entry : around.around(i)) {
      if (elements.eroded_e[entry / 8])
        continue;
      mass += elements.mass_e[entry / 8];
      volume += elements.V_e[elements.slot(entry / 8)];
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

void BackgroundParticles::return_forces(const Particles& p, std::vector<Vec3>& f_nodes,
                                        const std::vector<Index>* only) const {
  // Each node has at most one background particle: no two slots write the same node.
  const IndexRange returned = IndexRange::of(only, size());
#pragma omp parallel for schedule(static) if (returned.count > parallel_min_items)
  for (Index m = 0; m < returned.count; ++m) {
    const Index k = returned[m];
    f_nodes[nodes_[k]] += p.f_p[p.background_row(k)];
  }
}

ExactSum BackgroundParticles::energy(const Particles& p, IndexRange rows) const {
  return exact_sums<1>(rows, [&](Index i) { return std::array{p.e_p[i] - 0.5 * p.de_p[i]}; })[0];
}

} // namespace sphfem
