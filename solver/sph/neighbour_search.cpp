#include "solver/sph/neighbour_search.hpp"

#include "solver/core/error.hpp"
#include "solver/core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sphfem {

namespace {

int thread_id() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

int thread_count() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

int thread_limit() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

constexpr double infinity = std::numeric_limits<double>::infinity();

// Cells are made this much wider than the cutoff so that rounding of the cell coordinate
// (a few ulps of the coordinate, < 1e-6 up to ~10^8 cells along an axis) can never place two
// points within the cutoff more than search_reach cells apart.
constexpr double cell_margin = 1e-6;

// At most this many cells per point: keeps a huge, sparse bounding box cheap.
Index max_cells_for(std::size_t n) {
  const auto cap = 2 * static_cast<std::int64_t>(n) + 1;
  return static_cast<Index>(std::min<std::int64_t>(cap, std::numeric_limits<Index>::max() / 2));
}

struct Box {
  Vec3 lo = Vec3::Constant(infinity);
  Vec3 hi = Vec3::Constant(-infinity);
};

// Bounding box of the points of x that `binned` marks (all when empty); throws naming the first
// of them with a non-finite coordinate.
Box bounding_box(std::span<const Vec3> x, std::span<const unsigned char> binned) {
  const Index n = static_cast<Index>(x.size());
  double lx = infinity, ly = infinity, lz = infinity;
  double ux = -infinity, uy = -infinity, uz = -infinity;
  Index first_bad = n;
#pragma omp parallel for schedule(static) reduction(min                                            \
                                                    : lx, ly, lz, first_bad)                       \
    reduction(max                                                                                  \
              : ux, uy, uz) if (n > parallel_min_items)
  for (Index i = 0; i < n; ++i) {
    if (!binned.empty() && !binned[i])
      continue;
    const Vec3& p = x[i];
    if (!p.allFinite())
      first_bad = std::min(first_bad, i);
    lx = std::min(lx, p.x());
    ly = std::min(ly, p.y());
    lz = std::min(lz, p.z());
    ux = std::max(ux, p.x());
    uy = std::max(uy, p.y());
    uz = std::max(uz, p.z());
  }
  SPHFEM_CHECK(first_bad == n, "neighbour search: particle ", first_bad,
               " has a non-finite position (", x[first_bad].x(), ", ", x[first_bad].y(), ", ",
               x[first_bad].z(), ")");
  return {Vec3(lx, ly, lz), Vec3(ux, uy, uz)};
}

// Largest h of the points `binned` marks (all when empty); throws naming the first of them
// whose h is negative or not finite.
double max_smoothing_length(std::span<const double> h, std::span<const unsigned char> binned) {
  const Index n = static_cast<Index>(h.size());
  double h_max = 0;
  Index first_bad = n;
#pragma omp parallel for schedule(static) reduction(min                                            \
                                                    : first_bad)                                   \
    reduction(max                                                                                  \
              : h_max) if (n > parallel_min_items)
  for (Index i = 0; i < n; ++i) {
    if (!binned.empty() && !binned[i])
      continue;
    if (!(h[i] >= 0 && h[i] < infinity))
      first_bad = std::min(first_bad, i);
    h_max = std::max(h_max, h[i]);
  }
  SPHFEM_CHECK(first_bad == n, "neighbour search: particle ", first_bad,
               " has an invalid smoothing length h = ", h[first_bad]);
  return h_max;
}

// e_i = |x_i − x⁰_i| + (h_i − h⁰_i) of the rebuild condition; a non-finite or negative state
// gives +∞ so that a rebuild (which throws with the particle index) is requested.
double excursion(const Vec3& x, const Vec3& x0, double h, double h0) {
  const double e = (x - x0).norm() + (h - h0);
  return std::isfinite(e) && h >= 0 ? e : infinity;
}

// The two largest values of a set; merging is exact, so any summation order gives the same.
struct TopTwo {
  double first = -infinity;
  double second = -infinity;
  TopTwo& operator+=(const TopTwo& o) {
    if (o.first > first) {
      second = std::max(first, o.second);
      first = o.first;
    } else {
      second = std::max(second, o.first);
    }
    return *this;
  }
};

