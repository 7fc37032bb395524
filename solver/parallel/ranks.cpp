#include "solver/parallel/ranks.hpp"

#include <algorithm>
#include <cstdlib>

#ifdef SPHFEM_HAVE_MPI
#include <mpi.h>
#endif

namespace sphfem::ranks {

#ifdef SPHFEM_HAVE_MPI

namespace {

bool started() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  return initialised && !finalised;
}

} // namespace

int rank() {
  int r = 0;
  if (started())
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int size() {
  int n = 1;
  if (started())
    MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

double min(double value) {
  if (size() > 1)
    MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return value;
}

int max(int value) {
  if (size() > 1)
    MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

double max(double value) {
  if (size() > 1)
    MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

std::vector<double> sum_in_rank_order(std::span<const double> values) {
  const int n = size();
  std::vector<double> out(values.begin(), values.end());
  if (n == 1 || values.empty())
    return out;
  const int count = static_cast<int>(values.size());
  const std::vector<double> all = gather_all(values);
  for (int k = 0; k < count; ++k) {
    double sum = all[k];
    for (int r = 1; r < n; ++r)
      sum += all[static_cast<std::size_t>(r) * count + k];
    out[k] = sum;
  }
  return out;
}

std::vector<double> gather_all(std::span<const double> values) {
  const int n = size();
  if (n == 1)
    return {values.begin(), values.end()};
  const int count = static_cast<int>(values.size());
  std::vector<double> all(static_cast<std::size_t>(count) * n);
  MPI_Allgather(values.data(), count, MPI_DOUBLE, all.data(), count, MPI_DOUBLE, MPI_COMM_WORLD);
  return all;
}

std::vector<Index> gather_all_varying(std::span<const Index> values) {
  const int n = size();
  if (n == 1)
    return {values.begin(), values.end()};
  const int count = static_cast<int>(values.size());
  std::vector<int> counts(n), at(n, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int r = 1; r < n; ++r)
    at[r] = at[r - 1] + counts[r - 1];
  std::vector<Index> all(static_cast<std::size_t>(at[n - 1] + counts[n - 1]));
  const MPI_Datatype type = sizeof(Index) == 8 ? MPI_INT64_T : MPI_INT32_T;
  MPI_Allgatherv(values.data(), count, type, all.data(), counts.data(), at.data(), type,
                 MPI_COMM_WORLD);
  return all;
}

void sum_exactly(std::span<ExactSum> sums) {
  if (size() == 1 || sums.empty())
    return;
  constexpr int n = ExactSum::limb_count;
  std::vector<long long> limbs(sums.size() * n);
  std::vector<double> special(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) {
    const ExactSum::Limbs l = sums[k].limbs();
    std::copy(l.begin(), l.end(), limbs.begin() + static_cast<std::ptrdiff_t>(k * n));
    special[k] = sums[k].special();
  }
  // Integer sums: exact and the same in any grouping of the ranks.
  MPI_Allreduce(MPI_IN_PLACE, limbs.data(), static_cast<int>(limbs.size()), MPI_LONG_LONG, MPI_SUM,
                MPI_COMM_WORLD);
  special = sum_in_rank_order(special); // ±∞, NaN or 0: the same in any order
  for (std::size_t k = 0; k < sums.size(); ++k) {
    ExactSum::Limbs l;
    std::copy_n(limbs.begin() + static_cast<std::ptrdiff_t>(k * n), n, l.begin());
    sums[k] = ExactSum::of(l, special[k]);
  }
}

void barrier() {
  if (size() > 1)
    MPI_Barrier(MPI_COMM_WORLD);
}

void abort(int code) {
  if (started())
    MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else

int rank() {
  return 0;
}
int size() {
  return 1;
}
double min(double value) {
  return value;
}
int max(int value) {
  return value;
}
double max(double value) {
  return value;
}
std::vector<double> sum_in_rank_order(std::span<const double> values) {
  return {values.begin(), values.end()};
}
std::vector<double> gather_all(std::span<const double> values) {
  return {values.begin(), values.end()};
}
std::vector<Index> gather_all_varying(std::span<const Index> values) {
  return {values.begin(), values.end()};
}
void sum_exactly(std::span<ExactSum>) {}
void barrier() {}
void abort(int code) {
  std::exit(code);
}

#endif

} // namespace sphfem::ranks
