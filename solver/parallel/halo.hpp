// What each part of a decomposition holds and what it would receive from the other parts every
// step (issue 28, points 2–3), counted on the model's reference configuration: its ghost
// points — particles and background particles of other parts within h_i + h_j + skin of one of
// its own (the kernel's reach, METHOD.md §2, plus the neighbour list's skin) — and its foreign
// nodes — nodes of its elements that another part owns, whose partial forces and masses are
// summed across parts. A background particle stepped on another part than its node's counts as
// a ghost point there (its filled values arrive) and as a foreign node of the node's part (its
// force returns). The halo fraction (ghost points + foreign nodes) / (own particles + own
// nodes) is what weak scaling must keep constant. Verified by
// tests/parallel/decomposition_test.cpp.
#pragma once

#include "solver/parallel/decomposition.hpp"

namespace sphfem {

struct PartLoad {
  Index particles = 0;     // owned
  Index elements = 0;      // owned
  Index nodes = 0;         // owned
  Index shared_nodes = 0;  // owned nodes that elements of other parts hold too
  Index ghost_points = 0;  // particles and background particles received (see above)
  Index foreign_nodes = 0; // nodes of its elements that other parts own, nodes' returned forces
  double cost_s = 0;       // summed entity costs per step (one thread), s

  double halo_fraction() const;
};

struct HaloCensus {
  std::vector<PartLoad> parts;
  double skin = 0;      // m
  double imbalance = 1; // the worse phase's (particles', elements'): largest part's / mean cost
};

// Throws sphfem::Error for a negative or non-finite skin or a decomposition of another model.
HaloCensus halo_census(const Model& m, const EntityCosts& costs, const Decomposition& d,
                       double skin);

} // namespace sphfem
