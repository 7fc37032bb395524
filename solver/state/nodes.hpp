// FE nodes as a struct of arrays (STYLE.md B): reference and current positions, half-step
// velocities, lumped masses and the force buffers of one step.
#pragma once

#include "solver/core/types.hpp"

#include <vector>

namespace sphfem {

struct Nodes {
  std::vector<Vec3> x0_n;    // reference position, m
  std::vector<Vec3> x_n;     // current position x^n, m
  std::vector<Vec3> v_n;     // velocity v^{n−½} (after a step: v^{n+½}), m/s
  std::vector<double> m_n;   // lumped mass, kg
  std::vector<int> body_n;   // body id
  std::vector<Vec3> f_int_n; // force from the elements on the node, N
  std::vector<Vec3> f_ext_n; // applied external force (pressure loads), N

  Index size() const { return static_cast<Index>(x_n.size()); }
  // Visits every per-node array with its name (checkpoint).
  template <class Visit> void for_each_field(Visit visit) {
    visit("x0_n", x0_n), visit("x_n", x_n), visit("v_n", v_n), visit("m_n", m_n);
    visit("body_n", body_n), visit("f_int_n", f_int_n), visit("f_ext_n", f_ext_n);
  }
};

} // namespace sphfem
