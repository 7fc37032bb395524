#include "solver/coupling/interface_ties.hpp"

#include <cmath>
#include <map>
#include <tuple>

namespace sphfem {

InterfaceTies::InterfaceTies(const Case& c, const Model& model) {
  for (const AttachSpec& a : c.attachments) {
    const int fem = c.body_index(a.fem_body), sph = c.body_index(a.sph_body);
    const double tolerance = 1e-6 * model.spacing_b[sph];
    // Background nodes of the FE body, keyed by their position rounded to the tolerance.
    using Key = std::tuple<long long, long long, long long>;
    const auto key = [&](const Vec3& x) {
      return Key{std::llround(x.x() / tolerance), std::llround(x.y() / tolerance),
                 std::llround(x.z() / tolerance)};
    };
    std::map<Key, Index> nodes;
    for (Index node : model.background_nodes)
      if (model.body_n[node] == fem)
        nodes.emplace(key(model.x_n[node]), node);
    for (Index i = 0; i < model.particle_count(); ++i)
      if (model.body_p[i] == sph)
        if (const auto it = nodes.find(key(model.x_p[i])); it != nodes.end()) {
          particle_ids_.push_back(i);
          nodes_.push_back(it->second);
        }
  }
}

void InterfaceTies::merge(Particles& p, Nodes& nodes,
                          const std::function<Index(Index)>& index_of) const {
  for (Index k = 0; k < size(); ++k) {
    const Index i = index_of(particle_ids_[k]), node = nodes_[k];
    if (i < 0)
      continue; // a distributed run's rank not holding the particle (nor stepping the node)
    const double m_p = p.m_p[i], m_n = nodes.m_n[node];
    const Vec3 v = (m_p * p.v_p[i] + m_n * nodes.v_n[node]) / (m_p + m_n);
    p.v_p[i] = nodes.v_n[node] = v;
  }
}

void InterfaceTies::follow(Particles& p, const Nodes& nodes,
                           const std::function<Index(Index)>& index_of) const {
  for (Index k = 0; k < size(); ++k) {
    const Index i = index_of(particle_ids_[k]);
    if (i < 0)
      continue;
    p.v_p[i] = nodes.v_n[nodes_[k]];
    p.xsph_p[i].setZero();
  }
}

} // namespace sphfem
