// Neighbour search for SPH (METHOD.md §2): a cell list and full Verlet neighbour lists in
// compressed rows for the cubic B-spline of support 2 h_ij, h_ij = (h_i + h_j)/2, with
// variable h. A pair (i, j ≠ i) is listed when |x_i − x_j| < h_i + h_j + skin at build time;
// force loops still test r < 2 h_ij themselves. Lengths in metres.
// Verified by tests/sph/neighbour_search_test.cpp (equality with an O(N²) brute force, lattice
// counts, the rebuild condition, thread-count independence); timed by bench/neighbour_search.cpp.
//
// Rebuild condition (needs_update). Let x⁰, h⁰ be the build-time state, d_i = |x_i − x⁰_i| and
// g_i = h_i − h⁰_i. A pair missing from the list had r⁰ = |x⁰_i − x⁰_j| ≥ h⁰_i + h⁰_j + skin.
// It interacts now if r < h_i + h_j. By the triangle inequality r ≥ r⁰ − d_i − d_j, so that needs
//   h⁰_i + g_i + h⁰_j + g_j > r⁰ − d_i − d_j ≥ h⁰_i + h⁰_j + skin − d_i − d_j,
// i.e. e_i + e_j > skin with e_i = d_i + g_i. So the list is complete as long as the two largest
// e_i sum to at most skin; needs_update() returns e_(1) + e_(2) > skin. This is sharper than the
// usual "any d_i > skin/2" (one particle alone may move up to a whole skin) and, unlike a test
// on max h, catches a small-h particle whose h grows while max h does not. It also implies the
// common split: d_i ≤ skin/4 and g_i ≤ skin/4 for all i is safe. Rounding at r = 2 h_ij is
// harmless: W and ∇W vanish there as (2 − q)³ and (2 − q)².
#pragma once

