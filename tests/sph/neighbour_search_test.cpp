// Unit tests of the SPH neighbour search (solver/sph/neighbour_search): lists equal to an
// O(N²) brute force on random clouds with mixed h (cube, thin slab, thin rod), lattice
// neighbour counts, the Verlet rebuild condition (its thresholds, its tightness and its
// sufficiency), rows sorted by index whatever the numbering (and so alike for a subset numbered
// alike), the cell grid, independence of the thread count, a build of some rows only, and
// degenerate inputs.
#include "solver/sph/neighbour_search.hpp"

#include "solver/core/error.hpp"

#include <gtest/gtest.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

using namespace sphfem;

// Every allocation of the test program is counted, and every block still held, to check that
// rebuilding does not allocate and that what a build frees is freed. The replacements are not
// inlined: GCC would otherwise pair malloc() with operator delete and warn
// (-Wmismatched-new-delete).
std::atomic<long> allocations{0};
std::atomic<long> held{0};

[[gnu::noinline]] void* operator new(std::size_t size) {
  ++allocations;
  if (void* p = std::malloc(size > 0 ? size : 1)) {
    ++held;
    return p;
  }
  throw std::bad_alloc();
}
[[gnu::noinline]] void* operator new(std::size_t size, std::align_val_t align) {
  ++allocations;
  const auto a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (std::max<std::size_t>(size, 1) + a - 1) / a * a)) {
    ++held;
    return p;
  }
  throw std::bad_alloc();
}
[[gnu::noinline]] void operator delete(void* p) noexcept {
  held -= p != nullptr;
  std::free(p);
}
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept {
  held -= p != nullptr;
  std::free(p);
}
[[gnu::noinline]] void operator delete(void* p, std::align_val_t) noexcept {
  held -= p != nullptr;
  std::free(p);
}
[[gnu::noinline]] void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  held -= p != nullptr;
  std::free(p);
}

namespace {

using Rows = std::vector<std::vector<Index>>;

struct Cloud {
  std::vector<Vec3> x;
  std::vector<double> h;
};

// n points uniform in [0, size] with h uniform in [h0, 3 h0]; h0 = 0.6 × mean spacing gives
// some 60 neighbours on average when the box is thicker than the cutoff.
Cloud random_cloud(Index n, const Vec3& size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double h0 = 0.6 * std::cbrt(size.prod() / std::max<Index>(n, 1));
  Cloud c;
  for (Index i = 0; i < n; ++i) {
    c.x.emplace_back(size.x() * unit(rng), size.y() * unit(rng), size.z() * unit(rng));
    c.h.push_back(h0 * (1 + 2 * unit(rng)));
  }
  return c;
}

// The cloud renumbered: particle k of the result is particle new_to_old[k] of c.
Cloud permuted(const Cloud& c, const std::vector<Index>& new_to_old) {
  Cloud out;
  for (Index old : new_to_old) {
    out.x.push_back(c.x[old]);
    out.h.push_back(c.h[old]);
  }
  return out;
}

// A numbering along x (ties by index): spatially coherent like a lattice's, and far from the
// search's cell order (rows gather many ascending runs).
std::vector<Index> along_x(const Cloud& c) {
  std::vector<Index> order(c.x.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&c](Index a, Index b) { return c.x[a].x() < c.x[b].x(); });
  return order;
}

// The listing predicate written out independently: r < h_i + h_j + skin, compared squared.
bool within(const Vec3& xi, const Vec3& xj, double hi, double hj, double skin) {
  const double dx = xj.x() - xi.x(), dy = xj.y() - xi.y(), dz = xj.z() - xi.z();
  const double cut = hi + hj + skin;
  return dx * dx + dy * dy + dz * dz < cut * cut;
}

// The rows of the particles `wanted` marks (all when empty); the others empty.
Rows brute_force(const Cloud& c, double skin, const std::vector<unsigned char>& wanted = {}) {
  const auto n = static_cast<Index>(c.x.size());
  Rows rows(n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n && (wanted.empty() || wanted[i]); ++j)
      if (j != i && within(c.x[i], c.x[j], c.h[i], c.h[j], skin))
        rows[i].push_back(j);
  return rows;
}

