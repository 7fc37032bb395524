// Deterministic parallel sums: the range is cut into a fixed number of blocks that do not
// depend on the thread count, each block is summed in order, then the blocks in order. So a
// total is bit-identical for any number of threads (DESIGN.md: determinism).
#pragma once

#include "solver/core/types.hpp"

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
