// This rank's share of a distributed run's finite elements (issue 28, point 3): the nodes it
// owns (the decomposition's), the elements it computes (the decomposition's: each element once),
// and the exchanges that keep the rest current:
// - `halo`: after the nodes move, the positions and velocities of its elements' nodes that other
//   ranks own (one message per neighbouring rank and step);
// - `element_forces`: after the element update, the forces on its nodes of the other ranks'
//   elements that hold one of its nodes (with what a background particle's fill reads of them:
//   HexElements::for_each_nodal_field), so that each owned node's force is summed here from all
//   its elements in the same order as on one process — each element computed once (computing
//   them on every rank holding one of their nodes cost the Børvik shot's rank 0 5–8% more
//   elements than its share);
// - `all_elements`: every element it does not compute — their erosion flags (for the contact
//   surfaces, a checkpoint and a new cut) and, at a new cut, whether they yield (their state
//   goes to their new ranks alone: Simulation::take_share);
// - background particles (METHOD.md §4.1) are filled from their node by the node's rank, which
//   holds the node's elements, and stepped in the particle phase by the particles' cut's rank
//   (Decomposition::part_b): `background_filled` sends the filled rows to that rank,
//   `background_returned` their pair and contact forces back to the node's rank before they join
//   the node's force. Indexed by background particle.
// The nodes are gathered (before a checkpoint or a new cut) by an exchange made when needed from
// the decomposition's owners (HaloExchange::gather).
// Every rank keeps the nodes' arrays and the elements' mesh fields in the model's numbering
// (replicated; each rank writes only its share of them); of the elements' state it holds only
// that of `elements` and `foreign_elements`, in that order (HexElements' slots). Verified by
// tests/parallel/decomposition_test.cpp and the mpirun runs of tests/e2e/mpi_launch_test.cpp.
#pragma once

#include "solver/parallel/decomposition.hpp"
#include "solver/parallel/halo_exchange.hpp"
#include "solver/state/model.hpp"

#include <vector>

namespace sphfem {

struct Subdomain {
  std::vector<Index> nodes;            // owned, ascending
  std::vector<unsigned char> owns_n;   // per node: 1 when owned here
  std::vector<Index> elements;         // computed here (the decomposition's), ascending
  std::vector<Index> foreign_elements; // other ranks' elements holding an owned node, ascending
  std::vector<Index> halo_nodes;       // nodes of `elements` owned elsewhere, ascending
  std::vector<Index> background;       // background particles of owned nodes: filled here
  HaloExchange halo, element_forces, all_elements, background_filled, background_returned;

  // Bytes this rank sent in the step's exchanges (the gathers for output not counted).
  long long bytes_sent() const {
    return halo.bytes_sent() + element_forces.bytes_sent() + background_filled.bytes_sent() +
           background_returned.bytes_sent();
  }
};

// The share of `rank` in `d`. Collective (the exchanges are agreed among all ranks) when the
// run has several ranks; `collective = false` builds the lists alone (tests, census).
Subdomain make_subdomain(const Decomposition& d, const Model& m, int rank, bool collective = true);

} // namespace sphfem
