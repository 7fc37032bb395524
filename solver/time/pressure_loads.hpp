// Pressure loads on named faces (follower loads on the current geometry): each quadrilateral
// takes −p(t) A⃗/4 on each of its nodes, A⃗ = ½ d₁ × d₂ its outward area vector from the
// diagonals. Positive pressure pushes into the body. Verified by the plane-wave test.
#pragma once

#include "solver/core/time_function.hpp"
#include "solver/core/types.hpp"
#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <vector>

namespace sphfem {

class PressureLoads {
public:
  PressureLoads() = default;
  PressureLoads(const Case& c, const Model& model);

  // Sets f_ext on the loaded nodes to the loads at time t on geometry x (others untouched).
  void apply(double t, const std::vector<Vec3>& x, std::vector<Vec3>& f_ext) const;
  bool empty() const { return loads_.empty(); }

private:
  struct Load {
    std::vector<Quad> faces;
    double pressure;
    TimeFunction function;
  };
  std::vector<Load> loads_;
  std::vector<Index> loaded_nodes_;
};

} // namespace sphfem
