// This rank's share of a distributed run's particles (issue 28, point 3), for one neighbour
// list: the rows it owns and steps (the decomposition's particles, by model id, and background
// rows, both of the particles' cut) and its halo — the rows its own rows' kinematics, material
// update and forces read and other ranks own: their neighbours (a mirror image stands for its
// source), and what a coupling adds (`read_also`: the surface contact's faces and slaves). The
// exchanges:
// - `halo`: the halo rows, twice in each particle phase: before the kinematics what moved
//   (Particles::for_each_moved_field: positions, velocities, forces, the background fill) and
//   after the material update what it changed (for_each_updated_field: density, stress, kill
//   state and the rest that the forces read), so that no rank repeats another's material update;
//   each carries what the owners wrote since the other (together a third of a row's bytes);
// - `all`: every row and mirror image this rank does not own (an image is its source's owner's):
//   their positions and smoothing lengths before a neighbour-list rebuild
//   (Particles::for_each_listed_field: every rank then sorts all particles as one process does,
//   lists its own rows — and the background rows near them that a coupling reads — and the new
//   halo is refreshed whole after it), every field before a checkpoint or a new cut.
// A rank refreshes each step only the mirror images of its visible rows (`visible`), the only
// ones its rows read; the others are current on their source's owner.
// Rebuilt with each neighbour list. The arrays keep the one-process layout on every rank.
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
  std::vector<Index> halo_rows;    // rows read here and owned elsewhere, ascending
  std::vector<Index> visible;      // own and halo rows, then the images of those, ascending
  HaloExchange halo, all;
};

// owner_of_id: the rank of each model particle; owner_of_background: of each background row in
// the particle phase. Collective when `collective`.
ParticleShare make_particle_share(const Particles& p, const NeighbourList& list,
                                  const MirrorParticles& mirrors, std::span<const int> owner_of_id,
                                  std::span<const int> owner_of_background, int rank,
                                  bool collective = true);

// Adds `rows` (any order; own rows and rows already read are skipped) to the halo, and their
// images to the visible rows; false, and nothing changed, when no rank has rows to add.
// Collective.
bool read_also(ParticleShare& s, const MirrorParticles& mirrors, std::span<const Index> rows);

} // namespace sphfem
