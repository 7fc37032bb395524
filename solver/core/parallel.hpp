// Deterministic parallel sums: the range is cut into a fixed number of blocks that do not
// depend on the thread count, each block is summed in order, then the blocks in order. So a
// total is bit-identical for any number of threads (DESIGN.md: determinism). And IndexRange:
// the indices a loop visits, all or a distributed run's share.
#pragma once

#include "solver/core/types.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace sphfem {

// Loops shorter than this run on one thread: forking costs more than the work saved.
inline constexpr Index parallel_min_items = 4096;

// Chunk of a static schedule over items whose cost varies along the range (plastic against
// elastic elements, particles in the impact zone against those far from it, background rows):
// chunks dealt round-robin keep both threads busy where one contiguous half each would leave
// one waiting. The split is static, so it does not depend on timing; each item writes only its
// own results, so the results do not depend on the split.
inline constexpr Index interleave_chunk = 16;

// The indices of [begin, end) a loop visits: all of them (only == null), or those of `only`
// (ascending) in that range — a distributed run's share (solver/parallel/). The k-th visited
// index is range[k], k < count.
struct IndexRange {
  const Index* list = nullptr; // null: begin + k
  Index begin = 0, count = 0;
  Index operator[](Index k) const { return list != nullptr ? list[k] : begin + k; }
  static IndexRange of(const std::vector<Index>* only, Index begin, Index end) {
    if (only == nullptr)
      return {nullptr, begin, end - begin};
    const auto lo = std::lower_bound(only->begin(), only->end(), begin);
    const auto hi = std::lower_bound(lo, only->end(), end);
    return {only->data() + (lo - only->begin()), 0, static_cast<Index>(hi - lo)};
  }
  static IndexRange of(const std::vector<Index>* only, Index n) { return of(only, 0, n); }
};

template <class T, class Term> T deterministic_sum(Index n, T zero, Term term) {
  constexpr Index blocks = 64;
  std::array<T, blocks> partial;
  partial.fill(zero);
#pragma omp parallel for schedule(static) if (n > parallel_min_items)
  for (Index b = 0; b < blocks; ++b) {
    const Index begin = static_cast<Index>(static_cast<long long>(n) * b / blocks);
    const Index end = static_cast<Index>(static_cast<long long>(n) * (b + 1) / blocks);
    T sum = zero;
    for (Index i = begin; i < end; ++i)
      sum += term(i);
    partial[b] = sum;
  }
  T total = zero;
  for (const T& p : partial)
    total += p;
  return total;
}

} // namespace sphfem