::testing::AssertionResult lists_equal(const NeighbourList& list, const Rows& expected) {
  if (list.offsets.size() != expected.size() + 1)
    return ::testing::AssertionFailure()
           << list.offsets.size() << " offsets for " << expected.size() << " particles";
  std::size_t entries = 0;
  for (Index i = 0; i < static_cast<Index>(expected.size()); ++i) {
    const auto row = list.of(i);
    if (!std::equal(row.begin(), row.end(), expected[i].begin(), expected[i].end()))
      return ::testing::AssertionFailure() << "row of particle " << i << " has " << row.size()
                                           << " entries, brute force " << expected[i].size();
    entries += expected[i].size();
  }
  if (list.pair_count() != entries)
    return ::testing::AssertionFailure() << list.pair_count() << " entries, expected " << entries;
  return ::testing::AssertionSuccess();
}

// Sets the OpenMP thread count while in scope.
class ThreadCount {
public:
  explicit ThreadCount([[maybe_unused]] int n) {
#ifdef _OPENMP
    omp_set_num_threads(n);
#endif
  }
  ~ThreadCount() {
#ifdef _OPENMP
    omp_set_num_threads(saved_);
#endif
  }
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

private:
#ifdef _OPENMP
  int saved_ = omp_get_max_threads();
#endif
};

// --- Equality with the brute force --------------------------------------------------------

enum class Shape { Cube, Slab, Rod };

Vec3 box_of(Shape s) {
  switch (s) {
  case Shape::Cube:
    return {1.0, 1.0, 1.0};
  case Shape::Slab:
    return {1.0, 0.8, 0.01};
  case Shape::Rod:
    return {1.0, 0.002, 0.002};
  }
  return {};
}

class BruteForce : public ::testing::TestWithParam<std::tuple<Index, Shape, double>> {};

TEST_P(BruteForce, ListsEqualBruteForce) {
  const auto [n, shape, skin_factor] = GetParam();
  const Cloud c = random_cloud(n, box_of(shape), 1234u + static_cast<unsigned>(n));
  const double skin = n > 0 ? skin_factor * *std::min_element(c.h.begin(), c.h.end()) : 0;
  NeighbourSearch search;
  search.build(c.x, c.h, skin);
  EXPECT_TRUE(lists_equal(search.list(), brute_force(c, skin)));
  EXPECT_LE(search.grid().count(), 2 * n + 1);
}

std::string brute_force_name(const ::testing::TestParamInfo<BruteForce::ParamType>& info) {
  const auto [n, shape, skin] = info.param;
  const char* shapes[] = {"cube", "slab", "rod"};
  return shapes[static_cast<int>(shape)] + std::string("_n") + std::to_string(n) +
         (skin > 0 ? "_skin" : "_noskin");
}

INSTANTIATE_TEST_SUITE_P(Clouds, BruteForce,
                         ::testing::Combine(::testing::Values(1, 2, 500, 3000),
                                            ::testing::Values(Shape::Cube, Shape::Slab, Shape::Rod),
                                            ::testing::Values(0.0, 0.5)),
                         brute_force_name);

// Above parallel_min_items the rows are found on several threads: still the brute force, and
// bit-identical lists for 1 and 2 threads, for a random numbering and one along x.
TEST(NeighbourSearch, ParallelBuildEqualsBruteForceAndIsThreadCountIndependent) {
  const Cloud c = random_cloud(9000, {1.0, 0.5, 0.3}, 99u);
  const double skin = 0.3 * c.h[0];
  NeighbourSearch one, two;
  const Cloud by_x = permuted(c, along_x(c));
  for (const Cloud* cloud : {&c, &by_x}) {
    {
      const ThreadCount serial(1);
      one.build(cloud->x, cloud->h, skin);
    }
    {
      const ThreadCount parallel(2);
      two.build(cloud->x, cloud->h, skin);
    }
    EXPECT_TRUE(one.list().offsets == two.list().offsets);
    EXPECT_TRUE(one.list().neighbours == two.list().neighbours);
    EXPECT_TRUE(lists_equal(two.list(), brute_force(*cloud, skin)));
  }
}

