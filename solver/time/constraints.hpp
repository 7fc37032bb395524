// Kinematic boundary conditions on node velocities (METHOD.md §3): fixed (v = 0), prescribed
// velocity components scaled by a time function, and symmetry planes (no velocity along the
// plane normal). Applied to v^{n+½} after the free update; the change they make is a reaction
// force whose work and impulse are returned so energy and momentum balances stay closed.
// Verified by tests/fem/constraints_test.cpp and the plane-wave test.
#pragma once

#include "solver/core/exact_sum.hpp"
#include "solver/core/time_function.hpp"
#include "solver/core/types.hpp"
#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <array>
#include <optional>
#include <span>
#include <vector>

namespace sphfem {

// The work and impulse of reactions or loads over a step, as exact sums (core/exact_sum.hpp):
// the same bits however the nodes or particles are shared among ranks.
struct ReactionTotals {
  ExactSums<4> sums; // work (J), impulse x, y, z (N s)
  void add(double work, const Vec3& impulse) {
    sums[0].add(work);
    for (int d = 0; d < 3; ++d)
      sums[1 + d].add(impulse[d]);
  }
  double work() const { return sums[0].value(); }
  Vec3 impulse() const { return {sums[1].value(), sums[2].value(), sums[3].value()}; }
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
