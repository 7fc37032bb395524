// Loads and kinematic boundary conditions on the named faces of SPH bodies (the particle
// layers of Model::particle_faces): a pressure p(t) gives each particle i within 4h of the face
// the force −p w_i n, w_i its share of the face area from surface_traction.hpp (consistent
// with the SPH momentum equation; n the face's outward normal, that of the initial face, not a
// follower load), and fixed / prescribed-velocity conditions set the face particles'
// velocities. A symmetry plane (mirror particles) holds the particles lying on it (lattice on
// nodes) to it: their normal velocity is zero. Applied right after the particles' kick; returns
// the work and impulse of loads and reactions for the energy and momentum balances.
// Verified by tests/sph/particle_boundaries_test.cpp and the bar_pressed_sph case.
#pragma once

#include "solver/core/time_function.hpp"
#include "solver/io/case.hpp"
#include "solver/sph/particle_system.hpp"
#include "solver/state/model.hpp"
#include "solver/time/constraints.hpp"

#include <array>
#include <optional>
#include <vector>

namespace sphfem {

class ParticleBoundaries {
public:
  ParticleBoundaries() = default;
  ParticleBoundaries(const Case& c, const Model& model);

  // t: time of the loads (tⁿ); t_half: of the velocities (t^{n+½}); dt_v: the kick's interval.
  ReactionTotals apply(double t, double t_half, double dt_v, ParticleSystem& system) const;
  bool empty() const { return loads_.empty() && constraints_.empty(); }

private:
  struct Load {
    std::vector<Index> ids;   // particle ids (model.h5 order)
    std::vector<double> area; // share of the face area, m²
    Vec3 normal;
    double pressure;
    TimeFunction function;
  };
  struct Constraint {
    std::vector<Index> ids;
    std::array<std::optional<double>, 3> velocity; // all zero for fixed
    TimeFunction function;
  };
  std::vector<Load> loads_;
  std::vector<Constraint> constraints_;
};

} // namespace sphfem
