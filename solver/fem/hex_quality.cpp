// Scaled Jacobians and characteristic lengths of hexahedra (see the header).
#include "solver/fem/hex_quality.hpp"

#include <algorithm>

namespace sphfem {

double hex8_scaled_jacobian(const HexPoints& x) {
  // At corner i its neighbours along ξ, η and ζ, and the signs that turn the edges to +ξ, +η.
  static constexpr int xi_neighbour[8] = {1, 0, 3, 2, 5, 4, 7, 6};
  static constexpr int eta_neighbour[8] = {3, 2, 1, 0, 7, 6, 5, 4};
  static constexpr int xi_sign[8] = {1, -1, -1, 1, 1, -1, -1, 1};
  static constexpr int eta_sign[8] = {1, 1, -1, -1, 1, 1, -1, -1};
  double least = 1;
  for (int i = 0; i < 8; ++i) {
    const Vec3 a = xi_sign[i] * (x[xi_neighbour[i]] - x[i]);
    const Vec3 b = eta_sign[i] * (x[eta_neighbour[i]] - x[i]);
    const Vec3 c = (i < 4 ? 1 : -1) * (x[i ^ 4] - x[i]);
    const double lengths = a.norm() * b.norm() * c.norm();
    least = std::min(least, lengths > 0 ? a.dot(b.cross(c)) / lengths : 0.0);
  }
  return least;
}

HexQuality hex_quality(const Model& m, int body) {
  HexQuality q;
  bool first = true;
  for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
    if (body >= 0 && m.body_e[e] != body)
      continue;
    HexPoints x;
    Vec3 centroid = Vec3::Zero();
    for (int a = 0; a < 8; ++a) {
      x[a] = m.x_n[static_cast<std::size_t>(m.hex_e[e][a])];
      centroid += x[a] / 8;
    }
    const double jacobian = hex8_scaled_jacobian(x);
    const double length = hex8_characteristic_length(x, hex8_gradient(x).volume);
    ++q.elements;
    if (first || jacobian < q.scaled_jacobian) {
      q.scaled_jacobian = jacobian;
      q.worst_jacobian = static_cast<Index>(e);
      q.worst_jacobian_at = centroid;
    }
    if (first || length < q.length) {
      q.length = length;
      q.shortest = static_cast<Index>(e);
      q.shortest_at = centroid;
    }
    first = false;
  }
  return q;
}

} // namespace sphfem
