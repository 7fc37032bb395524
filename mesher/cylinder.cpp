// Structured hex mesh of a cylinder: an O-grid disk (square core + 4 ring blocks) extruded
// along local z into 5 transfinite, recombined blocks, then placed on the axis; faces base,
// top, side. A quarter (axis along +z only) is an O-grid of the quadrant x, y ≥ base: the core
// square [0, c]² and the two ring blocks between 0°–45° and 45°–90°, 3 blocks; faces base, top,
// side, xmin (x = base.x), ymin (y = base.y). Its mesh is not in general the quadrant of the
// full cylinder's, whose blocks end at 45°, 135°, … c = R/2. Counts: n_q elements along each
// core side and each rim arc (full: n_q = max(1, round(2c / h)) per core side and 90° arc;
// quarter: round(c / h) per half side and 45° arc), radially round((R − c(1 + √2)/2) / h), along
// the axis round(L/h), each at least 1. Verified by tests/mesher/mesher_test.cpp.
#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"

#include <Eigen/Geometry>
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace sphfem::mesher {
namespace {

namespace geo = gmsh::model::geo;

// Element counts of the O-grid: `along` along each block's rim arc and core side, `radial`
// across the ring, `layers` along the axis.
struct OGrid {
  double radius = 0, core = 0, length = 0; // core: half-width of the square core
  bool quarter = false;
  int along = 1, radial = 1, layers = 1;
};

OGrid plan(const CylinderGeometry& g, double h) {
  OGrid o;
  o.radius = g.radius;
  o.length = g.axis.norm();
  o.core = 0.5 * g.radius;
  o.quarter = g.sector == Sector::Quarter;
  // Core elements of size h (the arcs' are π/4 · R / c ≈ 1.57 times longer): the core sets the
  // stable time step, and the flat nose that meets the target is mostly core.
  o.along = divisions((o.quarter ? 1.0 : 2.0) * o.core, h);
  // The ring is R − a thick at mid-side and R − a√2 at the core's corners: use the mean.
  o.radial = divisions(g.radius - 0.5 * (1 + std::numbers::sqrt2) * o.core, h);
  o.layers = divisions(o.length, h);
  return o;
}

// The disk at z = 0 as five quadrilateral surfaces (core and ring blocks), loops
// counter-clockwise about +z.
std::vector<int> build_disk(const OGrid& o) {
  static constexpr std::array<double, 4> sx{1, -1, -1, 1}, sy{1, 1, -1, -1}; // 45°, 135°, …
  const double rim = o.radius / std::numbers::sqrt2;
  const int centre = geo::addPoint(0, 0, 0);
  std::array<int, 4> corner{}, outer{};
  for (int k = 0; k < 4; ++k) {
    corner[k] = geo::addPoint(sx[k] * o.core, sy[k] * o.core, 0);
    outer[k] = geo::addPoint(sx[k] * rim, sy[k] * rim, 0);
  }
  std::array<int, 4> side{}, spoke{}, arc{};
  for (int k = 0; k < 4; ++k) {
    const int next = (k + 1) % 4;
    side[k] = geo::addLine(corner[k], corner[next]);
    spoke[k] = geo::addLine(corner[k], outer[k]);
    arc[k] = geo::addCircleArc(outer[k], centre, outer[next]);
  }
  std::vector<int> surfaces{
      geo::addPlaneSurface({geo::addCurveLoop({side[0], side[1], side[2], side[3]})})};
  for (int k = 0; k < 4; ++k) {
    const int next = (k + 1) % 4;
    surfaces.push_back(
        geo::addPlaneSurface({geo::addCurveLoop({spoke[k], arc[k], -spoke[next], -side[k]})}));
  }
  return surfaces;
}

// The quarter disk x, y ≥ 0 at z = 0: the core square [0, c]² and the ring blocks 0°–45° and
// 45°–90°, loops counter-clockwise about +z.
std::vector<int> build_quarter_disk(const OGrid& o) {
  const double c = o.core, diagonal = o.radius / std::numbers::sqrt2;
  const int centre = geo::addPoint(0, 0, 0);
  const std::array<int, 3> corner{geo::addPoint(c, 0, 0), geo::addPoint(c, c, 0),
                                  geo::addPoint(0, c, 0)};
  const std::array<int, 3> outer{geo::addPoint(o.radius, 0, 0),
                                 geo::addPoint(diagonal, diagonal, 0),
                                 geo::addPoint(0, o.radius, 0)};
  std::array<int, 3> spoke{};
  for (int k = 0; k < 3; ++k)
    spoke[k] = geo::addLine(corner[k], outer[k]);
  const std::array<int, 2> side{geo::addLine(corner[0], corner[1]),
                                geo::addLine(corner[1], corner[2])};
  const int core = geo::addPlaneSurface({geo::addCurveLoop(
      {geo::addLine(centre, corner[0]), side[0], side[1], geo::addLine(corner[2], centre)})});
  std::vector<int> surfaces{core};
  for (int k = 0; k < 2; ++k) {
    const int arc = geo::addCircleArc(outer[k], centre, outer[k + 1]);
    surfaces.push_back(
        geo::addPlaneSurface({geo::addCurveLoop({spoke[k], arc, -spoke[k + 1], -side[k]})}));
  }
  return surfaces;
}

Vec3 point(int tag) {
  std::vector<double> x;
  gmsh::model::getValue(0, tag, {}, x);
  return {x[0], x[1], x[2]};
}

// Node counts by curve kind: axial edges (ends at different z) get `layers`, spokes (one end on
// the rim) `radial`, core sides and rim arcs `along` elements. Then every surface and block is
// transfinite and recombined, giving hexahedra.
void make_structured(const OGrid& o) {
  gmsh::vectorpair curves, surfaces, volumes;
  gmsh::model::getEntities(curves, 1);
  const auto on_rim = [&](const Vec3& x) {
    return std::abs(x.head<2>().norm() - o.radius) < 1e-6 * o.radius;
  };
  for (const auto& [dim, curve] : curves) {
    std::vector<int> faces, ends;
    gmsh::model::getAdjacencies(1, curve, faces, ends);
    SPHFEM_CHECK(ends.size() == 2, "curve ", curve, " is not a simple edge");
    const Vec3 a = point(ends[0]), b = point(ends[1]);
    const bool axial = std::abs(a.z() - b.z()) > 0.5 * o.length;
    const int n = axial ? o.layers : on_rim(a) != on_rim(b) ? o.radial : o.along;
    gmsh::model::mesh::setTransfiniteCurve(curve, n + 1);
  }
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, surface] : surfaces) {
    gmsh::model::mesh::setTransfiniteSurface(surface);
    gmsh::model::mesh::setRecombine(2, surface);
  }
  gmsh::model::getEntities(volumes, 3);
  for (const auto& [dim, volume] : volumes)
    gmsh::model::mesh::setTransfiniteVolume(volume);
}