// A build of some rows (a distributed run's: a rank's region and a few rows elsewhere) gives
// those rows the brute force's and leaves the others empty, for a random numbering and one along
// x, on 1 and 2 threads alike; its rebuild condition is the whole build's. Relisting from the
// last build gives the same rows, and frees the longer lists.
TEST(NeighbourSearch, SomeRowsListedEqualBruteForceAndTheOthersAreEmpty) {
  const Cloud c = random_cloud(5000, {1.0, 0.5, 0.3}, 7u); // above parallel_min_items
  const double skin = 0.3 * c.h[0];
  NeighbourSearch whole;
  const Cloud by_x = permuted(c, along_x(c));
  for (const Cloud* cloud : {&c, &by_x}) {
    const auto n = static_cast<Index>(cloud->x.size());
    std::vector<unsigned char> listed(n, 0);
    Index listed_count = 0;
    for (Index i = 0; i < n; ++i) {
      listed[i] = cloud->x[i].x() < 0.3 || i % 97 == 0;
      listed_count += listed[i];
    }
    ASSERT_GT(listed_count, n / 5);
    ASSERT_LT(listed_count, n / 2);
    const Rows expected = brute_force(*cloud, skin, listed);
    NeighbourSearch one, two;
    {
      const ThreadCount serial(1);
      one.build(cloud->x, cloud->h, skin, {listed, {}, {}});
    }
    {
      const ThreadCount parallel(2);
      two.build(cloud->x, cloud->h, skin, {listed, {}, {}});
    }
    EXPECT_TRUE(lists_equal(one.list(), expected));
    EXPECT_TRUE(one.list().offsets == two.list().offsets);
    EXPECT_TRUE(one.list().neighbours == two.list().neighbours);

    whole.build(cloud->x, cloud->h, skin);
    Cloud moved = *cloud;
    moved.x[n - 1] += Vec3(0.6 * skin, 0, 0);
    moved.x[n / 2] -= Vec3(0.6 * skin, 0, 0);
    EXPECT_TRUE(one.needs_update(moved.x, moved.h));
    EXPECT_FALSE(one.needs_update(cloud->x, cloud->h));

    const std::size_t whole_entries = whole.list().pair_count();
    whole.free_lists();
    whole.build(cloud->x, cloud->h, skin, {listed, {}, {}});
    EXPECT_TRUE(lists_equal(whole.list(), expected));
    EXPECT_LT(whole.list().neighbours.capacity(), whole_entries / 2);
  }
}

// Rows listed when near a listed row (the surface contact's corners near a rank's rows): every
// such row within two cutoffs of a listed row has the brute force's row; rows marked by neither
// flag are empty, and those farther are either.
TEST(NeighbourSearch, RowsListedIfNearAListedRow) {
  const Cloud c = random_cloud(3000, {1.0, 0.5, 0.3}, 11u);
  const auto n = static_cast<Index>(c.x.size());
  const double skin = 0.3 * c.h[0];
  std::vector<unsigned char> listed(n, 0), if_near(n, 0);
  for (Index i = 0; i < n; ++i) {
    listed[i] = c.x[i].x() < 0.25;
    if_near[i] = i % 3 == 0;
  }
  NeighbourSearch search;
  search.build(c.x, c.h, skin, {listed, if_near, {}});
  const double reach = 2 * search.cutoff();
  std::vector<unsigned char> compared(n);
  for (Index i = 0; i < n; ++i)
    compared[i] = listed[i] || if_near[i];
  const Rows all = brute_force(c, skin, compared);
  Index near_count = 0, far_listed = 0, far_count = 0;
  for (Index i = 0; i < n; ++i) {
    const auto row = search.list().of(i);
    const bool full = std::ranges::equal(row, all[i]);
    if (listed[i]) {
      EXPECT_TRUE(full) << "listed row " << i;
      continue;
    }
    if (!if_near[i]) {
      EXPECT_TRUE(row.empty()) << "row " << i << " is listed";
      continue;
    }
    bool near = false;
    for (Index j = 0; j < n && !near; ++j)
      near = listed[j] && (c.x[i] - c.x[j]).norm() < reach;
    near_count += near;
    far_count += !near;
    if (near)
      EXPECT_TRUE(full) << "row " << i << " near a listed row";
    else
      EXPECT_TRUE(full || row.empty()) << "row " << i;
    far_listed += !near && !row.empty();
  }
  EXPECT_GT(near_count, 0);
  EXPECT_LT(far_listed, far_count / 2); // the cells' margin lists some, not most
}