// Stable counting sort by cell: order[k] is the original index of the k-th sorted point and
// start[c] the first k of cell c (start has cells + 1 entries).
void sort_by_cell(const std::vector<Index>& cell, Index cells, std::vector<Index>& start,
                  std::vector<Index>& order) {
  const Index n = static_cast<Index>(cell.size());
  start.assign(static_cast<std::size_t>(cells) + 1, 0);
  for (Index i = 0; i < n; ++i)
    ++start[cell[i] + 1];
  for (Index c = 0; c < cells; ++c)
    start[c + 1] += start[c];
  order.resize(n);
  for (Index i = 0; i < n; ++i) // start[c] runs to the end of cell c ...
    order[start[cell[i]]++] = i;
  for (Index c = cells; c > 0; --c) // ... and is shifted back to its beginning
    start[c] = start[c - 1];
  start[0] = 0;
}

// Sorts a row by original index. A row is a run of ascending indices per cell of the stencil;
// a row with at most two descents (a numbering close to the cells' order) sorts by insertion in
// linear time.
void sort_row(Index* begin, Index* end) {
  int descents = 0;
  for (const Index* p = begin + 1; p < end; ++p)
    descents += static_cast<int>(p[-1] > p[0]);
  if (descents == 0)
    return;
  if (descents > 2) {
    std::sort(begin, end);
    return;
  }
  for (Index* p = begin + 1; p < end; ++p)
    for (Index* q = p; q > begin && q[-1] > q[0]; --q)
      std::swap(q[-1], q[0]);
}

} // namespace

CellGrid CellGrid::make(const Vec3& lo, const Vec3& hi, double min_edge, Index max_cells) {
  const Vec3 extent = hi - lo;
  std::array<double, 3> cells{};
  // Cells along each axis for a given edge: floor(extent/edge) ≥ 1 keeps every cell ≥ edge.
  const auto cells_for = [&](double edge) {
    double product = 1;
    for (int d = 0; d < 3; ++d) {
      // Flat axes, an infinite edge and an overflowed extent (|x| ~ 1e308) give one cell.
      const double c = extent[d] < infinity ? std::floor(extent[d] / edge) : 1;
      cells[d] = c >= 1 ? std::min(c, static_cast<double>(max_cells)) : 1;
      product *= cells[d];
    }
    return product;
  };
  double edge = std::max(min_edge, extent.maxCoeff() / max_cells);
  for (double product = cells_for(edge); product > max_cells; product = cells_for(edge))
    edge *= std::max(1.01, std::cbrt(product / max_cells));

  CellGrid g;
  g.lo = lo;
  for (int d = 0; d < 3; ++d) {
    g.n[d] = static_cast<Index>(cells[d]);
    g.scale[d] = extent[d] > 0 && extent[d] < infinity ? cells[d] / extent[d] : 0;
  }
  return g;
}

Index CellGrid::cell_of(const Vec3& x) const {
  std::array<Index, 3> c{};
  for (int d = 0; d < 3; ++d) {
    // x ≥ lo, so u ≥ 0; the top face belongs to the last cell. u is NaN (∞ · 0) only on an
    // axis of overflowed extent, which has one cell.
    const double u = (x[d] - lo[d]) * scale[d];
    c[d] = u < n[d] - 1 ? static_cast<Index>(u) : n[d] - 1;
  }
  return c[0] + n[0] * (c[1] + n[1] * c[2]);
}

void NeighbourSearch::build(std::span<const Vec3> x, std::span<const double> h, double skin,
                            ListedRows listed) {
  SPHFEM_CHECK(x.size() == h.size(), "neighbour search: ", x.size(), " positions but ", h.size(),
               " smoothing lengths");
  for (const auto flags : {listed.rows, listed.if_near, listed.binned})
    SPHFEM_CHECK(flags.empty() || flags.size() == x.size(), "neighbour search: ", flags.size(),
                 " row flags for ", x.size(), " points");
  SPHFEM_CHECK(skin >= 0 && skin < infinity, "neighbour search: invalid skin ", skin);
  SPHFEM_CHECK(x.size() < static_cast<std::size_t>(std::numeric_limits<Index>::max()),
               "neighbour search: too many particles (", x.size(), ")");
  built_ = false;
  skin_ = skin;
  cutoff_ = 2 * max_smoothing_length(h, listed.binned) + skin;
  const Box box = bounding_box(x, listed.binned);
  const auto binned =
      listed.binned.empty()
          ? x.size()
          : static_cast<std::size_t>(std::count(listed.binned.begin(), listed.binned.end(), 1));
  grid_ = CellGrid::make(box.lo, box.hi, cutoff_ / search_reach * (1 + cell_margin),
                         max_cells_for(binned));
  bin(x, h, listed.binned);
  mark_listed(listed);
  fill_rows();
  x_build_.assign(x.begin(), x.end());
  h_build_.assign(h.begin(), h.end());
  built_ = true;
}

