// Unit tests of the cubic B-spline kernel (solver/sph/kernel.hpp): normalisation, the
// derivative against finite differences, and the lattice sums SPH relies on.
#include "solver/sph/kernel.hpp"

#include "solver/core/types.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sphfem;

TEST(Kernel, IntegratesToOne) {
  // ∫ W dV = ∫₀^{2h} 4π r² W dr, by Simpson's rule on 2000 intervals (error ≪ 1e-8).
  const double h = 0.7;
  const int n = 2000;
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    const double r = 2 * h * k / n;
    const double weight = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
    sum += weight * 4 * M_PI * r * r * kernel_W(r, h);
  }
  EXPECT_NEAR(sum * (2 * h / n) / 3, 1.0, 1e-8);
}

TEST(Kernel, DerivativeMatchesFiniteDifference) {
  const double h = 1e-3;
  for (double q : {0.1, 0.5, 0.99, 1.01, 1.5, 1.9}) {
    const double r = q * h, d = 1e-9 * h;
    const double fd = (kernel_W(r + d, h) - kernel_W(r - d, h)) / (2 * d);
    EXPECT_NEAR(kernel_dW(r, h), fd, 1e-6 * std::abs(fd)) << "q = " << q;
  }
  EXPECT_EQ(kernel_W(2.0 * h, h), 0.0);
  EXPECT_EQ(kernel_dW(2.5 * h, h), 0.0);
}

TEST(Kernel, LatticeSumsAwayFromBoundaries) {
  // On a cubic lattice (spacing Δp, h = 1.2 Δp) at an interior particle: Σ V W ≈ 1
  // (partition of unity), Σ V ∇W = 0 (symmetry, exactly up to round-off) and
  // Σ V (x_j − x_i) ⊗ ∇_i W ≈ I (first-order consistency). Tolerances: the sums of a 2.4 Δp
  // support on a lattice differ from the integrals by a few per cent (measured 1.2% and 2.7%).
  const double dp = 1e-3, h = 1.2 * dp, V = dp * dp * dp;
  double unity = 0;
  Vec3 gradient = Vec3::Zero();
  Mat3 M = Mat3::Zero();
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) {
        const Vec3 x_ij = -dp * Vec3(i, j, k); // x_i = 0
        const double r = x_ij.norm();
        unity += V * kernel_W(r, h);
        if (r == 0)
          continue;
        const Vec3 grad = (kernel_dW(r, h) / r) * x_ij;
        gradient += V * grad;
        M -= V * x_ij * grad.transpose();
      }
  EXPECT_NEAR(unity, 1.0, 0.03);
  EXPECT_LT(gradient.norm() * dp, 1e-14);
  EXPECT_LT((M - Mat3::Identity()).norm(), 0.05);
}