// Rebuilding for a stable particle count allocates nothing (counted by the operator new above),
// for a random numbering and one along x alike, of all rows or of some (a distributed run's,
// with rows listed when near them), and holds as many blocks as before.
TEST(NeighbourSearch, RebuildDoesNotAllocate) {
  const Cloud c = random_cloud(6000, {1.0, 1.0, 1.0}, 5u);
  const Cloud by_x = permuted(c, along_x(c));
  std::vector<unsigned char> rows(6000), if_near(6000);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i] = c.x[i].x() < 0.5;
    if_near[i] = i % 3 == 0;
  }
  for (const NeighbourSearch::ListedRows listed :
       {NeighbourSearch::ListedRows{}, NeighbourSearch::ListedRows{rows, if_near, {}}})
    for (const Cloud* cloud : {&c, &by_x}) {
      Cloud moved = *cloud; // the same order, every particle moved a little
      for (std::size_t i = 0; i < moved.x.size(); ++i)
        moved.x[i] += 1e-3 * Vec3(std::sin(1.0 * i), std::cos(2.0 * i), std::sin(3.0 * i));
      NeighbourSearch search;
      for (int warm_up = 0; warm_up < 3; ++warm_up) {
        search.build(cloud->x, cloud->h, 0.0, listed);
        search.build(moved.x, moved.h, 0.0, listed);
      }
      const long before = allocations.load(), held_before = held.load();
      search.build(cloud->x, cloud->h, 0.0, listed);
      search.build(moved.x, moved.h, 0.0, listed);
      search.build(cloud->x, cloud->h, 0.0, listed);
      EXPECT_FALSE(search.needs_update(cloud->x, cloud->h));
      EXPECT_EQ(allocations.load() - before, 0)
          << (listed.rows.empty() ? "all" : "some") << " rows";
      EXPECT_EQ(held.load() - held_before, 0);
    }
}

// --- Lattice ------------------------------------------------------------------------------

// Lattice of spacing Δp, h = 1.2 Δp: an interior particle has the lattice points within
// 2.4 Δp, counted here over integer offsets (56: shells |a|² = 1, 2, 3, 4, 5 of 6, 12, 8, 6, 24).
TEST(NeighbourSearch, LatticeInteriorCount) {
  const double dp = 0.01;
  const int side = 11;
  Cloud c;
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        c.x.push_back(Vec3(0.3, -0.7, 1.1) + dp * Vec3(i, j, k));
        c.h.push_back(1.2 * dp);
      }
  Index expected = 0;
  for (int a = -3; a <= 3; ++a)
    for (int b = -3; b <= 3; ++b)
      for (int d = -3; d <= 3; ++d)
        if (a * a + b * b + d * d > 0 && a * a + b * b + d * d < 2.4 * 2.4)
          ++expected;
  EXPECT_EQ(expected, 56);

  NeighbourSearch search;
  search.build(c.x, c.h, 0.0);
  for (int k = 3; k < side - 3; ++k)
    for (int j = 3; j < side - 3; ++j)
      for (int i = 3; i < side - 3; ++i) {
        const Index p = i + side * (j + side * k);
        EXPECT_EQ(static_cast<Index>(search.list().of(p).size()), expected) << "particle " << p;
      }
  EXPECT_TRUE(lists_equal(search.list(), brute_force(c, 0.0)));
}

// --- Rebuild condition --------------------------------------------------------------------

class Rebuild : public ::testing::Test {
protected:
  void SetUp() override {
    c = random_cloud(500, {1.0, 1.0, 1.0}, 7u);
    skin = 0.4 * c.h[0];
    search.build(c.x, c.h, skin);
  }
  Vec3 random_direction() {
    std::normal_distribution<double> normal;
    return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
  }
  Cloud c;
  double skin = 0;
  NeighbourSearch search;
  std::mt19937 rng{11u};
};

TEST_F(Rebuild, FalseRightAfterBuild) {
  EXPECT_FALSE(search.needs_update(c.x, c.h));
}

