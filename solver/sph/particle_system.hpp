// The SPH half of a simulation: the particles, their neighbour search and the per-step
// sequence of METHOD.md §7 for particles — kick (v^{n+½} = v^{n−½} + Δt f/m), drift
// (x^{n+1} = xⁿ + Δt (v^{n+½} + XSPH)), then the particle phase of sph_update.hpp on the new
// positions. Particles are kept sorted by cell (reordered whenever the neighbour list is
// rebuilt); id_p and index_of() map back to model.h5 order. With coupling (METHOD.md §4) the
// arrays continue with the background particles of FE nodes, refreshed from the FE state before
// each particle phase; contact between bodies (coupling/contact.hpp) is added by the step after
// the particle phase. A case without particles or background particles builds none of this.
// Verified by tests/sph/sph_test.cpp and tests/coupling/.
#pragma once

#include "solver/coupling/background_particles.hpp"
#include "solver/io/case.hpp"
#include "solver/material/material.hpp"
#include "solver/sph/mirror_particles.hpp"
#include "solver/sph/neighbour_search.hpp"
#include "solver/state/model.hpp"
#include "solver/state/particles.hpp"

#include <vector>

namespace sphfem {

// The FE state background particles are copied from.
struct FeState {
  const Nodes& nodes;
  const HexElements& elements;
  const NodeGather& around;
};

class ParticleSystem {
public:
  ParticleSystem() = default;
  // fe: required when the model has background nodes.
  ParticleSystem(const Case& c, const Model& model, const std::vector<Material>& materials,
                 const FeState* fe = nullptr);

  bool empty() const { return particles_.total() == 0; }
  // v += Δt_v f/m and the heating of the artificial terms over the same interval.
  void kick(double dt_v);
  void drift(double dt);
  // Background particles from `fe`, neighbours (rebuilt when needed), kinematics, material
  // update over dt, forces.
  void update(double dt, const FeState* fe = nullptr);
  // Adds the forces on background particles to their FE nodes.
  void return_background_forces(std::vector<Vec3>& f_nodes) const;
  // Energy stored by the coupling pairs on the background side (at the half step), J.
  double background_energy() const;
  // Force of the symmetry planes (mirror images) on the particles at the last evaluation, N:
  // an external reaction for the momentum balance.
  Vec3 mirror_force() const;
  const BackgroundParticles& background() const { return background_; }
  // Stable step of the particles, s (∞ without particles).
  double stable_dt() const { return dt_stable_; }

  const Particles& particles() const { return particles_; }
  Particles& particles() { return particles_; }
  // Current index of the particle that model.h5 lists at `id`.
  Index index_of(Index id) const { return index_of_id_[id]; }
  long long rebuilds() const { return rebuilds_; }
  const NeighbourList& neighbours() const { return search_.list(); }
  // Checkpoint: every particle field, the neighbour search, the mirror images and the counters
  // that decide the next rebuild.
  void persist(StateArchive& a);

private:
  void rebuild();
  void forces(double dt);
  void fill_background(const FeState* fe);
  void place_mirrors();

  SphSpec spec_;
  std::vector<Material> materials_;
  Particles particles_;
  NeighbourSearch search_;
  BackgroundParticles background_;
  MirrorParticles mirror_;
  std::vector<Index> index_of_id_;
  double skin_ = 0;
  double dt_stable_ = 0;
  long long rebuilds_ = 0;
};

} // namespace sphfem
