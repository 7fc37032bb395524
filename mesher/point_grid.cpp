// Builds the PointGrid (mesher/point_grid.hpp): points sorted by cell key, ties by index, so
// the layout and every query are deterministic.
#include "mesher/point_grid.hpp"

#include "solver/core/error.hpp"

#include <algorithm>
#include <numeric>

namespace sphfem::mesher {

namespace {
constexpr double max_cells_per_axis = 1 << 20; // keys of three axes fit 60 bits
}

PointGrid::PointGrid(const std::vector<Vec3>& points, double cell) : x_(points), cell_(cell) {
  SPHFEM_CHECK(cell > 0 && std::isfinite(cell), "grid cell size must be positive, got ", cell);
  if (x_.empty())
    return;
  Vec3 low = x_.front(), high = x_.front();
  for (const Vec3& p : x_) {
    SPHFEM_CHECK(p.allFinite(), "non-finite point in the grid");
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  origin_ = low;
  cell_ = std::max(cell, (high - low).maxCoeff() / (max_cells_per_axis - 1));
  for (int a = 0; a < 3; ++a)
    n_[a] = static_cast<std::int64_t>(std::floor((high[a] - low[a]) / cell_)) + 1;
  std::vector<std::uint64_t> point_keys(x_.size());
  for (std::size_t p = 0; p < x_.size(); ++p)
    point_keys[p] = key(coordinate(x_[p], 0), coordinate(x_[p], 1), coordinate(x_[p], 2));
  order_.resize(x_.size());
  std::iota(order_.begin(), order_.end(), 0);
  std::ranges::stable_sort(order_, {}, [&point_keys](Index p) { return point_keys[p]; });
  keys_.resize(x_.size());
  for (std::size_t e = 0; e < order_.size(); ++e)
    keys_[e] = point_keys[static_cast<std::size_t>(order_[e])];
}

std::int64_t PointGrid::coordinate(const Vec3& x, int a) const {
  const auto c = static_cast<std::int64_t>(std::floor((x[a] - origin_[a]) / cell_));
  return std::clamp<std::int64_t>(c, 0, n_[a] - 1); // rounding at the upper end
}

std::pair<std::size_t, std::size_t> PointGrid::cell_range(std::uint64_t k) const {
  const auto [first, last] = std::ranges::equal_range(keys_, k);
  return {static_cast<std::size_t>(first - keys_.begin()),
          static_cast<std::size_t>(last - keys_.begin())};
}

} // namespace sphfem::mesher
