// The point of a hexahedron's face nearest to a point, for surface contact
// (coupling/surface_contact.hpp, docs/contact.md). The face is the bilinear patch
//   x(ξ, η) = Σ_a N_a x_a,  N_a = ¼ (1 + ξ_a ξ)(1 + η_a η),  (ξ_a, η_a) = (−1,−1), (1,−1), (1,1),
//   (−1,1),
// its nodes ordered so that x_ξ × x_η points out of the body (types.hpp's Quad). Inside the patch
// the nearest point is found by Gauss–Newton on ½|x(ξ, η) − p|² from the centre (exact in one
// iteration on a flat parallelogram). A projection up to quad_edge_tolerance beyond an edge
// (in ξ, η) still counts as inside, at the edge's point: two faces meeting edge on edge, whose
// nodes coincide up to rounding, then see each other's edge nodes (without it the corner nodes
// of two bars struck end on end pass through each other). Further out the nearest point lies on
// one of the four straight edges and is found exactly there.
// Verified by tests/coupling/quad_projection_test.cpp.
#pragma once

#include "solver/core/types.hpp"

#include <array>

namespace sphfem {

inline constexpr double quad_edge_tolerance = 0.05;

struct QuadPoint {
  Vec3 x = Vec3::Zero();      // the nearest point, m
  std::array<double, 4> N{};  // its shape-function weights (sum 1, each in [0, 1])
  Vec3 normal = Vec3::Zero(); // unit outward normal of the patch there
  double distance = 0;        // |p − x|, m
  bool inside = false; // projects onto the patch (within the tolerance); else nearest on an edge
};

QuadPoint nearest_on_quad(const std::array<Vec3, 4>& corners, const Vec3& p);

} // namespace sphfem
