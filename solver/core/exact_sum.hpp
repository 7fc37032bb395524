// Exact sums of doubles: each term is added without rounding into an integer accumulator that
// spans the whole range of doubles (a "superaccumulator": 67 limbs of 32 bits, carries held in
// 64-bit integers), and the total is rounded to a double once, when read. So a sum is the same
// bits in any order of its terms — over any number of threads, and over any number of ranks,
// whose accumulators add as integers. The balances and the bodies' sums of the history are
// taken this way (solver/time/simulation.cpp): a run of N ranks sums its own entities and
// repeats the single process's history bit for bit without gathering the state (issue 28,
// point 4). Verified by tests/core/exact_sum_test.cpp.
#pragma once

#include "solver/core/parallel.hpp"
#include "solver/core/types.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace sphfem {

__extension__ using Uint128 = unsigned __int128; // GCC's and Clang's; ISO C++ has none

class ExactSum {
public:
  static constexpr int limb_bits = 32;
  // Bit 0 of limb 0 is worth 2⁻¹⁰⁷⁴ (the least subnormal); a term's 53 bits shifted by up to
  // 31 span three limbs, the largest double's reach limb 65, and limb 66 takes the carries.
  static constexpr int limb_count = 67;
  using Limbs = std::array<std::int64_t, limb_count>;

  void add(double x) {
    if (x == 0)
      return;
    if (!std::isfinite(x)) {
      special_ += x; // ±∞ and NaN decide the total as in any order of addition
      return;
    }
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const int exponent = static_cast<int>((bits >> 52) & 0x7ff);
    std::uint64_t mantissa = bits & ((std::uint64_t(1) << 52) - 1);
    if (exponent != 0)
      mantissa |= std::uint64_t(1) << 52;
    // x = mantissa × 2^(position − 1074), position ∈ [0, 2045]
    const int position = exponent == 0 ? 0 : exponent - 1;
    const int limb = position / limb_bits;
    const Uint128 shifted = static_cast<Uint128>(mantissa) << (position % limb_bits);
    const auto low = static_cast<std::int64_t>(shifted & 0xffffffffu);
    const auto mid = static_cast<std::int64_t>((shifted >> 32) & 0xffffffffu);
    const auto high = static_cast<std::int64_t>(shifted >> 64);
    if (bits >> 63) {
      limbs_[limb] -= low, limbs_[limb + 1] -= mid, limbs_[limb + 2] -= high;
    } else {
      limbs_[limb] += low, limbs_[limb + 1] += mid, limbs_[limb + 2] += high;
    }
    if (++pending_ == max_pending)
      propagate();
  }

  ExactSum& operator+=(ExactSum other) {
    other.propagate();
    propagate();
    for (int k = 0; k < limb_count; ++k)
      limbs_[k] += other.limbs_[k];
    special_ += other.special_;
    pending_ = 2;
    return *this;
  }

  // The total rounded to the nearest double (ties to even; ±∞ beyond the range).
  double value() const;

  // For a sum over ranks: the limbs with their carries propagated (each of limbs 0–65 in
  // [0, 2³²), the sign in limb 66) and the non-finite terms' sum. The limbs of several sums add
  // exactly as integers; of() makes a sum of such a total.
  Limbs limbs() const {
    ExactSum copy = *this;
    copy.propagate();
    return copy.limbs_;
  }
  double special() const { return special_; }
  static ExactSum of(const Limbs& limbs, double special) {
    ExactSum s;
    s.limbs_ = limbs;
    s.special_ = special;
    s.propagate();
    return s;
  }

private:
  // Adds between carry propagations: each changes a limb by less than 2³², so a limb stays
  // below 2⁶² in magnitude.
  static constexpr std::int32_t max_pending = 1 << 29;

  void propagate() {
    for (int k = 0; k + 1 < limb_count; ++k) {
      const std::int64_t carry = limbs_[k] >> limb_bits; // floor: limbs_[k] − carry·2³² ∈ [0, 2³²)
      limbs_[k] -= carry * (std::int64_t(1) << limb_bits);
      limbs_[k + 1] += carry;
    }
    pending_ = 0;
  }

  Limbs limbs_{};
  double special_ = 0;
  std::int32_t pending_ = 0;
};

template <std::size_t K> using ExactSums = std::array<ExactSum, K>;

template <std::size_t K> void add_to(ExactSums<K>& total, const ExactSums<K>& part) {
  for (std::size_t j = 0; j < K; ++j)
    total[j] += part[j];
}

// Σ term(range[k]) over the range, K sums at once (term returns std::array<double, K>), exactly,
// in parallel: the same bits for any number of threads.
template <std::size_t K, class Term> ExactSums<K> exact_sums(IndexRange range, Term term) {
  ExactSums<K> total;
#pragma omp parallel if (range.count > parallel_min_items)
  {
    ExactSums<K> mine;
#pragma omp for schedule(static) nowait
    for (Index k = 0; k < range.count; ++k) {
      const std::array<double, K> terms = term(range[k]);
      for (std::size_t j = 0; j < K; ++j)
        mine[j].add(terms[j]);
    }
#pragma omp critical(sphfem_exact_sums)
    for (std::size_t j = 0; j < K; ++j)
      total[j] += mine[j];
  }
  return total;
}

} // namespace sphfem