#include "solver/core/types.hpp"
#include "solver/io/state_archive.hpp"

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace sphfem {

// Full neighbour lists in compressed rows: row i holds every j ≠ i within the build cutoff,
// sorted ascending. Full (each pair appears in both rows) so that force loops can gather per
// particle without races. A build for some rows only (a distributed run's) leaves the others
// empty.
struct NeighbourList {
  std::vector<Index> offsets;    // particle count + 1
  std::vector<Index> neighbours; // the j's, grouped by i

  std::span<const Index> of(Index i) const {
    return {neighbours.data() + offsets[i], neighbours.data() + offsets[i + 1]};
  }
  // Number of (i, j) entries: each unordered pair counts twice.
  std::size_t pair_count() const { return neighbours.size(); }
  Index particle_count() const {
    return offsets.empty() ? 0 : static_cast<Index>(offsets.size()) - 1;
  }
};

// The bounding box [lo, hi] of a point set cut into n[0] × n[1] × n[2] cells of edge ≥ min_edge,
// indexed x fastest. Cells are enlarged when needed to keep at most max_cells of them, so a
// huge box holding few points costs no memory.
struct CellGrid {
  Vec3 lo = Vec3::Zero();
  Vec3 scale = Vec3::Zero(); // cells per metre along each axis
  std::array<Index, 3> n{1, 1, 1};

  static CellGrid make(const Vec3& lo, const Vec3& hi, double min_edge, Index max_cells);
  Index count() const { return n[0] * n[1] * n[2]; }
  Index cell_of(const Vec3& x) const;
};

// Cell list + Verlet list. A build bins the particles into cells of edge ≥ cutoff/search_reach
// (counting sort), finds each pair once in a half stencil of the sorted points, completes each
// row from the half rows that list it, and sorts each row by original index. So a row's order,
// hence the order of every sum over it, is the numbering's alone: a subset of the points numbered
// in the same relative order (a distributed run's rank) lists its rows in the same order.
// Buffers are reused, so rebuilding for a stable particle count does not allocate.
// Deterministic: the lists do not depend on the thread count.
//
// Room for passive candidates (FE nodes as background particles, searched only as neighbours):
// they would be binned by a second Bins over the same CellGrid and give a second NeighbourList
// (active i → passive j) with no half-list symmetry; nothing of that is built yet.
class NeighbourSearch {
public:
  // Fills the lists for positions x and smoothing lengths h (skin ≥ 0, in metres). O(N),
  // parallel over cells. Throws sphfem::Error naming the particle for a non-finite position or
  // a negative or non-finite h, and for a negative skin or mismatched sizes.
  // The rows a build lists (one flag per point): those `rows` marks (empty: all), and those
  // `if_near` marks when within two cutoffs of one of them (a coupling reading the lists of
  // rows near a distributed run's own: the surface contact's face corners). Listed rows are
  // those of a build of all, the others empty. The search visits only the cells within reach of
  // a listed point. "Within two cutoffs" is decided by cells: some rows farther are listed too.
  // `binned` (empty: all) marks the points binned at all: the others are in no list and their
  // positions are not read (a distributed run's rank bins the rows near its own; the caller
  // makes sure that every point within reach of a listed row is binned).
  struct ListedRows {
    std::span<const unsigned char> rows;
    std::span<const unsigned char> if_near;
    std::span<const unsigned char> binned;
  };
  void build(std::span<const Vec3> x, std::span<const double> h, double skin,
             ListedRows listed = {});

  // True when the list may be missing a pair (see the rebuild condition above), when the
  // particle count changed, before the first build, and for non-finite x or h.
  bool needs_update(std::span<const Vec3> x, std::span<const double> h) const;
  // The same in parts, for a distributed run whose ranks each know some of the points: whether
  // the list was built for this many points; the two largest e_i over the points `counted`
  // marks (all when empty); pairs of them (one per rank) merged; whether a pair asks for a
  // rebuild (also when infinite: a non-finite state).
  bool built_for(std::span<const Vec3> x, std::span<const double> h) const;
  bool built() const { return built_; }
  std::array<double, 2> largest_excursions(std::span<const Vec3> x, std::span<const double> h,
                                           std::span<const unsigned char> counted = {}) const;
  static std::array<double, 2> merge_excursions(std::span<const double> pairs);
  bool exceeds_skin(const std::array<double, 2>& top) const;

  const NeighbourList& list() const { return list_; }
  double skin() const { return skin_; }
  // Largest pair cutoff at the last build: 2 max h + skin.
  double cutoff() const { return cutoff_; }
  const CellGrid& grid() const { return grid_; }

  // The build-time positions and smoothing lengths (the rebuild condition's reference): for a
  // distributed run's gather (each owner's rows were binned at the build) and to list other rows
  // of that build (a new cut, a checkpoint read).
  template <class Visit> void for_each_build_field(Visit visit) {
    visit("x_build", x_build_);
    visit("h_build", h_build_);
  }
  std::span<const Vec3> build_positions() const { return x_build_; }
  std::span<const double> build_smoothing_lengths() const { return h_build_; }

  // Checkpoint: the build-time positions, smoothing lengths and skin, and whether built. After
  // reading, the caller builds the lists from them (a build is deterministic: the very lists of
  // that build). persist_through passes the arrays through array(name, field) instead (a
  // distributed run writes every rank's rows).
  void persist(StateArchive& a) {
    persist_through(a, [&a](const std::string& name, auto& field) { a.array(name, field); });
  }
  template <class Array> void persist_through(StateArchive& a, Array array) {
    for_each_build_field([&array](const char* name, auto& field) {
      array(std::string("neighbours/") + name, field);
    });
    a.value("neighbours/skin", skin_);
    a.value("neighbours/built", built_);
  }
  // Frees the lists' memory (before a build that lists fewer rows than the last).
  void free_lists();

private:
  struct Point {
    double x, y, z, h;
  };
  // Points sorted by cell (counting sort, stable in the original index).
  struct Bins {
    std::vector<Index> cell_start; // grid cells + 1
    std::vector<Index> order;      // sorted position → original index
    std::vector<Point> points;     // x, h in sorted order
    std::vector<Index> cell;       // cell of each original index (scratch)
  };
  // Half lists in sorted positions: for each sorted point k, the m > k within the cutoff,
  // ascending. A thread's rows are in its own buffer: entries[0, used) are filled and entries
  // only grows (no allocation once stable). Padded so that two threads never share a line.
  struct alignas(64) UpperBuffer {
    std::vector<Index> entries;
    std::size_t used = 0;
  };
  struct HalfLists {
    std::vector<UpperBuffer> buffers; // one per thread
    std::vector<Index> first;         // first sorted point of each thread, threads + 1
    std::vector<std::size_t> at;      // row k starts at buffers[owner].entries[at[k]]
    std::vector<Index> count;         // length of row k
    std::vector<Index> lower;         // rows k' < k listing k: count, then write cursor
  };
  // Cells searched on each side of a particle's own cell. Smaller cells test fewer candidates
  // ((2r + 1)³/r³ cutoff³: 27, 15.6, 12.7 for r = 1, 2, 3) over more, shorter spans; measured
  // on the benchmark's lattice, r = 2 builds fastest (r = 1 and r = 3: ~1.2× slower).
  static constexpr Index search_reach = 2;

  void bin(std::span<const Vec3> x, std::span<const double> h,
           std::span<const unsigned char> binned);
  void mark_listed(ListedRows listed);
  void cells_within(std::span<const unsigned char> points, Index cells,
                    std::vector<unsigned char>& near);
  void fill_rows();
  void search_upper(Index c, UpperBuffer& rows);
  std::span<const Index> upper_row(Index k, int thread, int threads) const;

  CellGrid grid_;
  Bins bins_;
  HalfLists half_;
  NeighbourList list_;
  std::vector<unsigned char> listed_;   // per point, when not all are listed: 1 if listed
  std::vector<unsigned char> searched_; // per cell, when not all are listed: within reach of one
  std::vector<unsigned char> near_;     // per cell: within two cutoffs of a listed point (scratch)
  std::vector<unsigned char> dilated_;  // per cell (cells_within's scratch)
  std::vector<Vec3> x_build_;
  std::vector<double> h_build_;
  double skin_ = 0;
  double cutoff_ = 0;
  bool built_ = false;
};

} // namespace sphfem
