// A uniform cell grid over a fixed set of points for fixed-radius "is any point near x?"
// queries: the points sorted by cell, a query visits the 27 cells around x. Used by the
// interface tagging (mesher/interface_tags.cpp), where models hold 1e5 particles and nodes and
// all-pairs tests would cost 1e10 distance evaluations. Verified against brute force by
// tests/mesher/interface_tags_test.cpp.
#pragma once

#include "solver/core/types.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace sphfem::mesher {

class PointGrid {
public:
  // Indexes `points` (copied; point j keeps index j) in cubic cells of edge `cell` (m, > 0, the
  // largest radius a query will ask about; enlarged when the points span more than 2^20 cells).
  PointGrid(const std::vector<Vec3>& points, double cell);

  // True if test(j) holds for some point j in the 27 cells around x, which include every point
  // within `cell` of x. Stops at the first j that passes.
  template <class Test> bool any_near(const Vec3& x, Test test) const;

  const Vec3& point(Index j) const { return x_[static_cast<std::size_t>(j)]; }

private:
  // Cell coordinate of an indexed point along axis a.
  std::int64_t coordinate(const Vec3& x, int a) const;
  std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return (static_cast<std::uint64_t>(i) * static_cast<std::uint64_t>(n_[1]) +
            static_cast<std::uint64_t>(j)) *
               static_cast<std::uint64_t>(n_[2]) +
           static_cast<std::uint64_t>(k);
  }
  // The range [first, last) of sorted entries in the cell with key `k`.
  std::pair<std::size_t, std::size_t> cell_range(std::uint64_t k) const;

  std::vector<Vec3> x_;
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1;
  std::int64_t n_[3] = {0, 0, 0};
  std::vector<std::uint64_t> keys_; // sorted cell keys, one per point
  std::vector<Index> order_;        // point index of each sorted entry
};

template <class Test> bool PointGrid::any_near(const Vec3& x, Test test) const {
  if (x_.empty())
    return false;
  // Cell coordinates of x, unclamped (may lie one cell outside the grid).
  std::int64_t c[3];
  for (int a = 0; a < 3; ++a) {
    const double u = std::floor((x[a] - origin_[a]) / cell_);
    if (!(u >= -1 && u <= static_cast<double>(n_[a])))
      return false; // more than one cell away from every point
    c[a] = static_cast<std::int64_t>(u);
  }
  for (std::int64_t i = c[0] - 1; i <= c[0] + 1; ++i)
    for (std::int64_t j = c[1] - 1; j <= c[1] + 1; ++j)
      for (std::int64_t k = c[2] - 1; k <= c[2] + 1; ++k) {
        if (i < 0 || j < 0 || k < 0 || i >= n_[0] || j >= n_[1] || k >= n_[2])
          continue;
        const auto [first, last] = cell_range(key(i, j, k));
        for (std::size_t e = first; e < last; ++e)
          if (test(order_[e]))
            return true;
      }
  return false;
}

} // namespace sphfem::mesher
