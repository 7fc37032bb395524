#include "solver/fem/node_gather.hpp"

#include "solver/core/parallel.hpp"

namespace sphfem {

NodeGather::NodeGather(const std::vector<Hex>& elements, Index node_count)
    : offsets_(static_cast<std::size_t>(node_count) + 1, 0) {
  for (const Hex& hex : elements)
    for (Index node : hex)
      ++offsets_[node + 1];
  for (Index i = 0; i < node_count; ++i)
    offsets_[i + 1] += offsets_[i];
  entries_.resize(offsets_.back());
  std::vector<Index> fill(offsets_.begin(), offsets_.end() - 1);
  for (Index e = 0; e < static_cast<Index>(elements.size()); ++e)
    for (int I = 0; I < 8; ++I)
      entries_[fill[elements[e][I]]++] = e * 8 + I;
}

void NodeGather::gather_forces(const HexElements& e, std::vector<Vec3>& out,
                               const std::vector<Index>* only) const {
  const IndexRange nodes = IndexRange::of(only, static_cast<Index>(offsets_.size()) - 1);
#pragma omp parallel for schedule(static) if (nodes.count > parallel_min_items)
  for (Index j = 0; j < nodes.count; ++j) {
    const Index i = nodes[j];
    Vec3 sum = Vec3::Zero();
    for (Index k = offsets_[i]; k < offsets_[i + 1]; ++k)
      sum += e.f_e[e.slot(entries_[k] / 8)][entries_[k] % 8];
    out[i] = sum;
  }
}

} // namespace sphfem
