// The point of a hexahedron's face nearest to a point, for surface contact
// (coupling/surface_contact.hpp, docs/contact.md). The face is the bilinear patch
//   x(ξ, η) = Σ_a N_a x_a,  N_a = ¼ (1 + ξ_a ξ)(1 + η_a η),  (ξ_a, η_a) = (−1,−1), (1,−1), (1,1),
//   (−1,1),
// its nodes ordered so that x_ξ × x_η points out of the body (types.hpp's Quad). Inside the patch
// the nearest point is found by Gauss–Newton on ½|x(ξ, η) − p|² from the centre (exact in one
// iteration on a flat parallelogram). Beyond the patch the nearest point lies on one of the four
// straight edges and is found exactly there.
// signed_gap turns the nearest point into the contact's signed distance (surface_contact.hpp).
// Verified by tests/coupling/quad_projection_test.cpp.
#pragma once

#include "solver/core/types.hpp"

#include <array>

namespace sphfem {

struct QuadPoint {
  Vec3 x = Vec3::Zero();      // the nearest point, m
  std::array<double, 4> N{};  // its shape-function weights (sum 1, each in [0, 1])
  Vec3 normal = Vec3::Zero(); // unit outward normal of the patch there
  double distance = 0;        // |p − x|, m
  bool inside = false;        // projects onto the patch; else nearest on an edge
};

QuadPoint nearest_on_quad(const std::array<Vec3, 4>& corners, const Vec3& p);

// The signed distance s of a slave x from the other body's surface (negative inside the body)
// and its gradient ∇s, given the surface's nearest point q (surface_contact.hpp chooses it):
// - q inside a face: s = d · n, ∇s = n (d = x − q, n the face's normal there);
// - q on an edge or a corner: s = ±|d|, ∇s = d / s, the side given by `outward`, the sum of the
//   normals of the faces that share the point (negative where d · outward < 0) — the true
//   signed distance, continuous from face to face and round convex and concave edges alike;
// - `held`: the face's plane goes on beyond its edge, s = d · n, ∇s = n (a node meeting a body
//   edge on edge, whose side face beyond that edge it does not see).
struct SignedGap {
  double s = 0;
  Vec3 gradient = Vec3::Zero();
};
inline SignedGap signed_gap(const QuadPoint& q, const Vec3& x, const Vec3& outward, bool held) {
  const Vec3 d = x - q.x;
  if (q.inside || held || q.distance == 0)
    return {d.dot(q.normal), q.normal};
  const double s = d.dot(outward) < 0 ? -q.distance : q.distance;
  return {s, d / s};
}

} // namespace sphfem
