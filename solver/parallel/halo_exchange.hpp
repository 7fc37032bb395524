// The exchange of a distributed run (issue 28, point 3): every rank addresses entities by their
// number in the model, steps the entities it owns and reads some it does not own (its halo:
// the nodes of the elements it computes). After a phase, each owner sends the values of those
// entities to the ranks that read them, which write them into the same slots. The lists are
// agreed once (each rank says what it reads, the owners learn it), so a refresh sends only the
// halo's values: per pair of ranks one message holding every field asked for.
//
// Fields are std::vectors of fixed-size values (numbers, Vec3, Mat3, arrays of them, plain
// structs) copied as bytes, or views of them indexed by entity (HexElements' BySlot: the
// elements' state is held in slots). Without MPI, or on one rank, there is nothing to exchange.
//
// An exchange of whole states (a gather before a checkpoint or a new cut, a new halo after a
// neighbour-list rebuild) goes field by field (refresh_by_field): its one-message
// buffers would hold, on every rank, a copy of the state it sends and of the state it receives —
// 1.2 KB per entity on each of 4 ranks on the Børvik shot, as much as the arrays themselves
// (docs/scaling.md).
#pragma once

#include "solver/core/types.hpp"

#include <cstddef>
#include <cstring>
#include <span>
#include <vector>

namespace sphfem {

// Whom a gather of a whole state serves: every rank (a new cut, a message naming an entity of
// all) or rank 0 alone, which writes the checkpoint.
enum class GatherTo { every_rank, writer };

class HaloExchange {
public:
  HaloExchange() = default;
  // owner[i]: the rank owning entity i (the same on every rank); reads: the entities this rank
  // reads, in any order (those it owns are skipped). Collective: every rank calls it together.
  HaloExchange(std::span<const int> owner, std::span<const Index> reads);
  // The other way round: sends[r] lists the entities this rank sends to rank r (its own, or any
  // it holds current), and each rank learns what it receives. Collective.
  static HaloExchange pushed(std::vector<std::vector<Index>> sends);
  // A gather: every entity into the ranks `to` names, from its owner (owner[i], the same on
  // every rank). Each rank knows from `owner` what it sends and receives, so nothing is agreed.
  static HaloExchange gather(std::span<const int> owner, GatherTo to);

  // Owners' values into the read slots of every rank, for each field `for_each` visits:
  // for_each(visit) calls visit(name, field) per field (as Nodes::for_each_field does).
  // Collective.
  template <class ForEach> void refresh_each(ForEach for_each);
  template <class... Field> void refresh(Field&... fields) {
    refresh_each([&](auto visit) { (visit("", fields), ...); });
  }
  // The same, one message per field and pair of ranks through buffers of one field's size.
  // Collective.
  template <class ForEach> void refresh_by_field(ForEach for_each);
  // Renumbers the lists from the numbers every rank shares to this rank's own slots
  // (slot_of(number)): for entities each rank lays out its own way, such as a distributed run's
  // particle rows. Built on the shared numbers, the lists pair up on both sides in that order.
  template <class SlotOf> void to_slots(SlotOf slot_of) {
    for (auto* lists : {&send_, &receive_})
      for (auto& list : *lists)
        for (Index& i : list)
          i = slot_of(i);
  }
  // Frees the message buffers (kept between refreshes otherwise, so that a step allocates
  // nothing): after a gather that is not repeated soon.
  void release();

  // What this rank receives from each rank, ascending.
  const std::vector<std::vector<Index>>& receives() const { return receive_; }
  // Entities this rank sends and receives per refresh (all ranks together).
  long long sent() const { return count(send_); }
  long long received() const { return count(receive_); }
  // Bytes sent by this rank over all refreshes so far.
  long long bytes_sent() const { return bytes_sent_; }

private:
  static long long count(const std::vector<std::vector<Index>>& lists);
  // Each rank's lists[r] of entities it names to rank r, delivered: what r named to this rank.
  static std::vector<std::vector<Index>> delivered(const std::vector<std::vector<Index>>& lists);
  // Sends send_buffer_[r] to each rank r and fills receive_buffer_[r] from it; `unit`: the bytes
  // of one entity's values (MPI counts in int: a message may hold 2³¹ − 1 entities, not only
  // 2³¹ − 1 bytes).
  void transfer(std::size_t unit);

  std::vector<std::vector<Index>> send_, receive_; // per rank: the entities, ascending
  std::vector<std::vector<std::byte>> send_buffer_, receive_buffer_;
  long long bytes_sent_ = 0;
};

template <class ForEach> void HaloExchange::refresh_each(ForEach for_each) {
  if (send_.empty())
    return;
  std::size_t row = 0; // bytes per entity over all fields
  for_each([&row](const char*, auto& field) { row += sizeof(field[0]); });
  if (row == 0)
    return;
  for (std::size_t r = 0; r < send_.size(); ++r) {
    send_buffer_[r].resize(send_[r].size() * row);
    receive_buffer_[r].resize(receive_[r].size() * row);
    std::byte* out = send_buffer_[r].data();
    for_each([&](const char*, auto& field) {
      constexpr std::size_t size = sizeof(field[0]);
      for (Index i : send_[r]) {
        std::memcpy(out, &field[i], size);
        out += size;
      }
    });
  }
  transfer(row);
  for (std::size_t r = 0; r < receive_.size(); ++r) {
    const std::byte* in = receive_buffer_[r].data();
    for_each([&](const char*, auto& field) {
      constexpr std::size_t size = sizeof(field[0]);
      for (Index i : receive_[r]) {
        std::memcpy(static_cast<void*>(&field[i]), in, size); // fixed-size values
        in += size;
      }
    });
  }
}

template <class ForEach> void HaloExchange::refresh_by_field(ForEach for_each) {
  if (send_.empty())
    return;
  for_each([this](const char* name, auto& field) {
    this->refresh_each([&](auto visit) { visit(name, field); });
  });
}

} // namespace sphfem
