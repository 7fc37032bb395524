// Node → (element, local node) adjacency in compressed rows, and the race-free gather of the
// elements' nodal forces into per-node sums: each node sums its own entries in a fixed order,
// so results are identical for any thread count. Verified by tests/fem/hex8_test.cpp.
#pragma once

#include "solver/core/types.hpp"
#include "solver/state/hex_elements.hpp"

#include <span>
#include <vector>

namespace sphfem {

class NodeGather {
public:
  NodeGather() = default;
  NodeGather(const std::vector<Hex>& elements, Index node_count);

  // out[i] = Σ over the elements around node i of their force on it, for the nodes in `only`
  // (null: all).
  void gather_forces(const HexElements& e, std::vector<Vec3>& out,
                     const std::vector<Index>* only = nullptr) const;

  // Elements around node i as (element, local node) pairs encoded element * 8 + local.
  std::span<const Index> around(Index node) const {
    return {entries_.data() + offsets_[node], entries_.data() + offsets_[node + 1]};
  }

private:
  std::vector<Index> offsets_; // node_count + 1
  std::vector<Index> entries_;
};

} // namespace sphfem
