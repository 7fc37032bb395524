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
//   each carries what the owners wrote since the other (together a third of a row's bytes).
// Mirror images are a rank's own: those of the rows it bins at a rebuild (below), numbered in
// their sources' order; it refreshes each step only those of its visible rows (`visible`), the
// only ones its rows read.
// Rebuilt with each neighbour list.
//
// A rank holds the rows it owns and those near them only (RowNumbering): its real particles'
// rows in model-id order, then its background rows in their nodes' order (also those of the
// nodes it steps), then its mirror images. The exchanges are
// agreed on the numbers every rank shares and then renumbered to each side's rows
// (HaloExchange::to_slots).
//
// A rebuild needs, on each rank, every row within reach of its own — their positions and
// smoothing lengths only: `rows_near_ranks` names, for each rank, the rows of this rank within
// `margin` of the other's own rows' bounding box, or with a mirror image there; the owners
// send them (HaloExchange::pushed). That rank then holds and bins its own rows and those, and
// lists its own rows exactly as one process would.
// Verified by tests/parallel/decomposition_test.cpp and tests/e2e/mpi_launch_test.cpp.
#pragma once

#include "solver/parallel/halo_exchange.hpp"
#include "solver/sph/mirror_particles.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/particles.hpp"

#include <limits>
#include <span>
#include <vector>

namespace sphfem {

// How a rank's rows map to the numbers every rank shares: a real particle's is its model id,
// background particle k's the model's particle count + k.
struct RowNumbering {
  std::span<const Index> id_of_row; // per row: a real particle's model id
  std::span<const Index> row_of_id; // per model particle: its row here, −1 when not held here
  Index real = 0;                   // real particles' rows here (background rows follow)
  // Per background row here (row − real): its background particle; per background particle: its
  // row (−1: not held). Empty: every one, in order (Particles::background_row).
  std::span<const Index> background_of_row = {};
  std::span<const Index> row_of_background = {};

  Index model() const { return static_cast<Index>(row_of_id.size()); }
  Index number(Index row) const {
    if (row < real)
      return id_of_row[row];
    return model() + (background_of_row.empty() ? row - real : background_of_row[row - real]);
  }
  Index row(Index number) const {
    if (number < model())
      return row_of_id[number];
    const Index k = number - model();
    return row_of_background.empty() ? real + k : row_of_background[k];
  }
};

struct ParticleShare {
  std::vector<int> owner;          // per row (real and background): the owning rank
  std::vector<unsigned char> owns; // per row of all (mirror images: their source's)
  std::vector<Index> own;          // owned rows, ascending
  std::vector<Index> halo_rows;    // rows read here and owned elsewhere, ascending
  std::vector<Index> visible;      // own and halo rows, then the images of those, ascending
  HaloExchange halo;
};

// owner: the rank of each shared number (RowNumbering: model particles, then background rows).
// Collective when `collective`.
ParticleShare make_particle_share(const Particles& p, const NeighbourList& list,
                                  const MirrorParticles& mirrors, std::span<const int> owner,
                                  const RowNumbering& numbering, int rank, bool collective = true);

// Adds `rows` (any order; own rows and rows already read are skipped) to the halo, and their
// images to the visible rows; false, and nothing changed, when no rank has rows to add.
// Collective.
bool read_also(ParticleShare& s, const MirrorParticles& mirrors, std::span<const Index> rows,
               std::span<const int> owner, const RowNumbering& numbering);

// The bounding box of the rows `own` lists (empty: lo > hi).
struct RowBox {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  RowBox(std::span<const Vec3> x, std::span<const Index> own);
  // Whether x lies within `margin` of the box (along each axis).
  bool near(const Vec3& x, double margin) const {
    return ((x - lo).array() >= -margin).all() && ((hi - x).array() >= -margin).all();
  }
};

// Per rank: the rows among `own` (this rank's, ascending; `box` theirs) at `x` (positions per
// row) within `margin` of that rank's own rows' box, or with a mirror image there (images within
// `image_reach` of a plane). Empty for this rank. Collective: the ranks' boxes are exchanged.
std::vector<std::vector<Index>> rows_near_ranks(const Particles& p, std::span<const Vec3> x,
                                                std::span<const Index> own, const RowBox& box,
                                                const MirrorParticles& mirrors, double margin,
                                                double image_reach);

} // namespace sphfem
