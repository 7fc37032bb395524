// Interface ties (attachment, METHOD.md §4.2): where the mesher puts the SPH lattice on the FE
// mesh's nodes (lattice: nodes), the SPH body's interface layer coincides with the FE body's
// interface nodes, each carrying half the mass of the site. Through kernel sums alone such a
// particle is held only by half its neighbours (the background half does not react to its
// motion), and the layer drifts off its nodes — 0.2 mm (0.2 Δp) in 5 µs when two glued blocks
// are pulled apart at ±100 m/s. A tie makes each such pair one material point: after the kick
// both take the momentum-weighted mean velocity, which is exactly the kick of the pair's summed
// force on its summed mass; the particle then drifts with the node (no XSPH).
// Verified by tests/coupling/coupling_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"
#include "solver/state/nodes.hpp"
#include "solver/state/particles.hpp"

#include <functional>
#include <vector>

namespace sphfem {

class InterfaceTies {
public:
  InterfaceTies() = default;
  // Pairs of a particle of an attached SPH body and a background node of the FE body it is
  // attached to that lie within 1e-6 Δp of each other.
  InterfaceTies(const Case& c, const Model& model);

  bool empty() const { return particle_ids_.empty(); }
  Index size() const { return static_cast<Index>(particle_ids_.size()); }
  // Tie k: the particle (model.h5 order) and the node it binds.
  Index particle_id(Index k) const { return particle_ids_[k]; }
  Index node(Index k) const { return nodes_[k]; }

  // After the kicks: particle and node take their momentum-weighted mean velocity.
  // index_of maps a particle id (model.h5 order) to its current index, −1 for a particle not held
  // (a distributed run's rank: a tie's particle is held where its node is stepped).
  void merge(Particles& p, Nodes& nodes, const std::function<Index(Index)>& index_of) const;
  // After the node constraints: the particle takes the node's velocity and no XSPH shift.
  void follow(Particles& p, const Nodes& nodes, const std::function<Index(Index)>& index_of) const;

private:
  std::vector<Index> particle_ids_;
  std::vector<Index> nodes_;
};

} // namespace sphfem
