// Which lattice points a closed triangulated surface encloses: the vertical line of each lattice
// column (i, j) is intersected with the triangles over it; a cell centre is inside when an odd
// number of crossings lie below it.
//
// Robustness: whether the line (px, py) passes a projected triangle is decided edge by edge, and
// each edge is evaluated from its lower-index vertex, so the two triangles sharing an edge see
// exactly the same number. Lines exactly through an edge or vertex (common: lattice columns
// often line up with structured surface meshes) are moved by the symbolic perturbation
// p + (ε, ε²), which puts them on one definite side of every edge. Triangles seen edge-on are
// then never crossed. So the line crosses each sheet of the surface exactly once and the parity
// is exact for any closed surface. Verified by tests/mesher/lattice_test.cpp.
#include "mesher/lattice.hpp"

#include "solver/core/error.hpp"

#include <algorithm>
#include <cmath>

namespace sphfem::mesher {
namespace {

// Twice the signed area of (a, b, p) in the xy-plane.
double orient(const Vec3& a, const Vec3& b, double px, double py) {
  return (b.x() - a.x()) * (py - a.y()) - (b.y() - a.y()) * (px - a.x());
}

// Side of the point (px, py) + (ε, ε²) of the directed edge u → v: +1 left, −1 right, never 0.
// `area` receives the unperturbed orient(u, v, p).
int side(const Triangulation& s, Index u, Index v, double px, double py, double& area) {
  const bool flip = u > v;
  const Vec3& a = s.x[flip ? v : u];
  const Vec3& b = s.x[flip ? u : v];
  const double o = orient(a, b, px, py);
  int sign = 0;
  if (o != 0)
    sign = o > 0 ? 1 : -1;
  else if (b.y() != a.y()) // orient(a, b, p + (ε, ε²)) = −(b_y − a_y) ε + (b_x − a_x) ε²
    sign = b.y() > a.y() ? -1 : 1;
  else
    sign = b.x() > a.x() ? 1 : -1;
  area = flip ? -o : o;
  return flip ? -sign : sign;
}

// If the vertical line through (px, py) crosses triangle t, sets z to the crossing height.
bool crossing(const Triangulation& s, const std::array<Index, 3>& t, double px, double py,
              double& z) {
  std::array<double, 3> w{}; // w[c]: area of the sub-triangle opposite corner c
  const int s0 = side(s, t[1], t[2], px, py, w[0]);
  const int s1 = side(s, t[2], t[0], px, py, w[1]);
  const int s2 = side(s, t[0], t[1], px, py, w[2]);
  if (s0 != s1 || s1 != s2)
    return false;
  const Vec3 &a = s.x[t[0]], &b = s.x[t[1]], &c = s.x[t[2]];
  const double low = std::min({a.z(), b.z(), c.z()}), high = std::max({a.z(), b.z(), c.z()});
  const double sum = w[0] + w[1] + w[2];
  z = sum != 0 ? (w[0] * a.z() + w[1] * b.z() + w[2] * c.z()) / sum : (a.z() + b.z() + c.z()) / 3;
  z = std::clamp(z, low, high);
  return true;
}

// Triangles by lattice column (compressed rows): every triangle whose xy bounds reach the column,
// with one column to spare each side against rounding (the crossing test decides exactly).
struct ColumnBins {
  std::vector<std::size_t> start; // n0·n1 + 1
  std::vector<Index> triangle;
};

ColumnBins bin_triangles(const Triangulation& s, const Lattice& l) {
  const std::size_t columns = static_cast<std::size_t>(l.n[0]) * static_cast<std::size_t>(l.n[1]);
  // Column range [lo, hi] of the triangle along axis a (empty if lo > hi).
  const auto range = [&](const std::array<Index, 3>& t, int a, Index& lo, Index& hi) {
    const double x0 = std::min({s.x[t[0]][a], s.x[t[1]][a], s.x[t[2]][a]});
    const double x1 = std::max({s.x[t[0]][a], s.x[t[1]][a], s.x[t[2]][a]});
    const double from = std::ceil((x0 - l.first[a]) / l.step[a]) - 1;
    const double to = std::floor((x1 - l.first[a]) / l.step[a]) + 1;
    lo = static_cast<Index>(std::clamp<double>(from, 0, l.n[a]));
    hi = static_cast<Index>(std::clamp<double>(to, -1, l.n[a] - 1));
  };
  ColumnBins bins;
  bins.start.assign(columns + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::size_t> fill;
    if (pass == 1) {
      for (std::size_t c = 0; c < columns; ++c)
        bins.start[c + 1] += bins.start[c];
      bins.triangle.resize(bins.start.back());
      fill.assign(bins.start.begin(), bins.start.end() - 1);
    }
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      Index i0 = 0, i1 = 0, j0 = 0, j1 = 0;
      range(s.triangles[t], 0, i0, i1);
      range(s.triangles[t], 1, j0, j1);
      for (Index i = i0; i <= i1; ++i)
        for (Index j = j0; j <= j1; ++j) {
          const std::size_t c = static_cast<std::size_t>(i) * l.n[1] + j;
          if (pass == 0)
            ++bins.start[c + 1];
          else
            bins.triangle[fill[c]++] = static_cast<Index>(t);
        }
    }
  }
  return bins;
}

} // namespace

void mark_enclosed(const Triangulation& surface, const Lattice& l, std::vector<char>& enclosed) {
  SPHFEM_CHECK(enclosed.size() == l.cell_count(), "mark_enclosed: ", enclosed.size(), " flags for ",
               l.cell_count(), " cells");
  for (const auto& t : surface.triangles)
    for (const Index v : t)
      SPHFEM_CHECK(v >= 0 && static_cast<std::size_t>(v) < surface.x.size(),
                   "mark_enclosed: triangle vertex ", v, " out of range");
  const ColumnBins bins = bin_triangles(surface, l);
  std::vector<double> heights;
  for (Index i = 0; i < l.n[0]; ++i)
    for (Index j = 0; j < l.n[1]; ++j) {
      const std::size_t column = static_cast<std::size_t>(i) * l.n[1] + j;
      const Vec3 bottom = l.centre(i, j, 0);
      heights.clear();
      for (std::size_t b = bins.start[column]; b < bins.start[column + 1]; ++b) {
        double z = 0;
        if (crossing(surface, surface.triangles[bins.triangle[b]], bottom.x(), bottom.y(), z))
          heights.push_back(z);
      }
      if (heights.empty())
        continue;
      std::sort(heights.begin(), heights.end());
      std::size_t below = 0; // crossings below the current centre
      char* flags = enclosed.data() + column * static_cast<std::size_t>(l.n[2]);
      for (Index k = 0; k < l.n[2]; ++k) {
        const double z = l.first.z() + k * l.step.z();
        while (below < heights.size() && heights[below] < z)
          ++below;
        if (below % 2 == 1)
          flags[k] = 1;
      }
    }
}

} // namespace sphfem::mesher
