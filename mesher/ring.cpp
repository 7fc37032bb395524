// Structured hex mesh of a plate ring (RingGeometry): the O-grid around a square hole that an SPH
// core fills. In plan the ring is cut by the rays at k·45° from the vertical axis through `base`
// into 45° sectors (full ring: the 8 sectors k = 0 … 7; half: the 4 between 0° and 180°;
// quarter: the 2 between 0° and 90°, so its mesh is exactly the y ≥ base.y or the x ≥ base.x,
// y ≥ base.y part of the full ring's). Each sector is a
// transfinite, recombined quadrilateral between the piece of the hole's side and the 45° rim arc
// that the two rays cut out, extruded through the thickness in uniform layers; the sectors share
// their points and curves, so the mesh is conforming. Faces inner (the hole's sides), rim, bottom
// (z = base.z), top; a half also ymin (y = base.y), a quarter xmin (x = base.x) and ymin.
//
// Element counts (h = element_size, a = half_width, R = radius, t = thickness):
//   n_s = max(1, round(a/h)) along each sector's piece of the hole side (length a) and its rim
//     arc (length πR/4), uniform. A `lattice: nodes` SPH box of spacing h filling the hole has
//     round(2a/h) cells across (quarter: round(a/h)), which is 2·n_s unless a/h ends in .5 (an
//     error for the full ring): then its nodes on the hole's sides are the ring's inner nodes.
//   layers = max(1, round(t/h)), uniform, also as in the lattice.
//   n_r along each spoke (the radial sector edges), growing geometrically from h at the hole to
//     about s at the rim, s = rim_element_size, or if that is 0 the rim arc's element πR/(4 n_s).
//     With the mean spoke length L = R − a(1 + √2)/2 (the spokes on the axes are R − a long, on
//     the diagonals R − a√2), the progression with first element h and last s sums to L with
//     ratio q* = (L − h)/(L − s) and 1 + ln(s/h)/ln q* elements: n_r is that rounded (at least
//     1; uniform, round(L/h), if s = h or L ≤ max(h, s)). Each spoke then gets the ratio q with
//     h(1 + q + … + q^(n_r − 1)) = its length, so its first element is exactly h, and its last,
//     h q^(n_r − 1), is a few % off s: larger on the axes, smaller on the diagonals, whose
//     lengths differ from L by ±a(√2 − 1)/2 (a = 24 mm, R = 250 mm, h = 2 … 0.75 mm: last/s =
//     1.03–1.04 on the axes, 0.96–0.97 on the diagonals). Inside a sector gmsh's transfinite
//     interpolation blends the two spokes. The hexes at the hole's corners have a 45° angle in
//     plan (scaled corner Jacobian 1/√2), as in any O-grid around a square.
//   hexahedra = sectors · n_s · n_r · layers (sectors = 8, 4 or 2); nodes 8 n_s (n_r + 1)(layers +
//     1) for the full ring, (sectors · n_s + 1)(n_r + 1)(layers + 1) for a half or a quarter.
// Verified by tests/mesher/ring_test.cpp.
#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace sphfem::mesher {
namespace {

namespace geo = gmsh::model::geo;

// The ray at k·45°, as the integer direction whose larger component is 1, so its hits on the
// hole (a times it) and on the planes x = 0, y = 0 are exact.
constexpr std::array<std::array<int, 2>, 8> ray{
    {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}}};

struct RingPlan {
  int sectors = 8;
  int along = 1, radial = 1, layers = 1; // n_s, n_r, layers
  // Growth of successive elements along the spokes from the hole outwards: on the axes (even
  // rays) and on the diagonals (odd rays).
  std::array<double, 2> ratio{1, 1};
};

