// The nearest point of a hexahedron's face (solver/coupling/quad_projection): exact on a flat
// face, inside and beyond its edges, and the true minimiser on a warped face (against a brute
// search of the bilinear patch).
#include "solver/coupling/quad_projection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace sphfem;

namespace {

// The unit square z = 0, counter-clockwise seen from +z: outward normal +z.
const std::array<Vec3, 4> square{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};

Vec3 weighted(const std::array<Vec3, 4>& x, const std::array<double, 4>& N) {
  return N[0] * x[0] + N[1] * x[1] + N[2] * x[2] + N[3] * x[3];
}

} // namespace

TEST(QuadProjection, FlatFaceInside) {
  const QuadPoint q = nearest_on_quad(square, Vec3(0.3, 0.6, 0.5));
  EXPECT_TRUE(q.inside);
  EXPECT_NEAR((q.x - Vec3(0.3, 0.6, 0)).norm(), 0, 1e-14);
  EXPECT_NEAR(q.distance, 0.5, 1e-14);
  EXPECT_NEAR((q.normal - Vec3::UnitZ()).norm(), 0, 1e-14);
  // Bilinear weights at ξ = −0.4, η = 0.2: ¼(1 ± ξ)(1 ± η).
  const std::array<double, 4> N{0.28, 0.12, 0.18, 0.42};
  for (int a = 0; a < 4; ++a)
    EXPECT_NEAR(q.N[a], N[a], 1e-14) << a;
  // Below the face the same point, the same normal: the sign is the caller's (s = d · n).
  const QuadPoint below = nearest_on_quad(square, Vec3(0.3, 0.6, -0.2));
  EXPECT_TRUE(below.inside);
  EXPECT_NEAR((below.x - q.x).norm(), 0, 1e-14);
  EXPECT_LT((Vec3(0.3, 0.6, -0.2) - below.x).dot(below.normal), 0);
}

TEST(QuadProjection, BeyondAnEdgeTheNearestPointIsOnIt) {
  const QuadPoint q = nearest_on_quad(square, Vec3(1.5, 0.5, 0.2));
  EXPECT_FALSE(q.inside);
  EXPECT_NEAR((q.x - Vec3(1, 0.5, 0)).norm(), 0, 1e-14);
  EXPECT_NEAR(q.distance, std::sqrt(0.25 + 0.04), 1e-14);
  EXPECT_NEAR(q.N[1], 0.5, 1e-14);
  EXPECT_NEAR(q.N[2], 0.5, 1e-14);
  // Beyond a corner: the corner.
  const QuadPoint corner = nearest_on_quad(square, Vec3(-0.5, -0.5, 0.1));
  EXPECT_NEAR((corner.x - square[0]).norm(), 0, 1e-14);
  EXPECT_NEAR(corner.N[0], 1, 1e-14);
  // Just beyond an edge: on the edge.
  const QuadPoint near_edge = nearest_on_quad(square, Vec3(1 + 0.02, 0.5, -0.1));
  EXPECT_FALSE(near_edge.inside);
  EXPECT_NEAR((near_edge.x - Vec3(1, 0.5, 0)).norm(), 0, 1e-14);
}

TEST(QuadProjection, OrientationGivesTheNormal) {
  const std::array<Vec3, 4> reversed{square[0], square[3], square[2], square[1]};
  EXPECT_NEAR((nearest_on_quad(reversed, Vec3(0.5, 0.5, 1)).normal + Vec3::UnitZ()).norm(), 0,
              1e-14);
}

// A warped (saddle) face: the point found is the nearest of a fine search over the patch.
TEST(QuadProjection, WarpedFaceMatchesABruteSearch) {
  const std::array<Vec3, 4> x{Vec3(0, 0, 0.1), Vec3(1, 0, -0.1), Vec3(1.1, 1, 0.1),
                              Vec3(-0.1, 0.9, -0.1)};
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-0.3, 1.3);
  for (int k = 0; k < 50; ++k) {
    const Vec3 p(u(random), u(random), 0.5 * u(random));
    const QuadPoint q = nearest_on_quad(x, p);
    double best = 1e9;
    constexpr int n = 400;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const double xi = -1 + 2.0 * i / n, eta = -1 + 2.0 * j / n;
        const std::array<double, 4> N{0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta),
                                      0.25 * (1 + xi) * (1 + eta), 0.25 * (1 - xi) * (1 + eta)};
        best = std::min(best, (p - weighted(x, N)).norm());
      }
    // The search's grid resolves distances to ~(2/400)² · curvature; the projection is never
    // farther than that.
    EXPECT_LT(q.distance, best + 1e-4) << "point " << k;
    EXPECT_GT(q.distance, best - 1e-4) << "point " << k;
    EXPECT_NEAR((weighted(x, q.N) - q.x).norm(), 0, 1e-12);
    double sum = 0;
    for (double N : q.N)
      sum += N;
    EXPECT_NEAR(sum, 1, 1e-14);
  }
}

// The contact's signed distance from the unit square (normal +z) and its gradient (the finite
// difference of s): on the face its height; on an edge ± the distance, the side from the
// normals' sum given (the square with a face going down from its edge x = 1: a convex edge;
// going up: a concave one); held by the face's plane beyond the edge, its height again.
TEST(QuadProjection, SignedGapOnTheFaceOnAnEdgeAndHeld) {
  const Vec3 convex = Vec3(1, 0, 1).normalized(), concave = Vec3(-1, 0, 1).normalized();
  const auto gap = [&](const Vec3& x, bool held, bool concave_edge = false) {
    return signed_gap(nearest_on_quad(square, x), x, concave_edge ? concave : convex, held);
  };
  EXPECT_NEAR(gap(Vec3(0.9, 0.5, -0.1), false).s, -0.1, 1e-14);           // on the face
  EXPECT_NEAR(gap(Vec3(1.1, 0.5, 0.1), false).s, std::sqrt(0.02), 1e-14); // round the edge
  EXPECT_NEAR(gap(Vec3(1.1, 0.5, -0.05), false, true).s, -std::sqrt(0.0125), 1e-14);
  EXPECT_NEAR(gap(Vec3(1.1, 0.5, -0.2), true).s, -0.2, 1e-14); // held
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const bool held : {false, true})
    for (const Vec3& x : {Vec3(0.7, 0.4, -0.05), Vec3(1.03, 0.5, -0.08), Vec3(1.2, 0.6, 0.1),
                          Vec3(1.2, 1.3, 0.2), Vec3(1.2, 0.6, -0.1)}) {
      const SignedGap g = gap(x, held);
      const Vec3 direction = Vec3(u(random), u(random), u(random)).normalized();
      constexpr double h = 1e-6;
      const double slope =
          (gap(x + h * direction, held).s - gap(x - h * direction, held).s) / (2 * h);
      EXPECT_NEAR(slope, g.gradient.dot(direction), 1e-8) << x.transpose() << " held " << held;
    }
}
