#include "solver/parallel/subdomain.hpp"

#include <algorithm>
#include <numeric>

namespace sphfem {

Subdomain make_subdomain(const Decomposition& d, const Model& m, int rank, bool collective) {
  Subdomain s;
  const Index n = m.node_count(), ne = m.element_count();
  s.owns_n.assign(n, 0);
  for (Index i = 0; i < n; ++i)
    if (d.part_n[i] == rank) {
      s.owns_n[i] = 1;
      s.nodes.push_back(i);
    }
  std::vector<unsigned char> read(n, 0);
  for (Index k = 0; k < ne; ++k) {
    if (d.part_e[k] != rank) {
      if (std::ranges::any_of(m.hex_e[k], [&s](Index i) { return s.owns_n[i] != 0; }))
        s.foreign_elements.push_back(k);
      continue;
    }
    s.elements.push_back(k);
    for (Index i : m.hex_e[k])
      read[i] = 1;
  }
  for (Index i = 0; i < n; ++i)
    if (read[i] && !s.owns_n[i])
      s.halo_nodes.push_back(i);
  const Index nb = static_cast<Index>(m.background_nodes.size());
  for (Index k = 0; k < nb; ++k)
    if (s.owns_n[m.background_nodes[k]])
      s.background.push_back(k);
  if (collective) {
    s.halo = HaloExchange(d.part_n, s.halo_nodes);
    s.element_forces = HaloExchange(d.part_e, s.foreign_elements);
    std::vector<Index> every_element(ne);
    std::iota(every_element.begin(), every_element.end(), Index{0});
    s.all_elements = HaloExchange(d.part_e, every_element);
    std::vector<int> node_part(nb);
    std::vector<Index> stepped_here;
    for (Index k = 0; k < nb; ++k) {
      node_part[k] = d.part_n[m.background_nodes[k]];
      if (d.part_b[k] == rank)
        stepped_here.push_back(k);
    }
    s.background_filled = HaloExchange(node_part, stepped_here);
    s.background_returned = HaloExchange(d.part_b, s.background);
  }
  return s;
}

} // namespace sphfem
