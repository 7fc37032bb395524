// The ranks of a distributed run (issue 28) and the few collective operations the step needs:
// the least of a value (the stable step: exact in any order), sums in rank order (so that a run
// repeats bit for bit at a given rank count), exact sums (the same at any rank count), a vote
// (stop, checkpoint) and an abort that ends every rank when one fails mid-run. Without MPI, or not
// started by a launcher, this process is rank 0 of 1 and each operation returns its own argument.
#pragma once

#include "solver/core/exact_sum.hpp"
#include "solver/core/types.hpp"

#include <span>
#include <vector>

namespace sphfem::ranks {

int rank();
int size();
inline bool distributed() {
  return size() > 1;
}

// The least of `value` over the ranks.
double min(double value);
// The largest of `value` over the ranks.
int max(int value);
double max(double value);
// Element-wise sums over the ranks, added in rank order (0, 1, …): the same on every rank and on
// every repeat.
std::vector<double> sum_in_rank_order(std::span<const double> values);
// Exact sums over the ranks (solver/core/exact_sum.hpp): each of `sums` becomes the total of
// every rank's, the same bits as one process summing all the terms, in any order.
void sum_exactly(std::span<ExactSum> sums);
// Every rank's `values` (each the same length), concatenated in rank order.
std::vector<double> gather_all(std::span<const double> values);
// Every rank's `values` (of any length), concatenated in rank order.
std::vector<Index> gather_all_varying(std::span<const Index> values);
// Waits for every rank.
void barrier();
// Ends every rank of the job with `code` (after an error one rank met alone mid-run: the others
// would wait for it forever).
[[noreturn]] void abort(int code);

} // namespace sphfem::ranks
