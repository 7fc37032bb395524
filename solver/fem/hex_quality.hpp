// Mesh quality of 8-node hexahedra, as meshers report it: the scaled Jacobian at a corner is the
// triple product of its three edges (along +ξ, +η, +ζ) divided by their lengths — 1 for a right
// angle in every pair, 0 for a flat corner, negative for an inverted one; an element's is the
// least of its 8 corners. The characteristic length L_e = V / (largest face area) sets the
// element's stable step L_e / c (METHOD.md §7). Node order: gmsh hexahedron.
// Verified by tests/fem/hex_quality_test.cpp.
#pragma once

#include "solver/fem/hex8.hpp"
#include "solver/state/model.hpp"

namespace sphfem {

// The least scaled corner Jacobian of one hexahedron (1 for a box, ≤ 0 if inverted).
double hex8_scaled_jacobian(const HexPoints& x);

// The worst elements of a body: the least scaled Jacobian and the shortest characteristic
// length, each with the element index and its centroid, m.
struct HexQuality {
  long long elements = 0;
  double scaled_jacobian = 1;
  Index worst_jacobian = -1;
  Vec3 worst_jacobian_at = Vec3::Zero();
  double length = 0; // L_e, m
  Index shortest = -1;
  Vec3 shortest_at = Vec3::Zero();
};

// Over the model's hexahedra of body `body` (all bodies when body < 0).
HexQuality hex_quality(const Model& m, int body = -1);

} // namespace sphfem
