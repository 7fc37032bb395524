#include "solver/parallel/halo_exchange.hpp"

#include "solver/core/error.hpp"
#include "solver/parallel/ranks.hpp"

#include <algorithm>

#ifdef SPHFEM_HAVE_MPI
#include <mpi.h>
#endif

namespace sphfem {

long long HaloExchange::count(const std::vector<std::vector<Index>>& lists) {
  long long n = 0;
  for (const auto& list : lists)
    n += static_cast<long long>(list.size());
  return n;
}

#ifdef SPHFEM_HAVE_MPI

namespace {

// MPI_Index: the MPI type of sphfem's Index.
MPI_Datatype index_type() {
  return sizeof(Index) == 8 ? MPI_INT64_T : MPI_INT32_T;
}

} // namespace

HaloExchange::HaloExchange(std::span<const int> owner, std::span<const Index> reads) {
  const int n = ranks::size(), me = ranks::rank();
  if (n == 1)
    return;
  receive_.assign(n, {});
  for (Index i : reads) {
    SPHFEM_CHECK(i >= 0 && static_cast<std::size_t>(i) < owner.size(), "halo: entity ", i,
                 " is not among the ", owner.size(), " entities (internal error)");
    if (owner[i] != me)
      receive_[owner[i]].push_back(i);
  }
  for (auto& list : receive_) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  // Tell each owner what this rank reads.
  std::vector<int> ask(n), asked(n);
  for (int r = 0; r < n; ++r)
    ask[r] = static_cast<int>(receive_[r].size());
  MPI_Alltoall(ask.data(), 1, MPI_INT, asked.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> ask_at(n, 0), asked_at(n, 0);
  for (int r = 1; r < n; ++r) {
    ask_at[r] = ask_at[r - 1] + ask[r - 1];
    asked_at[r] = asked_at[r - 1] + asked[r - 1];
  }
  std::vector<Index> asks, askeds(static_cast<std::size_t>(asked_at[n - 1] + asked[n - 1]));
  for (const auto& list : receive_)
    asks.insert(asks.end(), list.begin(), list.end());
  MPI_Alltoallv(asks.data(), ask.data(), ask_at.data(), index_type(), askeds.data(), asked.data(),
                asked_at.data(), index_type(), MPI_COMM_WORLD);
  send_.assign(n, {});
  for (int r = 0; r < n; ++r)
    send_[r].assign(askeds.begin() + asked_at[r], askeds.begin() + asked_at[r] + asked[r]);
  send_buffer_.resize(n);
  receive_buffer_.resize(n);
}

void HaloExchange::transfer() {
  const int n = static_cast<int>(send_.size());
  std::vector<MPI_Request> requests;
  requests.reserve(2 * static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r)
    if (!receive_buffer_[r].empty())
      MPI_Irecv(receive_buffer_[r].data(), static_cast<int>(receive_buffer_[r].size()), MPI_BYTE, r,
                28, MPI_COMM_WORLD, &requests.emplace_back());
  for (int r = 0; r < n; ++r)
    if (!send_buffer_[r].empty()) {
      MPI_Isend(send_buffer_[r].data(), static_cast<int>(send_buffer_[r].size()), MPI_BYTE, r, 28,
                MPI_COMM_WORLD, &requests.emplace_back());
      bytes_sent_ += static_cast<long long>(send_buffer_[r].size());
    }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

#else

HaloExchange::HaloExchange(std::span<const int>, std::span<const Index>) {}

void HaloExchange::transfer() {}

#endif

} // namespace sphfem