void NeighbourSearch::free_lists() {
  list_ = NeighbourList();
  half_ = HalfLists();
}

// The rows listed and the cells whose half rows their lists need: those within search_reach
// cells of a listed point's along each axis (a listed row's pairs lie there, and each pair is
// found from the lower of its two cells). Rows `if_near` marks are listed when within
// 2 search_reach cells of a row `rows` marks, which holds all within two cutoffs (cells are
// at least cutoff/search_reach wide). Both empty when every row is listed.
void NeighbourSearch::mark_listed(ListedRows listed) {
  listed_.clear();
  searched_.clear();
  if (listed.rows.empty())
    return;
  listed_.assign(listed.rows.begin(), listed.rows.end());
  if (!listed.if_near.empty()) {
    cells_within(listed_, 2 * search_reach, near_);
    const Index cells = grid_.count(); // an unbinned point's cell
    for (std::size_t i = 0; i < listed_.size(); ++i)
      listed_[i] =
          listed_[i] || (listed.if_near[i] && bins_.cell[i] < cells && near_[bins_.cell[i]]);
  }
  cells_within(listed_, search_reach, searched_);
}

// Per cell, into `near`: 1 when within `cells` cells, along each axis, of the cell of a point
// `points` marks (a box dilated along x, then y, then z, through the dilated_ scratch).
void NeighbourSearch::cells_within(std::span<const unsigned char> points, Index cells,
                                   std::vector<unsigned char>& near) {
  const Index count = grid_.count();
  near.assign(count, 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i] && bins_.cell[i] < count)
      near[bins_.cell[i]] = 1;
  const std::array<Index, 3> stride{1, grid_.n[0], grid_.n[0] * grid_.n[1]};
  for (int d = 0; d < 3; ++d) {
    dilated_.assign(count, 0);
    for (Index c = 0; c < count; ++c) {
      if (!near[c])
        continue;
      const Index at = (c / stride[d]) % grid_.n[d];
      const Index lo = std::max<Index>(at - cells, 0);
      const Index hi = std::min<Index>(at + cells, grid_.n[d] - 1);
      for (Index a = lo; a <= hi; ++a)
        dilated_[c + (a - at) * stride[d]] = 1;
    }
    near.swap(dilated_);
  }
}

// Counting sort of the particles into cells, stable in the original index. Points not binned
// go to a last bucket past the grid's cells, which is never searched.
void NeighbourSearch::bin(std::span<const Vec3> x, std::span<const double> h,
                          std::span<const unsigned char> binned) {
  const Index n = static_cast<Index>(x.size());
  const Index cells = grid_.count();
  bins_.cell.resize(n);
#pragma omp parallel for schedule(static) if (n > parallel_min_items)
  for (Index i = 0; i < n; ++i)
    bins_.cell[i] = binned.empty() || binned[i] ? grid_.cell_of(x[i]) : cells;
  sort_by_cell(bins_.cell, cells + 1, bins_.cell_start, bins_.order);
  const std::vector<Index>& order = bins_.order;
  const Index in_cells = bins_.cell_start[cells];
  bins_.points.resize(n);
#pragma omp parallel for schedule(static) if (n > parallel_min_items)
  for (Index k = 0; k < in_cells; ++k) {
    const Vec3& p = x[order[k]];
    bins_.points[k] = {p.x(), p.y(), p.z(), h[order[k]]};
  }
}