// A pair is missed only if the excursions e = d + Δh of its two particles sum above the skin.
TEST_F(Rebuild, DisplacementThresholds) {
  Cloud one = c;
  one.x[3] += 0.6 * skin * random_direction();
  EXPECT_FALSE(search.needs_update(one.x, one.h)); // alone, it closes a gap by 0.6 skin only
  one.x[4] += 0.6 * skin * random_direction();
  EXPECT_TRUE(search.needs_update(one.x, one.h)); // two of them: 1.2 skin

  Cloud all = c;
  for (Vec3& p : all.x)
    p += 0.4 * skin * random_direction();
  EXPECT_FALSE(search.needs_update(all.x, all.h)); // any pair: at most 0.8 skin
  Cloud far = c;
  for (Vec3& p : far.x)
    p += 0.55 * skin * random_direction();
  EXPECT_TRUE(search.needs_update(far.x, far.h));
}

TEST_F(Rebuild, SmoothingLengthThresholds) {
  Cloud one = c;
  one.h[10] += 0.9 * skin;
  EXPECT_FALSE(search.needs_update(one.x, one.h));
  one.h[10] += 0.2 * skin; // h_i alone grew by more than the skin
  EXPECT_TRUE(search.needs_update(one.x, one.h));

  Cloud all = c;
  for (double& h : all.h)
    h += 0.45 * skin;
  EXPECT_FALSE(search.needs_update(all.x, all.h)); // 2 h_ij grew by 0.9 skin
  for (double& h : all.h)
    h += 0.1 * skin;
  EXPECT_TRUE(search.needs_update(all.x, all.h));

  // Motion and growth share the budget: d ≤ skin/4 and Δh ≤ skin/4 everywhere is safe.
  Cloud both = c;
  for (Index i = 0; i < 500; ++i) {
    both.x[i] += 0.25 * skin * random_direction();
    both.h[i] += 0.24 * skin;
  }
  EXPECT_FALSE(search.needs_update(both.x, both.h));
  // Shrinking h frees budget for motion.
  both.h[0] -= 0.5 * skin;
  both.x[0] += 0.5 * skin * random_direction();
  EXPECT_FALSE(search.needs_update(both.x, both.h));
}

// The condition is tight: two particles just outside the list close in by a little more than
// half the skin each, interact, and needs_update says so.
TEST(NeighbourSearch, RebuildConditionIsTight) {
  const double h = 1.0, skin = 0.2, gap = 1e-3;
  Cloud c{{Vec3(0, 0, 0), Vec3(2 * h + skin + gap, 0, 0)}, {h, h}};
  NeighbourSearch search;
  search.build(c.x, c.h, skin);
  EXPECT_EQ(search.list().pair_count(), 0u);
  const double step = 0.5 * (skin + 2 * gap);
  c.x[0].x() += step;
  c.x[1].x() -= step;
  EXPECT_TRUE(within(c.x[0], c.x[1], h, h, 0.0)); // now within 2 h_ij but not listed
  EXPECT_TRUE(search.needs_update(c.x, c.h));
}

// Whenever needs_update is false, every pair within 2 h_ij now is in the list.
TEST_F(Rebuild, FalseImpliesNoMissingPair) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int complete = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Cloud moved = c;
    const double scale = 0.35 + 0.02 * trial; // around the threshold
    for (Index i = 0; i < 500; ++i) {
      const double share = unit(rng);
      moved.x[i] += share * scale * skin * random_direction();
      moved.h[i] += (1 - share) * scale * skin * (unit(rng) < 0.8 ? 1.0 : -1.0);
    }
    if (search.needs_update(moved.x, moved.h))
      continue;
    ++complete;
    const Rows now = brute_force(moved, 0.0);
    for (Index i = 0; i < 500; ++i) {
      const auto row = search.list().of(i);
      for (Index j : now[i])
        ASSERT_TRUE(std::binary_search(row.begin(), row.end(), j))
            << "pair " << i << ", " << j << " missing in trial " << trial;
    }
  }
  EXPECT_GT(complete, 5); // the property was exercised
}

TEST_F(Rebuild, TrueForOtherCountsNonFiniteStateAndBeforeBuild) {
  EXPECT_TRUE(NeighbourSearch().needs_update(c.x, c.h));
  Cloud more = c;
  more.x.push_back(Vec3::Zero());
  more.h.push_back(c.h[0]);
  EXPECT_TRUE(search.needs_update(more.x, more.h));
  Cloud bad = c;
  bad.x[42].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(search.needs_update(bad.x, bad.h));
  bad = c;
  bad.h[42] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(search.needs_update(bad.x, bad.h));
}

