// This rank's share of a distributed run's particles (issue 28, point 3), for one neighbour
// list: the rows it owns (the decomposition's particles, by model id, and the background rows
// of its nodes), the rows it computes —
// its own and their neighbours, whose density and stress its own forces read, evaluated here as
// their owners do — and the exchanges:
// - `halo`: every field of the rows those computations read and this rank does not own (the
//   computed rows and their neighbours; a mirror image stands for its source), before each
//   particle phase;
// - `all`: every row this rank does not own, before a neighbour-list rebuild (every rank then
//   sorts and lists all particles as one process does) and before output.
// Rebuilt with each neighbour list; a coupling that reads further (the surface contact's faces
// and slaves) adds its rows to the halo with `read_also`. The arrays keep the one-process layout
// on every rank.
// Verified by tests/parallel/decomposition_test.cpp and tests/e2e/mpi_launch_test.cpp.
#pragma once

#include "solver/parallel/halo_exchange.hpp"
#include "solver/sph/mirror_particles.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/particles.hpp"

#include <span>
#include <vector>

namespace sphfem {

struct ParticleShare {
  std::vector<int> owner;          // per row (real and background): the owning rank
  std::vector<unsigned char> owns; // per row of all (mirror images: their source's)
  std::vector<Index> own;          // owned rows, ascending
  std::vector<Index> computed;     // rows whose kinematics and material update run here
  std::vector<Index> halo_rows;    // rows read here and owned elsewhere, ascending
  HaloExchange halo, all;
};

// owner_of_id: the rank of each model particle; owner_of_background: of each background row
// (its node's). Collective when `collective`.
ParticleShare make_particle_share(const Particles& p, const NeighbourList& list,
                                  const MirrorParticles& mirrors, std::span<const int> owner_of_id,
                                  std::span<const int> owner_of_background, int rank,
                                  bool collective = true);

// Adds `rows` (any order; own rows and rows already read are skipped) to the halo; false, and
// nothing changed, when no rank has rows to add. Collective.
bool read_also(ParticleShare& s, std::span<const Index> rows);

} // namespace sphfem
