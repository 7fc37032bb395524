// The census of what each part holds and receives (halo.hpp): owned counts, foreign nodes, and
// ghost points from one neighbour search over particles and background particles.
// Verified by tests/parallel/decomposition_test.cpp.
#include "solver/parallel/halo.hpp"

#include "solver/core/error.hpp"
#include "solver/sph/neighbour_search.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace sphfem {

double PartLoad::halo_fraction() const {
  const Index own = particles + nodes;
  return own == 0 ? 0.0 : static_cast<double>(ghost_points + foreign_nodes) / own;
}

HaloCensus halo_census(const Model& m, const EntityCosts& costs, const Decomposition& d,
                       double skin) {
  if (!(skin >= 0) || !std::isfinite(skin))
    throw Error("halo census: the skin must be a finite length ≥ 0 m, got " + std::to_string(skin));
  if (d.part_p.size() != m.x_p.size() || d.part_e.size() != m.hex_e.size() ||
      d.part_n.size() != m.x_n.size() || d.part_b.size() != m.background_nodes.size() ||
      costs.particle.size() != m.x_p.size() || costs.element.size() != m.hex_e.size() ||
      costs.background.size() != m.background_nodes.size())
    throw Error("halo census: the decomposition or the costs are not of this model");

  HaloCensus census;
  census.skin = skin;
  census.parts.resize(static_cast<std::size_t>(d.parts));
  for (std::size_t i = 0; i < m.x_p.size(); ++i)
    ++census.parts[static_cast<std::size_t>(d.part_p[i])].particles;
  for (std::size_t e = 0; e < m.hex_e.size(); ++e)
    ++census.parts[static_cast<std::size_t>(d.part_e[e])].elements;
  const PhaseCosts phases = phase_costs(d, costs);
  for (std::size_t q = 0; q < census.parts.size(); ++q)
    census.parts[q].cost_s = phases.particle[q] + phases.element[q];
  for (std::size_t n = 0; n < m.x_n.size(); ++n) {
    PartLoad& p = census.parts[static_cast<std::size_t>(d.part_n[n])];
    ++p.nodes;
    p.shared_nodes += d.shared_n[n];
  }

  // Foreign nodes: each (part, node) pair once.
  std::vector<int> seen(m.x_n.size(), -1);
  std::vector<std::size_t> by_part(m.hex_e.size());
  for (std::size_t e = 0; e < by_part.size(); ++e)
    by_part[e] = e;
  std::stable_sort(by_part.begin(), by_part.end(),
                   [&d](std::size_t a, std::size_t b) { return d.part_e[a] < d.part_e[b]; });
  for (const std::size_t e : by_part) {
    const int q = d.part_e[e];
    for (const Index n : m.hex_e[e]) {
      const auto k = static_cast<std::size_t>(n);
      if (d.part_n[k] != q && seen[k] != q) {
        seen[k] = q;
        ++census.parts[static_cast<std::size_t>(q)].foreign_nodes;
      }
    }
  }

  // A background particle filled on its node's part and stepped on another: received by the
  // particles' part (a ghost point), its force sent back to the node's part (a foreign node).
  for (std::size_t k = 0; k < m.background_nodes.size(); ++k) {
    const int node_part = d.part_n[static_cast<std::size_t>(m.background_nodes[k])];
    if (node_part != d.part_b[k]) {
      ++census.parts[static_cast<std::size_t>(d.part_b[k])].ghost_points;
      ++census.parts[static_cast<std::size_t>(node_part)].foreign_nodes;
    }
  }

  // Ghost points: the particles and background particles, each with its part, searched together.
  const std::size_t np = m.x_p.size(), nb = m.background_nodes.size();
  std::vector<Vec3> x(m.x_p);
  std::vector<double> h(m.h_p);
  std::vector<int> part(d.part_p);
  for (std::size_t k = 0; k < nb; ++k) {
    const auto n = static_cast<std::size_t>(m.background_nodes[k]);
    x.push_back(m.x_n[n]);
    h.push_back(m.h_background[k]);
    part.push_back(d.part_b[k]);
  }
  if (np > 0) {
    NeighbourSearch search;
    search.build(x, h, skin);
    const NeighbourList& list = search.list();
    std::vector<unsigned char> ghost(x.size() * census.parts.size(), 0);
    for (std::size_t i = 0; i < x.size(); ++i) // background particles meet real ones only
      for (const Index j : list.of(static_cast<Index>(i)))
        if (part[static_cast<std::size_t>(j)] != part[i] &&
            (i < np || static_cast<std::size_t>(j) < np))
          ghost[static_cast<std::size_t>(part[i]) * x.size() + static_cast<std::size_t>(j)] = 1;
    for (std::size_t q = 0; q < census.parts.size(); ++q)
      census.parts[q].ghost_points += static_cast<Index>(
          std::count(ghost.begin() + static_cast<std::ptrdiff_t>(q * x.size()),
                     ghost.begin() + static_cast<std::ptrdiff_t>((q + 1) * x.size()), 1));
  }

  census.imbalance = phase_imbalance(d, costs);
  return census;
}

} // namespace sphfem
