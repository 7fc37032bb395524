// The SPH half of a simulation: the particles, their neighbour search and the per-step
// sequence of METHOD.md §7 for particles — kick (v^{n+½} = v^{n−½} + Δt f/m), drift
// (x^{n+1} = xⁿ + Δt (v^{n+½} + XSPH)), then the particle phase of sph_update.hpp on the new
// positions. Particles are kept sorted by cell (reordered whenever the neighbour list is
// rebuilt); id_p and index_of() map back to model.h5 order. A case without particles builds
// none of this. Verified by tests/sph/sph_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/material/elastic.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/model.hpp"
#include "solver/state/particles.hpp"

#include <vector>

namespace sphfem {

class ParticleSystem {
public:
  ParticleSystem() = default;
  ParticleSystem(const Case& c, const Model& model, const std::vector<ElasticConstants>& materials);

  bool empty() const { return particles_.size() == 0; }
  // v += Δt_v f/m and the heating of the artificial terms over the same interval.
  void kick(double dt_v);
  void drift(double dt);
  // Neighbours (rebuilt when needed), kinematics, material update over dt, forces.
  void update(double dt);
  // Stable step of the particles, s (∞ without particles).
  double stable_dt() const { return dt_stable_; }

  const Particles& particles() const { return particles_; }
  Particles& particles() { return particles_; }
  // Current index of the particle that model.h5 lists at `id`.
  Index index_of(Index id) const { return index_of_id_[id]; }
  long long rebuilds() const { return rebuilds_; }

private:
  void rebuild();
  void forces(double dt);

  SphSpec spec_;
  std::vector<ElasticConstants> materials_;
  Particles particles_;
  NeighbourSearch search_;
  std::vector<Index> index_of_id_;
  double skin_ = 0;
  double dt_stable_ = 0;
  long long rebuilds_ = 0;
};

} // namespace sphfem
