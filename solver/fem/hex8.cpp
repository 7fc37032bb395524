#include "solver/fem/hex8.hpp"

#include <algorithm>
#include <cmath>

namespace sphfem {

namespace {

// Natural coordinates of the nodes in gmsh order.
constexpr std::array<std::array<double, 3>, 8> node_sign{{
    {-1, -1, -1},
    {1, -1, -1},
    {1, 1, -1},
    {-1, 1, -1},
    {-1, -1, 1},
    {1, -1, 1},
    {1, 1, 1},
    {-1, 1, 1},
}};

// Faces of the hexahedron (node indices), for their areas.
constexpr std::array<std::array<int, 4>, 6> faces{{
    {0, 3, 2, 1},
    {4, 5, 6, 7},
    {0, 1, 5, 4},
    {1, 2, 6, 5},
    {2, 3, 7, 6},
    {0, 4, 7, 3},
}};

} // namespace

// x(ξ, η, ζ) = a0 + a1 ξ + a2 η + a3 ζ + a4 ξη + a5 ηζ + a6 ζξ + a7 ξηζ with
// a_m = ⅛ Σ_I s_mI x_I. Integrating det[x_ξ, x_η, x_ζ] over the cube exactly leaves
//   V = 8 [a1·(a2×a3) + ⅓ (a1·(a4×a6) + a4·(a2×a5) + a6·(a5×a3))]   (a7 drops out),
// so b_I = ∂V/∂x_I = Σ_m s_mI G_m with G_m = ⅛ ∂V/∂a_m. About 400 flops per element.
Hex8Gradient hex8_gradient(const HexPoints& x) {
  std::array<Vec3, 6> a; // a1 … a6 of the comment, a[m − 1]
  for (auto& am : a)
    am.setZero();
  for (int I = 0; I < 8; ++I) {
    const auto& s = node_sign[I];
    const double sign[6] = {s[0], s[1], s[2], s[0] * s[1], s[1] * s[2], s[2] * s[0]};
    for (int m = 0; m < 6; ++m)
      a[m] += sign[m] * x[I];
  }
  for (auto& am : a)
    am /= 8.0;
  const Vec3 &a1 = a[0], &a2 = a[1], &a3 = a[2], &a4 = a[3], &a5 = a[4], &a6 = a[5];
  constexpr double third = 1.0 / 3.0;
  const Vec3 a2a3 = a2.cross(a3), a4a6 = a4.cross(a6), a2a5 = a2.cross(a5), a5a3 = a5.cross(a3);
  const std::array<Vec3, 6> G{
      a2a3 + third * a4a6,
      a3.cross(a1) + third * a5.cross(a4),
      a1.cross(a2) + third * a6.cross(a5),
      third * (a6.cross(a1) + a2a5),
      third * (a4.cross(a2) + a3.cross(a6)),
      third * (a1.cross(a4) + a5a3),
  };
  Hex8Gradient out;
  out.volume = 8.0 * (a1.dot(a2a3) + third * (a1.dot(a4a6) + a4.dot(a2a5) + a6.dot(a5a3)));
  for (int I = 0; I < 8; ++I) {
    const auto& s = node_sign[I];
    out.b[I] = s[0] * G[0] + s[1] * G[1] + s[2] * G[2] + (s[0] * s[1]) * G[3] +
               (s[1] * s[2]) * G[4] + (s[2] * s[0]) * G[5];
  }
  return out;
}

Mat3 hex8_velocity_gradient(const Hex8Gradient& g, const HexPoints& v) {
  Mat3 L = Mat3::Zero();
  for (int I = 0; I < 8; ++I)
    L += v[I] * g.b[I].transpose();
  return L / g.volume;
}

std::array<std::array<double, 8>, 4> hex8_hourglass_shape(const HexPoints& x,
                                                          const Hex8Gradient& g) {
  std::array<std::array<double, 8>, 4> gamma;
  for (int a = 0; a < 4; ++a) {
    Vec3 h = Vec3::Zero();
    for (int J = 0; J < 8; ++J)
      h += hourglass_base[a][J] * x[J];
    for (int I = 0; I < 8; ++I)
      gamma[a][I] = hourglass_base[a][I] - h.dot(g.b[I]) / g.volume;
  }
  return gamma;
}

double hex8_characteristic_length(const HexPoints& x, double volume) {
  double largest = 0;
  for (const auto& f : faces) {
    const Vec3 area = 0.5 * (x[f[2]] - x[f[0]]).cross(x[f[3]] - x[f[1]]);
    largest = std::max(largest, area.norm());
  }
  return volume / largest;
}

} // namespace sphfem
