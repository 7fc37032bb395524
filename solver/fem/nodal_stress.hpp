// Nodal stress as the volume-weighted average of the adjacent elements' stress
// σ = S − p I (bulk viscosity excluded, as explicit codes report it). Used for probes and
// point output, and for background particles (METHOD.md §4.1). Eroded elements are gone.
#pragma once

#include "solver/fem/node_gather.hpp"
#include "solver/state/hex_elements.hpp"

#include <cmath>

namespace sphfem {

inline Mat3 nodal_stress(const HexElements& e, const NodeGather& around, Index node) {
  Mat3 sum = Mat3::Zero();
  double volume = 0;
  for (Index entry : around.around(node)) {
    const Index k = entry / 8, s = e.slot(k);
    if (e.eroded_e[k])
      continue;
    sum += e.V_e[s] * (e.S_e[s] - e.p_e[s] * Mat3::Identity());
    volume += e.V_e[s];
  }
  return volume > 0 ? Mat3(sum / volume) : Mat3(Mat3::Zero());
}

// √(3/2 S:S) of the deviator of σ, Pa.
inline double von_mises(const Mat3& sigma) {
  const Mat3 S = sigma - (sigma.trace() / 3.0) * Mat3::Identity();
  return std::sqrt(1.5 * S.cwiseProduct(S).sum());
}

} // namespace sphfem
