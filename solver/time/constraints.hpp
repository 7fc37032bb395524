// Kinematic boundary conditions on node velocities (METHOD.md §3): fixed (v = 0), prescribed
// velocity components scaled by a time function, and symmetry planes (no velocity along the
// plane normal). Applied to v^{n+½} after the free update; the change they make is a reaction
// force whose work and impulse are returned so energy and momentum balances stay closed.
// Verified by tests/fem/constraints_test.cpp and the plane-wave test.
#pragma once

#include "solver/core/time_function.hpp"
#include "solver/core/types.hpp"
#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <array>
#include <optional>
#include <span>
#include <vector>

namespace sphfem {

struct ReactionTotals {
  double work = 0;             // J, over the step
  Vec3 impulse = Vec3::Zero(); // N s, over the step
};

class Constraints {
public:
  Constraints() = default;
  Constraints(const Case& c, const Model& model);

  // Sets constrained components of v_half (at time t_half). v^{n−½} is recovered as
  // v_half − Δt f/m from the unconstrained update with the nodal force f. The totals count the
  // nodes `counted` marks (a distributed run's own nodes; empty: all).
  ReactionTotals apply(double t_half, double dt, const std::vector<double>& m,
                       const std::vector<Vec3>& f, std::vector<Vec3>& v_half,
                       std::span<const unsigned char> counted = {});
  // The same constraints on initial velocities (no reactions counted).
  void apply_initial(std::vector<Vec3>& v) const;

private:
  struct Symmetry {
    Index node;
    Vec3 normal;
  };
  struct Prescribed {
    Index node;
    std::array<std::optional<double>, 3> velocity;
    TimeFunction function;
  };
  void constrain(double t, std::vector<Vec3>& v) const;

  std::vector<Symmetry> symmetry_;
  std::vector<Prescribed> prescribed_;
  std::vector<Index> fixed_;
  std::vector<Index> nodes_; // every constrained node once, sorted
  std::vector<Vec3> v_free_; // scratch: v_half of nodes_ before constraining
};

} // namespace sphfem