// --- Cell grid and numbering ---------------------------------------------------------------

// Cells are at least the edge asked for, at most max_cells of them, and cell_of places every
// point in the cell holding it.
TEST(NeighbourSearch, CellGridCellsHoldTheirPoints) {
  const Cloud c = random_cloud(3000, {1.0, 0.6, 0.3}, 3u);
  const double edge = 0.05;
  Vec3 lo = c.x[0], hi = c.x[0];
  for (const Vec3& p : c.x) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const CellGrid grid = CellGrid::make(lo, hi, edge, 6001);
  EXPECT_LE(grid.count(), 6001);
  for (int d = 0; d < 3; ++d)
    EXPECT_GE((hi[d] - lo[d]) / grid.n[d], edge) << "axis " << d;
  for (const Vec3& p : c.x) {
    const Index cell = grid.cell_of(p);
    const std::array<Index, 3> at{cell % grid.n[0], (cell / grid.n[0]) % grid.n[1],
                                  cell / (grid.n[0] * grid.n[1])};
    for (int d = 0; d < 3; ++d) {
      const double width = (hi[d] - lo[d]) / grid.n[d];
      EXPECT_LE(lo[d] + at[d] * width, p[d] * (1 + 1e-12));
      if (at[d] + 1 < grid.n[d]) {
        EXPECT_LT(p[d], lo[d] + (at[d] + 1) * width * (1 + 1e-12));
      }
    }
  }
}

// Cell index x fastest, the top face in the last cell, on hand-checked points.
TEST(NeighbourSearch, CellGridSmallCases) {
  // Line: extent 3.8, edge 1 → 3 cells of 1.27.
  const CellGrid line = CellGrid::make(Vec3(0.1, 0, 0), Vec3(3.9, 0, 0), 1.0, 11);
  EXPECT_EQ(line.count(), 3);
  for (const auto& [x, cell] :
       std::vector<std::pair<double, Index>>{{2.5, 1}, {0.1, 0}, {1.7, 1}, {0.2, 0}, {3.9, 2}})
    EXPECT_EQ(line.cell_of(Vec3(x, 0, 0)), cell) << "x = " << x;
  // Unit cube, edge 0.5 → 2 cells per axis.
  const CellGrid cube = CellGrid::make(Vec3::Zero(), Vec3::Ones(), 0.5, 9);
  EXPECT_EQ(cube.cell_of(Vec3(0, 1, 0)), 2);
  EXPECT_EQ(cube.cell_of(Vec3(1, 0, 0)), 1);
  EXPECT_EQ(cube.cell_of(Vec3(0, 0, 0)), 0);
  EXPECT_EQ(cube.cell_of(Vec3(1, 1, 1)), 7);
}

// Renumbered particles give the same pairs, relabelled, each row sorted by the new numbers.
TEST(NeighbourSearch, ReorderedParticlesGiveRelabelledLists) {
  const Cloud c = random_cloud(2000, {1.0, 1.0, 0.5}, 17u);
  NeighbourSearch search;
  search.build(c.x, c.h, 0.0);
  const std::vector<Index> new_to_old = along_x(c);
  const Cloud sorted = permuted(c, new_to_old);
  std::vector<Index> old_to_new(c.x.size());
  for (Index k = 0; k < static_cast<Index>(new_to_old.size()); ++k)
    old_to_new[new_to_old[k]] = k;
  NeighbourSearch resorted;
  resorted.build(sorted.x, sorted.h, 0.0);
  for (Index i = 0; i < 2000; ++i) {
    std::vector<Index> mapped;
    for (Index j : search.list().of(i))
      mapped.push_back(old_to_new[j]);
    std::sort(mapped.begin(), mapped.end());
    const auto row = resorted.list().of(old_to_new[i]);
    ASSERT_TRUE(std::equal(row.begin(), row.end(), mapped.begin(), mapped.end())) << i;
  }
}