// Half rows of the particles of cell c: for each sorted point k, the m > k within the cutoff,
// appended to `rows`. The cells within search_reach of c along x are contiguous in the sorted
// points, so the search runs over (2 reach + 1)² contiguous spans, ascending. Every candidate
// is written and the write position advanced by the test's outcome: no unpredictable branch.
void NeighbourSearch::search_upper(Index c, UpperBuffer& rows) {
  constexpr Index reach = search_reach;
  const auto [nx, ny, nz] = grid_.n;
  const Index cx = c % nx, cy = (c / nx) % ny, cz = c / (nx * ny);
  const Index x0 = std::max(cx - reach, 0), x1 = std::min(cx + reach, nx - 1);
  const Index begin = bins_.cell_start[c], end = bins_.cell_start[c + 1];
  if (!searched_.empty() && !searched_[c]) { // no listed row has a pair here
    for (Index k = begin; k < end; ++k) {
      half_.at[k] = rows.used;
      half_.count[k] = 0;
    }
    return;
  }
  std::array<std::array<Index, 2>, (2 * reach + 1) * (2 * reach + 1)> spans;
  int span_count = 0;
  std::size_t candidates = 0;
  for (Index z = cz; z <= std::min(cz + reach, nz - 1); ++z) // lower planes hold only m < k
    for (Index y = std::max(cy - reach, 0); y <= std::min(cy + reach, ny - 1); ++y) {
      const Index row = nx * (y + ny * z);
      const Index b = std::max(bins_.cell_start[row + x0], begin + 1);
      const Index e = bins_.cell_start[row + x1 + 1];
      if (b < e) {
        spans[span_count++] = {b, e};
        candidates += static_cast<std::size_t>(e - b);
      }
    }

  const Point* points = bins_.points.data();
  const double skin = skin_;
  const std::size_t need = rows.used + candidates * static_cast<std::size_t>(end - begin);
  if (rows.entries.size() < need)
    rows.entries.resize(std::max(need, 2 * rows.entries.size()));
  for (Index k = begin; k < end; ++k) {
    const Point p = points[k];
    Index* const first = rows.entries.data() + rows.used;
    Index* out = first;
    for (int s = 0; s < span_count; ++s)
      for (Index m = std::max(spans[s][0], k + 1); m < spans[s][1]; ++m) {
        const double dx = points[m].x - p.x, dy = points[m].y - p.y, dz = points[m].z - p.z;
        const double cut = p.h + points[m].h + skin;
        *out = m;
        out += static_cast<int>(dx * dx + dy * dy + dz * dz < cut * cut);
      }
    half_.at[k] = rows.used;
    half_.count[k] = static_cast<Index>(out - first);
    rows.used += static_cast<std::size_t>(out - first);
  }
}

// Half row of sorted point k, found by the thread that owns k (thread `thread` owns most).
std::span<const Index> NeighbourSearch::upper_row(Index k, int thread, int threads) const {
  if (k < half_.first[thread]) {
    const auto end = half_.first.begin() + threads + 1;
    thread =
        static_cast<int>(std::upper_bound(half_.first.begin(), end, k) - half_.first.begin()) - 1;
  }
  return {half_.buffers[thread].entries.data() + half_.at[k],
          static_cast<std::size_t>(half_.count[k])};
}

