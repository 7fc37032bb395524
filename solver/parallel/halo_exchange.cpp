#include "solver/parallel/halo_exchange.hpp"

#include "solver/core/error.hpp"
#include "solver/parallel/ranks.hpp"

#include <algorithm>
#include <limits>

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

void HaloExchange::release() {
  for (auto* buffers : {&send_buffer_, &receive_buffer_})
    for (auto& buffer : *buffers)
      std::vector<std::byte>().swap(buffer);
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
  send_ = delivered(receive_); // each owner learns what this rank reads
  send_buffer_.resize(n);
  receive_buffer_.resize(n);
}

HaloExchange HaloExchange::pushed(std::vector<std::vector<Index>> sends) {
  HaloExchange h;
  const int n = ranks::size();
  if (n == 1)
    return h;
  SPHFEM_CHECK(sends.size() == static_cast<std::size_t>(n), "halo: ", sends.size(),
               " send lists for ", n, " ranks (internal error)");
  sends[ranks::rank()].clear();
  for (auto& list : sends) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  h.receive_ = delivered(sends);
  h.send_ = std::move(sends);
  h.send_buffer_.resize(n);
  h.receive_buffer_.resize(n);
  return h;
}

HaloExchange HaloExchange::gather(std::span<const int> owner, GatherTo to) {
  HaloExchange h;
  const int n = ranks::size(), me = ranks::rank();
  if (n == 1)
    return h;
  const auto receives = [to](int r) { return to == GatherTo::every_rank || r == 0; };
  h.send_.assign(n, {});
  h.receive_.assign(n, {});
  for (std::size_t i = 0; i < owner.size(); ++i) {
    const int r = owner[i];
    SPHFEM_CHECK(r >= 0 && r < n, "halo: entity ", i, " has owner ", r, " of ", n,
                 " ranks (internal error)");
    if (r == me) {
      for (int to_rank = 0; to_rank < n; ++to_rank)
        if (to_rank != me && receives(to_rank))
          h.send_[to_rank].push_back(static_cast<Index>(i));
    } else if (receives(me)) {
      h.receive_[r].push_back(static_cast<Index>(i));
    }
  }
  h.send_buffer_.resize(n);
  h.receive_buffer_.resize(n);
  return h;
}

std::vector<std::vector<Index>>
HaloExchange::delivered(const std::vector<std::vector<Index>>& lists) {
  const int n = static_cast<int>(lists.size());
  std::vector<int> ask(n), asked(n);
  for (int r = 0; r < n; ++r)
    ask[r] = static_cast<int>(lists[r].size());
  MPI_Alltoall(ask.data(), 1, MPI_INT, asked.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> ask_at(n, 0), asked_at(n, 0);
  for (int r = 1; r < n; ++r) {
    ask_at[r] = ask_at[r - 1] + ask[r - 1];
    asked_at[r] = asked_at[r - 1] + asked[r - 1];
  }
  std::vector<Index> asks, askeds(static_cast<std::size_t>(asked_at[n - 1] + asked[n - 1]));
  for (const auto& list : lists)
    asks.insert(asks.end(), list.begin(), list.end());
  MPI_Alltoallv(asks.data(), ask.data(), ask_at.data(), index_type(), askeds.data(), asked.data(),
                asked_at.data(), index_type(), MPI_COMM_WORLD);
  std::vector<std::vector<Index>> out(n);
  for (int r = 0; r < n; ++r)
    out[r].assign(askeds.begin() + asked_at[r], askeds.begin() + asked_at[r] + asked[r]);
  return out;
}

void HaloExchange::transfer(std::size_t unit) {
  const int n = static_cast<int>(send_.size());
  // Counted in bytes while every message's bytes fit in MPI's int count (Open MPI's fastest
  // path); in entities of `unit` bytes beyond (an MPI type of that size) — a gather's message
  // grows with the model.
  std::size_t largest = 0;
  for (int r = 0; r < n; ++r)
    largest = std::max({largest, send_buffer_[r].size(), receive_buffer_[r].size()});
  const std::size_t int_max = std::numeric_limits<int>::max();
  SPHFEM_CHECK(largest / unit <= int_max, "halo: a message of ", largest / unit,
               " entities exceeds MPI's count (use more ranks)");
  const bool in_bytes = largest <= int_max;
  MPI_Datatype type = MPI_BYTE;
  if (!in_bytes) {
    MPI_Type_contiguous(static_cast<int>(unit), MPI_BYTE, &type);
    MPI_Type_commit(&type);
  }
  const auto count = [&](const std::vector<std::byte>& buffer) {
    return static_cast<int>(in_bytes ? buffer.size() : buffer.size() / unit);
  };
  std::vector<MPI_Request> requests;
  requests.reserve(2 * static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r)
    if (!receive_buffer_[r].empty())
      MPI_Irecv(receive_buffer_[r].data(), count(receive_buffer_[r]), type, r, 28, MPI_COMM_WORLD,
                &requests.emplace_back());
  for (int r = 0; r < n; ++r)
    if (!send_buffer_[r].empty()) {
      MPI_Isend(send_buffer_[r].data(), count(send_buffer_[r]), type, r, 28, MPI_COMM_WORLD,
                &requests.emplace_back());
      bytes_sent_ += static_cast<long long>(send_buffer_[r].size());
    }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  if (!in_bytes)
    MPI_Type_free(&type);
}

#else

HaloExchange::HaloExchange(std::span<const int>, std::span<const Index>) {}

HaloExchange HaloExchange::pushed(std::vector<std::vector<Index>>) {
  return {};
}

HaloExchange HaloExchange::gather(std::span<const int>, GatherTo) {
  return {};
}

void HaloExchange::transfer(std::size_t) {}

#endif

} // namespace sphfem