// What a distributed rank's rows rest on: the points of a region and of its halo, numbered in
// the whole's relative order, list each row of the region as the whole does — the same
// neighbours in the same order, so a sum over a row runs alike — for the whole numbered along x
// or at random, and with a few points swapped (the insertion sort's path).
TEST(NeighbourSearch, SubsetNumberedAlikeListsRowsInTheSameOrder) {
  const Cloud c = random_cloud(4000, {1.0, 0.5, 0.3}, 23u);
  const double skin = 0.3 * c.h[0];
  Cloud swapped = permuted(c, along_x(c));
  std::mt19937 rng(5u);
  std::uniform_int_distribution<Index> pick(0, 3999);
  for (int swap = 0; swap < 20; ++swap) {
    const Index a = pick(rng), b = pick(rng);
    std::swap(swapped.x[a], swapped.x[b]);
    std::swap(swapped.h[a], swapped.h[b]);
  }
  const Cloud by_x = permuted(c, along_x(c));
  for (const Cloud* whole : {&c, &by_x, static_cast<const Cloud*>(&swapped)}) {
    NeighbourSearch all;
    all.build(whole->x, whole->h, skin);
    const double reach = all.cutoff();
    std::vector<Index> kept; // the region x < 0.4 and the points within a cutoff of it
    std::vector<unsigned char> region;
    for (Index i = 0; i < 4000; ++i)
      if (whole->x[i].x() < 0.4 + reach) {
        kept.push_back(i);
        region.push_back(whole->x[i].x() < 0.4);
      }
    ASSERT_LT(kept.size(), 3000u);
    NeighbourSearch part;
    part.build(permuted(*whole, kept).x, permuted(*whole, kept).h, skin, {region, {}, {}});
    for (std::size_t k = 0; k < kept.size(); ++k) {
      if (!region[k])
        continue;
      std::vector<Index> mapped;
      for (Index j : part.list().of(static_cast<Index>(k)))
        mapped.push_back(kept[j]);
      const auto row = all.list().of(kept[k]);
      ASSERT_TRUE(std::equal(row.begin(), row.end(), mapped.begin(), mapped.end()))
          << "row " << kept[k];
    }
  }
}

// A build binning some points only (a distributed rank's rows and those near them, in the
// whole's numbering) lists its rows as a build of all does, and never reads the other points:
// here they are poisoned — half with non-finite positions and negative h, which a build reading
// them rejects, half moved among the listed rows, which a build binning them would list.
TEST(NeighbourSearch, BinningTheRowsNearTheListedOnesListsThemAsTheWhole) {
  const Cloud c = random_cloud(4000, {1.0, 0.5, 0.3}, 13u);
  const double skin = 0.3 * c.h[0];
  const Cloud by_x = permuted(c, along_x(c));
  for (const Cloud* whole : {&c, &by_x}) {
    NeighbourSearch all;
    all.build(whole->x, whole->h, skin);
    const double reach = all.cutoff();
    Cloud poisoned = *whole;
    std::vector<unsigned char> listed(4000), binned(4000);
    Index binned_count = 0;
    for (Index i = 0; i < 4000; ++i) {
      listed[i] = whole->x[i].x() > 0.7;
      binned[i] = whole->x[i].x() > 0.7 - reach;
      binned_count += binned[i];
      if (!binned[i] && i % 2 == 0) {
        poisoned.x[i] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
        poisoned.h[i] = -1;
      } else if (!binned[i]) {
        poisoned.x[i] = Vec3(0.85, 0.25, 0.15) + 1e-6 * static_cast<double>(i) * Vec3::Ones();
      }
    }
    ASSERT_LT(binned_count, 2000);
    const std::vector<unsigned char> every(4000, 1);
    for (const bool if_near : {false, true}) { // rows marked if near: none binned is listed
      NeighbourSearch part;
      part.build(poisoned.x, poisoned.h, skin,
                 {listed, if_near ? std::span(every) : std::span<const unsigned char>(), binned});
      EXPECT_LE(part.grid().count(), 2 * binned_count + 1);
      for (Index i = 0; i < 4000; ++i) {
        if (if_near && binned[i] && !listed[i])
          continue; // listed or not, as the cells decide
        const auto expected = listed[i] ? all.list().of(i) : std::span<const Index>();
        const auto row = part.list().of(i);
        ASSERT_TRUE(std::equal(row.begin(), row.end(), expected.begin(), expected.end()))
            << "row " << i;
      }
    }
  }
}

// --- Degenerate inputs --------------------------------------------------------------------