// The q > 0 with first · (1 + q + … + q^(n−1)) = length, for n ≥ 2 and length > first.
double progression_ratio(int n, double first, double length) {
  const double target = length / first;
  const auto sum = [n](double q) {
    double s = 0;
    for (int i = 0; i < n; ++i)
      s = s * q + 1;
    return s;
  };
  double low = 0, high = target; // sum(0) = 1 < target < 1 + target ≤ sum(target)
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (sum(mid) < target ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

// Elements of a progression from `first` to about `last` over `length` (header comment).
int radial_count(double length, double first, double last) {
  if (length <= std::max(first, last) || std::abs(std::log(last / first)) < 1e-9)
    return divisions(length, first);
  const double n = 1 + std::log(last / first) / std::log((length - first) / (length - last));
  SPHFEM_CHECK(n < 1e6, "element_size ", first, " m gives ", n, " elements across the ring");
  return std::max(1, static_cast<int>(std::lround(n)));
}

RingPlan plan(const RingGeometry& g, double h) {
  SPHFEM_CHECK(g.base.allFinite(), "ring base must be finite");
  SPHFEM_CHECK(g.half_width > 0 && std::isfinite(g.half_width),
               "ring half_width must be positive, got ", g.half_width);
  SPHFEM_CHECK(g.thickness > 0 && std::isfinite(g.thickness),
               "ring thickness must be positive, got ", g.thickness);
  SPHFEM_CHECK(g.rim_element_size >= 0 && std::isfinite(g.rim_element_size),
               "ring rim_element_size must be positive or 0, got ", g.rim_element_size);
  const double axis_spoke = g.radius - g.half_width;
  const double diagonal_spoke = g.radius - std::numbers::sqrt2 * g.half_width;
  // Room for the first element h and one more between the hole's corners and the rim.
  SPHFEM_CHECK(std::isfinite(g.radius) && diagonal_spoke >= 2 * h, "ring radius ", g.radius,
               " m must exceed half_width·√2 = ", std::numbers::sqrt2 * g.half_width,
               " m (the hole's corners) by at least 2 element sizes (", 2 * h, " m)");
  RingPlan p;
  p.sectors = g.sector == Sector::Full ? 8 : g.sector == Sector::Half ? 4 : 2;
  p.along = divisions(g.half_width, h);
  const double cells = g.half_width / h;
  SPHFEM_CHECK(g.sector == Sector::Quarter || std::abs(cells - std::floor(cells) - 0.5) > 1e-6,
               "half_width / element_size = ", cells,
               " must not end in .5: a lattice of that spacing across the hole would have ",
               std::round(2 * cells), " cells, not 2 · ", p.along);
  p.layers = divisions(g.thickness, h);
  const double rim =
      g.rim_element_size > 0 ? g.rim_element_size : 0.25 * std::numbers::pi * g.radius / p.along;
  p.radial = radial_count(0.5 * (axis_spoke + diagonal_spoke), h, rim);
  if (p.radial > 1)
    p.ratio = {progression_ratio(p.radial, h, axis_spoke),
               progression_ratio(p.radial, h, diagonal_spoke)};
  return p;
}

// The ring's plan at z = 0 (local frame, base at the origin): one quadrilateral surface per
// sector, loop counter-clockwise about +z; spokes run from the hole to the rim.
struct Sectors {
  std::vector<int> surfaces, spokes, sides, arcs;
};

Sectors build_sectors(const RingGeometry& g, const RingPlan& p) {
  const int rays = p.sectors == 8 ? 8 : p.sectors + 1; // the full ring's last ends on ray 0
  const int centre = geo::addPoint(0, 0, 0);
  Sectors s;
  std::vector<int> inner(rays), outer(rays);
  for (int k = 0; k < rays; ++k) {
    const auto [cx, cy] = ray[k];
    const double rim = g.radius / std::hypot(cx, cy);
    inner[k] = geo::addPoint(cx * g.half_width, cy * g.half_width, 0);
    outer[k] = geo::addPoint(cx * rim, cy * rim, 0);
    s.spokes.push_back(geo::addLine(inner[k], outer[k]));
  }
  for (int k = 0; k < p.sectors; ++k) {
    const int next = (k + 1) % rays;
    s.sides.push_back(geo::addLine(inner[k], inner[next]));
    s.arcs.push_back(geo::addCircleArc(outer[k], centre, outer[next]));
    s.surfaces.push_back(geo::addPlaneSurface(
        {geo::addCurveLoop({s.spokes[k], s.arcs.back(), -s.spokes[next], -s.sides.back()})}));
  }
  return s;
}

// Node counts on the plan's curves (each spoke's ratio applies from the hole outwards, its
// direction), transfinite recombined sectors.
void make_structured(const Sectors& s, const RingPlan& p) {
  for (std::size_t k = 0; k < s.spokes.size(); ++k)
    gmsh::model::mesh::setTransfiniteCurve(s.spokes[k], p.radial + 1, "Progression",
                                           p.ratio[k % 2]);
  for (const auto* curves : {&s.sides, &s.arcs})
    for (const int curve : *curves)
      gmsh::model::mesh::setTransfiniteCurve(curve, p.along + 1);
  for (const int surface : s.surfaces) {
    gmsh::model::mesh::setTransfiniteSurface(surface);
    gmsh::model::mesh::setRecombine(2, surface);
  }
}

// Boundary surfaces (bounding one block) by where their corners lie.
void name_faces(const std::string& body, const RingGeometry& g, const RingPlan& p) {
  const double tol = 1e-9 * g.radius;
  const auto all = [](const std::vector<Vec3>& x, auto on) { return std::ranges::all_of(x, on); };
  std::vector<int> inner, rim, bottom, top, xmin, ymin;
  for (const auto& [surface, x] : boundary_surfaces()) {
    if (all(x, [&](const Vec3& c) { return std::abs(c.z()) < tol; }))
      bottom.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.z() - g.thickness) < tol; }))
      top.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.head<2>().norm() - g.radius) < tol; }))
      rim.push_back(surface);
    else if (all(x, [&](const Vec3& c) {
               return std::abs(c.head<2>().lpNorm<Eigen::Infinity>() - g.half_width) < tol;
             }))
      inner.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.x()) < tol; }))
      xmin.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.y()) < tol; }))
      ymin.push_back(surface);
    else
      throw Error(detail::concat("ring surface ", surface, " is on no named face"));
  }
  // One face on each cut ray.
  const std::size_t n = p.sectors;
  const auto [x_cuts, y_cuts] = cut_rays(g.sector);
  SPHFEM_CHECK(inner.size() == n && rim.size() == n && bottom.size() == n && top.size() == n &&
                   xmin.size() == x_cuts && ymin.size() == y_cuts,
               "unexpected ring boundary (", inner.size(), " inner, ", rim.size(), " rim, ",
               bottom.size(), " bottom, ", top.size(), " top, ", xmin.size(), " xmin, ",
               ymin.size(), " ymin surfaces)");
  add_named_face(body + "/inner", inner);
  add_named_face(body + "/rim", rim);
  add_named_face(body + "/bottom", bottom);
  add_named_face(body + "/top", top);
  if (x_cuts > 0)
    add_named_face(body + "/xmin", xmin);
  if (y_cuts > 0)
    add_named_face(body + "/ymin", ymin);
}

} // namespace

Placement build_ring(const BodySpec& body) {
  const RingGeometry& g = body.geometry.ring;
  const RingPlan p = plan(g, body.element_size);
  const Sectors sectors = build_sectors(g, p);
  gmsh::vectorpair plan_surfaces, extruded;
  for (const int s : sectors.surfaces)
    plan_surfaces.emplace_back(2, s);
  // Extruded in layers: the top and every layer are copies of the plan's mesh.
  geo::extrude(plan_surfaces, 0, 0, g.thickness, extruded, {p.layers}, {}, true);
  geo::synchronize();
  make_structured(sectors, p);
  name_faces(body.name, g, p);
  return {Mat3::Identity(), g.base};
}

} // namespace sphfem::mesher
