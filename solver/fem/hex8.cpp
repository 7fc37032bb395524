#include "solver/fem/hex8.hpp"

#include <algorithm>
#include <cmath>

namespace sphfem {

namespace {

// Natural coordinates of the nodes in gmsh order.
constexpr std::array<std::array<double, 3>, 8> node_sign{{
    {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
    {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1},
}};

// Shape-function derivatives ∂N_I/∂ξ_k at the eight 2×2×2 Gauss points, built once.
struct GaussDerivatives {
  std::array<std::array<Vec3, 8>, 8> dN; // [gauss point][node]
  GaussDerivatives() {
    const double g = 1.0 / std::sqrt(3.0);
    for (int p = 0; p < 8; ++p) {
      const double xi[3] = {node_sign[p][0] * g, node_sign[p][1] * g, node_sign[p][2] * g};
      for (int I = 0; I < 8; ++I) {
        const auto& s = node_sign[I];
        const double f0 = 1 + s[0] * xi[0], f1 = 1 + s[1] * xi[1], f2 = 1 + s[2] * xi[2];
        dN[p][I] = Vec3(s[0] * f1 * f2, f0 * s[1] * f2, f0 * f1 * s[2]) / 8.0;
      }
    }
  }
};

const GaussDerivatives& gauss() {
  static const GaussDerivatives derivatives;
  return derivatives;
}

// Faces of the hexahedron (node indices), for their areas.
constexpr std::array<std::array<int, 4>, 6> faces{{
    {0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {0, 4, 7, 3},
}};

} // namespace

Hex8Gradient hex8_gradient(const HexPoints& x) {
  Hex8Gradient out;
  for (auto& b : out.b)
    b.setZero();
  for (int p = 0; p < 8; ++p) {
    const auto& dN = gauss().dN[p];
    Mat3 J = Mat3::Zero(); // row k: ∂x/∂ξ_k
    for (int I = 0; I < 8; ++I)
      J += dN[I] * x[I].transpose();
    // adj(J) = det(J) J⁻¹ has columns r1×r2, r2×r0, r0×r1 (r_k the rows of J), so
    // Σ_p adj(J) ∂N/∂ξ = ∫ ∂N/∂x dV with unit Gauss weights.
    const Vec3 r0 = J.row(0), r1 = J.row(1), r2 = J.row(2);
    Mat3 adj;
    adj.col(0) = r1.cross(r2);
    adj.col(1) = r2.cross(r0);
    adj.col(2) = r0.cross(r1);
    out.volume += r0.dot(adj.col(0));
    for (int I = 0; I < 8; ++I)
      out.b[I] += adj * dN[I];
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