TEST(NeighbourSearch, EmptyAndSingle) {
  NeighbourSearch search;
  search.build({}, {}, 0.1);
  EXPECT_EQ(search.list().offsets, std::vector<Index>{0});
  EXPECT_EQ(search.list().pair_count(), 0u);
  EXPECT_FALSE(search.needs_update({}, {}));

  const std::vector<Vec3> x{Vec3(1, 2, 3)};
  const std::vector<double> h{0.5};
  search.build(x, h, 0.1);
  EXPECT_EQ(search.list().offsets, (std::vector<Index>{0, 0}));
  EXPECT_FALSE(search.needs_update(std::vector<Vec3>{Vec3(50, 2, 3)}, h)); // no pair to miss
}

TEST(NeighbourSearch, AllParticlesAtOnePoint) {
  Cloud c;
  for (Index i = 0; i < 60; ++i) {
    c.x.emplace_back(0.5, 0.5, 0.5);
    c.h.push_back(0.01 * (1 + i % 3));
  }
  NeighbourSearch search;
  search.build(c.x, c.h, 0.0);
  EXPECT_EQ(search.list().pair_count(), 60u * 59u);
  EXPECT_TRUE(lists_equal(search.list(), brute_force(c, 0.0)));
  EXPECT_EQ(search.grid().count(), 1);
  // With zero cutoff nothing is within r < 0.
  std::fill(c.h.begin(), c.h.end(), 0.0);
  search.build(c.x, c.h, 0.0);
  EXPECT_EQ(search.list().pair_count(), 0u);
}

TEST(NeighbourSearch, ZeroCutoffOnSpreadPoints) {
  Cloud c = random_cloud(5000, {1.0, 1.0, 1.0}, 8u);
  std::fill(c.h.begin(), c.h.end(), 0.0);
  NeighbourSearch search;
  search.build(c.x, c.h, 0.0);
  EXPECT_EQ(search.list().pair_count(), 0u);
  EXPECT_LE(search.grid().count(), 2 * 5000 + 1);
}

// A few far-flung particles (up to an overflowing extent) must not blow up the grid: cells
// stay ≤ 2N + 1, lists stay right.
TEST(NeighbourSearch, HugeBoundingBoxFewParticles) {
  Cloud c = random_cloud(300, {0.01, 0.01, 0.01}, 21u);
  for (const Vec3& far : {Vec3(1e9, 0, 0), Vec3(0, -1e12, 3e11), Vec3(1.5e308, 0, 0),
                          Vec3(-1.5e308, 1.5e308, 0), Vec3(1e9 + 1e-5, 0, 0)}) {
    c.x.push_back(far);
    c.h.push_back(c.h[0]);
  }
  NeighbourSearch search;
  search.build(c.x, c.h, 0.1 * c.h[0]);
  EXPECT_LE(search.grid().count(), 2 * 305 + 1);
  const Rows expected = brute_force(c, 0.1 * c.h[0]);
  EXPECT_EQ(expected[300], std::vector<Index>{304}); // the two far neighbours find each other
  EXPECT_TRUE(lists_equal(search.list(), expected));
}

TEST(NeighbourSearch, InvalidInputThrowsNamingTheParticle) {
  Cloud c = random_cloud(5000, {1.0, 1.0, 1.0}, 4u); // above parallel_min_items
  NeighbourSearch search;
  const auto message = [&](const Cloud& bad, double skin) -> std::string {
    try {
      search.build(bad.x, bad.h, skin);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  Cloud bad = c;
  bad.x[4321].z() = std::numeric_limits<double>::quiet_NaN();
  bad.x[4400].x() = std::numeric_limits<double>::infinity();
  EXPECT_NE(message(bad, 0.0).find("particle 4321 "), std::string::npos) << message(bad, 0.0);
  EXPECT_TRUE(search.needs_update(c.x, c.h)); // a failed build leaves no list to trust

  bad = c;
  bad.h[17] = -1.0;
  EXPECT_NE(message(bad, 0.0).find("particle 17 "), std::string::npos) << message(bad, 0.0);
  bad.h[17] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(bad, 0.0).find("particle 17 "), std::string::npos);
  EXPECT_NE(message(c, -0.1).find("skin"), std::string::npos);
  bad = c;
  bad.h.pop_back();
  EXPECT_THROW(search.build(bad.x, bad.h, 0.0), Error);
}

} // namespace