// Each thread owns a contiguous range of cells holding ~N/threads sorted points [k0, k1):
//  1. it finds their half rows (each pair tested once);
//  2. it counts, for each own m, the k < m that listed it: those k lie in own cells or in the
//     cells up to one stencil (search_reach (1 + nx + nx ny) linear cells) before them;
//  3. once the offsets are known, it writes each own row: those k ascending, then the half row,
//     as original indices, sorted.
// Rows not listed (listed_) are left empty.
// Every write goes to an own particle: no locks, no atomics, and each row's content does not
// depend on the thread count.
void NeighbourSearch::fill_rows() {
  const Index n = static_cast<Index>(bins_.order.size());
  const Index cells = grid_.count();
  const std::vector<Index>& start = bins_.cell_start;
  const std::vector<Index>& order = bins_.order;
  const Index in_cells = start[cells]; // the binned points; those after them have empty rows
  const bool all = listed_.empty();
  const auto wanted = [&](Index m) { return all || listed_[order[m]] != 0; };
  const std::int64_t stencil_back =
      search_reach * (1 + grid_.n[0] + static_cast<std::int64_t>(grid_.n[0]) * grid_.n[1]);
  list_.offsets.resize(static_cast<std::size_t>(n) + 1);
  list_.offsets[0] = 0;
  half_.at.resize(n);
  half_.count.resize(n);
  half_.lower.resize(n);
  const auto max_threads = static_cast<std::size_t>(thread_limit());
  if (half_.buffers.size() < max_threads)
    half_.buffers.resize(max_threads);
  half_.first.resize(max_threads + 1);
  bool fits = true;

#pragma omp parallel if (n > parallel_min_items)
  {
    const int t = thread_id(), threads = thread_count();
    const auto first_cell = [&](int share) {
      if (share == threads)
        return cells;
      const Index target =
          static_cast<Index>(static_cast<std::int64_t>(in_cells) * share / threads);
      return static_cast<Index>(std::lower_bound(start.begin(), start.begin() + cells, target) -
                                start.begin());
    };
    const Index c0 = first_cell(t), c1 = first_cell(t + 1);
    const Index k0 = start[c0], k1 = start[c1];
    const Index k_back = start[static_cast<Index>(std::max<std::int64_t>(c0 - stencil_back, 0))];
    half_.first[t] = k0;
    if (t == threads - 1)
      half_.first[threads] = in_cells;
    half_.buffers[t].used = 0;
    for (Index c = c0; c < c1; ++c)
      search_upper(c, half_.buffers[t]);
#pragma omp barrier

    // The half rows listing own points: k in [k_back, k1), own m in [k0, k1).
    const auto for_each_lower = [&](auto&& visit) {
      for (Index k = k_back; k < k0; ++k)
        for (Index m : upper_row(k, t, threads))
          if (m >= k0 && m < k1)
            visit(k, m);
      const Index* own = half_.buffers[t].entries.data();
      for (Index k = k0; k < k1; ++k) {
        const Index* row = own + half_.at[k];
        for (Index r = 0; r < half_.count[k] && row[r] < k1; ++r)
          visit(k, row[r]);
      }
    };
    Index* lower = half_.lower.data();
    std::fill(lower + k0, lower + k1, 0);
    for_each_lower([lower](Index, Index m) { ++lower[m]; });
    for (Index m = k0; m < k1; ++m)
      list_.offsets[order[m] + 1] = wanted(m) ? lower[m] + half_.count[m] : 0;
#pragma omp barrier

#pragma omp single
    {
      for (Index m = in_cells; m < n; ++m)
        list_.offsets[order[m] + 1] = 0;
      std::int64_t total = 0;
      for (Index i = 1; i <= n; ++i) {
        total += list_.offsets[i];
        list_.offsets[i] = static_cast<Index>(std::min<std::int64_t>(total, 0x7fffffff));
      }
      fits = total < std::numeric_limits<Index>::max();
      list_.neighbours.resize(fits ? static_cast<std::size_t>(total) : 0);
    }
    if (fits) {
      Index* out = list_.neighbours.data();
      for (Index m = k0; m < k1; ++m)
        lower[m] = list_.offsets[order[m]];
      const Index* original = order.data();
      if (all)
        for_each_lower([out, lower, original](Index k, Index m) { out[lower[m]++] = original[k]; });
      else
        for_each_lower([&](Index k, Index m) {
          if (wanted(m))
            out[lower[m]++] = original[k];
        });
      for (Index m = k0; m < k1; ++m) {
        if (!wanted(m))
          continue;
        Index* row_end = out + lower[m];
        for (Index j : upper_row(m, t, threads))
          *row_end++ = order[j];
        sort_row(out + list_.offsets[order[m]], row_end);
      }
    }
  }
  SPHFEM_CHECK(fits, "neighbour search: more than 2^31 neighbour entries for ", n, " particles");
}

bool NeighbourSearch::needs_update(std::span<const Vec3> x, std::span<const double> h) const {
  return !built_for(x, h) || exceeds_skin(largest_excursions(x, h));
}

bool NeighbourSearch::built_for(std::span<const Vec3> x, std::span<const double> h) const {
  return built_ && x.size() == x_build_.size() && h.size() == x.size();
}

std::array<double, 2>
NeighbourSearch::largest_excursions(std::span<const Vec3> x, std::span<const double> h,
                                    std::span<const unsigned char> counted) const {
  const Index n = static_cast<Index>(x.size());
  const TopTwo top = deterministic_sum(n, TopTwo{}, [&](Index i) {
    if (!counted.empty() && !counted[i])
      return TopTwo{};
    return TopTwo{excursion(x[i], x_build_[i], h[i], h_build_[i]), -infinity};
  });
  return {top.first, top.second};
}

std::array<double, 2> NeighbourSearch::merge_excursions(std::span<const double> pairs) {
  TopTwo top;
  for (std::size_t k = 0; k + 1 < pairs.size(); k += 2)
    top += TopTwo{pairs[k], pairs[k + 1]};
  return {top.first, top.second};
}

bool NeighbourSearch::exceeds_skin(const std::array<double, 2>& top) const {
  if (top[0] == infinity)
    return true;
  return top[0] + top[1] > skin_; // −∞ for a single particle: no pair to miss
}

} // namespace sphfem
