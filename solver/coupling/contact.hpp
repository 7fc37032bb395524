// Contact between bodies: the case's contact pairs, each by its model — the paper's kernel
// contact (kernel_contact.hpp, `model: kernel`) or the surface contact (surface_contact.hpp,
// `model: surface`, the default). Evaluated after the particles' forces, on the particle arrays
// and their background rows (the FE nodes of contact bodies), whose forces then go back to the
// nodes. Keeps what the balances and the step need: the contact energy, the power friction
// dissipates, and the contact springs' stable step. A case without contact pairs builds none of
// this. Verified by tests/coupling/contact_test.cpp and tests/coupling/surface_contact_test.cpp.
#pragma once

#include "solver/core/exact_sum.hpp"
#include "solver/coupling/kernel_contact.hpp"
#include "solver/coupling/surface_contact.hpp"
#include "solver/io/state_archive.hpp"

#include <limits>
#include <vector>

namespace sphfem {

class Contact {
public:
  Contact() = default;
  // p: the particle arrays with the background rows of `background`, before any step.
  Contact(const Case& c, const Model& model, const Particles& p,
          const BackgroundParticles& background, const HexElements& elements);

  bool empty() const { return kernel_.empty() && surface_.empty(); }
  // Sets fc_p to the contact force on every row and adds it to f_p; sets phi_p to each row's
  // share of the contact energy. lists: changes whenever the neighbour lists are made anew
  // (ParticleSystem::list_builds); dt: the step just taken (0 at the start). ranks: a
  // distributed run's (this rank's rows are evaluated; the friction power and the stable step
  // are then the ranks' total and least), null: one process.
  // Collective when distributed.
  void apply(Particles& p, const NeighbourList& list, long long lists, const HexElements& elements,
             double dt, const ContactRanks* ranks = nullptr);
  // Whether eroding elements change the contact surfaces (a distributed run then shares the
  // erosion of every element before apply()).
  bool follows_erosion() const { return surface_.follows_erosion(); }
  // Whether apply() reads the neighbour lists of background rows that a distributed run's rank
  // does not step: the surface contact finds its candidates from its faces' corners. A rank
  // evaluates a slave that is its own or near a face with an own corner; the slave's candidate
  // faces are those with a corner listing it, so it reads the lists of the corners within two
  // list cutoffs and a face's span of its own rows (ParticleSystem lists those within four).
  bool reads_lists_of_nearby_background_rows() const { return !surface_.empty(); }

  // Penalty energy stored at the last evaluation, J: Σ phi_p over `rows` (a distributed run: the
  // rows this rank owns; each pair's energy is on its slave's row), exactly.
  ExactSum energy(const Particles& p, IndexRange rows) const;
  // Power dissipated by friction at the last evaluation, W (its forces act over the next kick).
  double friction_power() const { return friction_power_; }
  // Critical step 2/ω of the stiffest surface contact spring near contact, s (∞ if none; the
  // kernel contact sets no limit).
  double stable_dt() const {
    return omega2_ > 0 ? 2 / std::sqrt(omega2_) : std::numeric_limits<double>::infinity();
  }
  // Contact force on body `body` from its contact partners, N: Σ fc_p over its `rows`, exactly
  // (x, y, z).
  ExactSums<3> force_on(const Particles& p, int body, IndexRange rows) const;

  void persist(StateArchive& a);

private:
  KernelContact kernel_;
  SurfaceContact surface_;
  std::vector<char> in_contact_; // per body: named in some pair
  double friction_power_ = 0;
  double omega2_ = 0;
};

} // namespace sphfem
