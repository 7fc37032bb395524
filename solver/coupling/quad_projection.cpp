#include "solver/coupling/quad_projection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphfem {
namespace {

constexpr double xi_a[4] = {-1, 1, 1, -1};
constexpr double eta_a[4] = {-1, -1, 1, 1};

std::array<double, 4> weights(double xi, double eta) {
  std::array<double, 4> N{};
  for (int a = 0; a < 4; ++a)
    N[a] = 0.25 * (1 + xi_a[a] * xi) * (1 + eta_a[a] * eta);
  return N;
}

Vec3 at(const std::array<Vec3, 4>& x, const std::array<double, 4>& N) {
  return N[0] * x[0] + N[1] * x[1] + N[2] * x[2] + N[3] * x[3];
}

// Tangents x_ξ, x_η of the patch at (ξ, η).
std::array<Vec3, 2> tangents(const std::array<Vec3, 4>& x, double xi, double eta) {
  Vec3 t_xi = Vec3::Zero(), t_eta = Vec3::Zero();
  for (int a = 0; a < 4; ++a) {
    t_xi += (0.25 * xi_a[a] * (1 + eta_a[a] * eta)) * x[a];
    t_eta += (0.25 * eta_a[a] * (1 + xi_a[a] * xi)) * x[a];
  }
  return {t_xi, t_eta};
}

Vec3 unit_normal(const std::array<Vec3, 4>& x, double xi, double eta) {
  const auto [t_xi, t_eta] = tangents(x, xi, eta);
  const Vec3 n = t_xi.cross(t_eta);
  const double length = n.norm();
  return length > 0 ? Vec3(n / length) : Vec3(Vec3::Zero());
}

} // namespace

QuadPoint nearest_on_quad(const std::array<Vec3, 4>& x, const Vec3& p) {
  // Gauss–Newton from the centre: (JᵀJ) Δ = Jᵀ (p − x(ξ, η)), J = [x_ξ x_η].
  double xi = 0, eta = 0;
  for (int iteration = 0; iteration < 4; ++iteration) {
    const auto [t_xi, t_eta] = tangents(x, xi, eta);
    const Vec3 r = p - at(x, weights(xi, eta));
    const double a = t_xi.squaredNorm(), b = t_xi.dot(t_eta), c = t_eta.squaredNorm();
    const double det = a * c - b * b;
    if (!(det > 0))
      break;
    const double g_xi = t_xi.dot(r), g_eta = t_eta.dot(r);
    const double d_xi = (c * g_xi - b * g_eta) / det, d_eta = (a * g_eta - b * g_xi) / det;
    xi += d_xi;
    eta += d_eta;
    if (std::abs(d_xi) + std::abs(d_eta) < 1e-12 || std::abs(xi) > 2 || std::abs(eta) > 2)
      break;
  }
  QuadPoint out;
  if (std::abs(xi) <= 1 && std::abs(eta) <= 1) {
    out.N = weights(xi, eta);
    out.x = at(x, out.N);
    out.inside = true;
  } else {
    // The nearest point of the four straight edges a → a + 1.
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 4; ++a) {
      const int b = (a + 1) % 4;
      const Vec3 edge = x[b] - x[a];
      const double length2 = edge.squaredNorm();
      const double t = length2 > 0 ? std::clamp((p - x[a]).dot(edge) / length2, 0.0, 1.0) : 0.0;
      const Vec3 q = x[a] + t * edge;
      const double d2 = (p - q).squaredNorm();
      if (d2 < best) {
        best = d2;
        out.x = q;
        out.N = {};
        out.N[a] = 1 - t;
        out.N[b] = t;
        xi = (1 - t) * xi_a[a] + t * xi_a[b];
        eta = (1 - t) * eta_a[a] + t * eta_a[b];
      }
    }
  }
  out.normal = unit_normal(x, xi, eta);
  out.distance = (p - out.x).norm();
  return out;
}

} // namespace sphfem
