// Exact sums (solver/core/exact_sum.hpp) against sums known exactly: cancellations that a
// double sum loses, integers on a fixed-point grid summed in 128-bit integers, subnormals and
// the rounding of ties; the same bits in any order, in any grouping (as ranks and threads group
// the terms), and with ±∞ and NaN as a double sum gives them.
#include "solver/core/exact_sum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using sphfem::ExactSum;
__extension__ using Int128 = __int128;

double exact(const std::vector<double>& terms) {
  ExactSum s;
  for (double t : terms)
    s.add(t);
  return s.value();
}

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

TEST(ExactSum, KeepsWhatADoubleSumLoses) {
  EXPECT_EQ(exact({1e100, 1.0, -1e100}), 1.0);
  const double big = std::ldexp(1.0, 53); // 2⁵³ + 1 + 1: a double sum stays at 2⁵³
  EXPECT_EQ(big + 1.0 + 1.0, big);
  EXPECT_EQ(exact({big, 1.0, 1.0}), big + 2.0);
  // 0.1, 0.2 and 0.3 as doubles are 3602879701896397 × 2⁻⁵⁵, 3602879701896397 × 2⁻⁵⁴ and
  // 5404319552844595 × 2⁻⁵⁴: their sum is 2⁻⁵⁵ exactly (a double sum gives 2⁻⁵⁴).
  EXPECT_EQ(exact({0.1, 0.2, -0.3}), std::ldexp(1.0, -55));
  EXPECT_EQ(exact({-0.3, 0.2, 0.1}), std::ldexp(1.0, -55));
  EXPECT_EQ(exact({}), 0.0);
  EXPECT_EQ(exact({-2.5, 0.5}), -2.0);
  EXPECT_EQ(exact({1e-300, -1e-300}), 0.0);
}

TEST(ExactSum, RoundsOnceToTheNearestDoubleTiesToEven) {
  const double big = std::ldexp(1.0, 53);
  EXPECT_EQ(exact({big, 1.0}), big);                             // tie: to even
  EXPECT_EQ(exact({big, 1.0, std::ldexp(1.0, -60)}), big + 2.0); // above the tie
  EXPECT_EQ(exact({big + 2.0, 1.0}), big + 4.0);                 // tie: to even, up
  EXPECT_EQ(exact({big, 1.0, -std::ldexp(1.0, -900)}), big);     // below the tie
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(exact({tiny, tiny, tiny}), 3 * tiny);
  EXPECT_EQ(exact({std::numeric_limits<double>::max(), -tiny}), std::numeric_limits<double>::max());
  EXPECT_EQ(exact({std::numeric_limits<double>::max(), std::numeric_limits<double>::max()}),
            std::numeric_limits<double>::infinity());
}

TEST(ExactSum, EqualsTheIntegerSumOfTermsOnAFixedPointGrid) {
  // Terms m × 2^e with |m| < 2⁴⁰ and e in [−30, 30] are integers on a 2⁻³⁰ grid: their exact
  // sum, in 128-bit integers, rounded once, is the reference.
  std::mt19937_64 random(7);
  std::uniform_int_distribution<long long> mantissa(-(1LL << 40), 1LL << 40);
  std::uniform_int_distribution<int> exponent(-30, 30);
  std::vector<double> terms;
  Int128 reference = 0;
  for (int k = 0; k < 200000; ++k) {
    const long long m = mantissa(random);
    const int e = exponent(random);
    terms.push_back(std::ldexp(static_cast<double>(m), e));
    reference += static_cast<Int128>(m) << (e + 30);
  }
  const double expected = std::ldexp(static_cast<double>(reference), -30);
  const double total = exact(terms);
  EXPECT_EQ(bits(total), bits(expected));
  double naive = 0;
  for (double t : terms)
    naive += t;
  EXPECT_NE(bits(naive), bits(expected)); // the terms are chosen so that order matters

  // Any order, any grouping: shuffled, and cut into "ranks" summed apart, then joined as the
  // ranks join them (limbs added as integers) and as threads do (+=).
  std::shuffle(terms.begin(), terms.end(), random);
  EXPECT_EQ(bits(exact(terms)), bits(expected));
  for (std::size_t parts : {2u, 3u, 7u}) {
    std::vector<ExactSum> part(parts);
    for (std::size_t k = 0; k < terms.size(); ++k)
      part[k % parts].add(terms[k]);
    ExactSum::Limbs limbs{};
    ExactSum joined;
    for (const ExactSum& p : part) {
      const ExactSum::Limbs l = p.limbs();
      for (int j = 0; j < ExactSum::limb_count; ++j)
        limbs[j] += l[j];
      joined += p;
    }
    EXPECT_EQ(bits(ExactSum::of(limbs, 0).value()), bits(expected)) << parts << " ranks";
    EXPECT_EQ(bits(joined.value()), bits(expected)) << parts << " parts";
  }
}

TEST(ExactSum, InParallelIsTheSameForAnyRange) {
  std::mt19937_64 random(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(100000);
  for (double& v : x)
    v = normal(random) * std::pow(10.0, 6 * normal(random));
  const sphfem::ExactSums<2> sums = sphfem::exact_sums<2>(
      sphfem::IndexRange{nullptr, 0, static_cast<sphfem::Index>(x.size())}, [&](sphfem::Index i) {
        return std::array{x[i], -2 * x[i]};
      });
  std::reverse(x.begin(), x.end());
  EXPECT_EQ(bits(sums[0].value()), bits(exact(x)));
  EXPECT_EQ(bits(sums[1].value()), bits(-2 * exact(x))); // ×(−2) is exact
}

TEST(ExactSum, NonFiniteTermsDecideAsInADoubleSum) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(exact({1.0, inf, -5.0}), inf);
  EXPECT_EQ(exact({-inf, 1e300}), -inf);
  EXPECT_TRUE(std::isnan(exact({inf, 1.0, -inf})));
  EXPECT_TRUE(std::isnan(exact({1.0, std::nan(""), 2.0})));
}

} // namespace