// Boundary surfaces (bounding one volume) by where their corners lie: at z = 0 the base, at
// z = L the top, on the planes x = 0 and y = 0 (quarter) xmin and ymin; the rest is the side.
void name_faces(const std::string& body, const OGrid& o) {
  const double tol = 1e-9 * std::max(o.radius, o.length);
  const auto all = [](const std::vector<Vec3>& x, auto on) { return std::ranges::all_of(x, on); };
  gmsh::vectorpair dim_tags;
  gmsh::model::getEntities(dim_tags, 2);
  std::vector<int> base, top, side, xmin, ymin;
  for (const auto& [dim, surface] : dim_tags) {
    std::vector<int> volumes, curves;
    gmsh::model::getAdjacencies(2, surface, volumes, curves);
    if (volumes.size() != 1)
      continue;
    const std::vector<Vec3> x = corner_points(2, surface);
    if (all(x, [&](const Vec3& c) { return std::abs(c.z()) < tol; }))
      base.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.z() - o.length) < tol; }))
      top.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.x()) < tol; }))
      xmin.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.y()) < tol; }))
      ymin.push_back(surface);
    else
      side.push_back(surface);
  }
  const std::size_t blocks = o.quarter ? 3 : 5, arcs = o.quarter ? 2 : 4, cut = o.quarter ? 2 : 0;
  SPHFEM_CHECK(base.size() == blocks && top.size() == blocks && side.size() == arcs &&
                   xmin.size() == cut && ymin.size() == cut,
               "unexpected cylinder boundary (", base.size(), " base, ", top.size(), " top, ",
               side.size(), " side, ", xmin.size(), " xmin, ", ymin.size(), " ymin surfaces)");
  add_named_face(body + "/base", base);
  add_named_face(body + "/top", top);
  add_named_face(body + "/side", side);
  if (o.quarter) {
    add_named_face(body + "/xmin", xmin);
    add_named_face(body + "/ymin", ymin);
  }
}

// A right-handed frame whose third axis is `axis`; the identity for +z.
Mat3 frame_along(const Vec3& axis) {
  const Vec3 a = axis.normalized();
  Eigen::Index least = 0;
  a.cwiseAbs().minCoeff(&least);
  const Vec3 helper = Vec3::Unit(least);
  const Vec3 e1 = (helper - helper.dot(a) * a).normalized();
  Mat3 r;
  r << e1, a.cross(e1), a;
  return r;
}

} // namespace

Placement build_cylinder(const BodySpec& body) {
  const CylinderGeometry& g = body.geometry.cylinder;
  SPHFEM_CHECK(g.radius > 0 && std::isfinite(g.radius), "cylinder radius must be positive");
  SPHFEM_CHECK(g.axis.allFinite() && g.axis.norm() > 0, "cylinder axis must be non-zero");
  SPHFEM_CHECK(g.base.allFinite(), "cylinder base must be finite");
  const bool quarter = g.sector == Sector::Quarter;
  // The quarter's cut faces lie on the planes x = base.x and y = base.y.
  SPHFEM_CHECK(!quarter || (g.axis.z() > 0 && g.axis.head<2>().norm() <= 1e-12 * g.axis.z()),
               "a quarter cylinder's axis must be along +z, got ", g.axis.transpose());
  const OGrid o = plan(g, body.element_size);

  gmsh::vectorpair disk, extruded;
  for (const int s : quarter ? build_quarter_disk(o) : build_disk(o))
    disk.emplace_back(2, s);
  geo::extrude(disk, 0, 0, o.length, extruded);
  geo::synchronize();
  make_structured(o);
  name_faces(body.name, o);
  return {quarter ? Mat3::Identity() : frame_along(g.axis), g.base};
}

} // namespace sphfem::mesher
