// Structured hex mesh of a cylinder: an O-grid disk extruded along local z into transfinite,
// recombined blocks, then placed on the axis; faces base, top, side. The disk is four quadrants,
// each the core square [0, c]² (c = R/2) turned into it and two ring blocks over its 45° halves
// (12 blocks); a quarter (axis along +z only) is the first quadrant alone, x, y ≥ base (3 blocks),
// with faces xmin (x = base.x) and ymin (y = base.y) as well, and its mesh is exactly the
// quadrant of the whole cylinder's; a half (axis in the x–z plane) the first two quadrants, its
// local y ≥ 0 placed on the world's y ≥ base.y (6 blocks), with face ymin. Counts: n = round(c / h)
// elements along each core half-side and each 45° rim arc, radially round((R − c(1 + √2)/2) / h),
// along the axis round(L/h), each at least 1. Verified by tests/mesher/mesher_test.cpp.
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
  Sector sector = Sector::Full;
  int along = 1, radial = 1, layers = 1;
};

OGrid plan(const CylinderGeometry& g, double h) {
  OGrid o;
  o.radius = g.radius;
  o.length = g.axis.norm();
  o.core = 0.5 * g.radius;
  o.sector = g.sector;
  // Core elements of size h (the arcs' are π/4 · R / c ≈ 1.57 times longer): the core sets the
  // stable time step, and the flat nose that meets the target is mostly core.
  o.along = divisions(o.core, h);
  // The ring is R − a thick at mid-side and R − a√2 at the core's corners: use the mean.
  o.radial = divisions(g.radius - 0.5 * (1 + std::numbers::sqrt2) * o.core, h);
  o.layers = divisions(o.length, h);
  return o;
}

// The disk at z = 0 as `quadrants` (4: whole, 2: the half y ≥ 0, 1: the quarter x, y ≥ 0) from
// +x, each three quadrilateral surfaces: the core square [0, c]² turned into it and the ring
// blocks over its first and second 45°; neighbouring quadrants share their points and curves on
// the axis between them. So the whole disk is four copies of the quarter, turned, and a quarter
// model's mesh is exactly the quadrant of the whole one's. Loops counter-clockwise about +z.
std::vector<int> build_disk(const OGrid& o, int quadrants) {
  const double c = o.core, r = o.radius, d = 1 / std::numbers::sqrt2;
  static constexpr std::array<double, 4> cx{1, 0, -1, 0}, cy{0, 1, 0, -1}; // 0°, 90°, …
  const int centre = geo::addPoint(0, 0, 0);
  const int rays = quadrants == 4 ? 4 : quadrants + 1; // the axes bounding the quadrants
  std::array<int, 4> core_on_axis{}, rim_on_axis{}, centre_line{}, axis_spoke{};
  for (int k = 0; k < rays; ++k) {
    core_on_axis[k] = geo::addPoint(c * cx[k], c * cy[k], 0);
    rim_on_axis[k] = geo::addPoint(r * cx[k], r * cy[k], 0);
    centre_line[k] = geo::addLine(centre, core_on_axis[k]);
    axis_spoke[k] = geo::addLine(core_on_axis[k], rim_on_axis[k]);
  }
  std::vector<int> surfaces;
  for (int k = 0; k < quadrants; ++k) {
    const int next = (k + 1) % rays;
    // The quadrant's corner and its diagonal point on the rim: (c, c) and (r, r)/√2 turned.
    const double ux = cx[k] - cy[k], uy = cy[k] + cx[k];
    const int corner = geo::addPoint(c * ux, c * uy, 0);
    const int rim = geo::addPoint(r * d * ux, r * d * uy, 0);
    const int side_a = geo::addLine(core_on_axis[k], corner);
    const int side_b = geo::addLine(corner, core_on_axis[next]);
    const int diagonal_spoke = geo::addLine(corner, rim);
    const int arc_a = geo::addCircleArc(rim_on_axis[k], centre, rim);
    const int arc_b = geo::addCircleArc(rim, centre, rim_on_axis[next]);
    surfaces.push_back(geo::addPlaneSurface(
        {geo::addCurveLoop({centre_line[k], side_a, side_b, -centre_line[next]})}));
    surfaces.push_back(geo::addPlaneSurface(
        {geo::addCurveLoop({axis_spoke[k], arc_a, -diagonal_spoke, -side_a})}));
    surfaces.push_back(geo::addPlaneSurface(
        {geo::addCurveLoop({diagonal_spoke, arc_b, -axis_spoke[next], -side_b})}));
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
// z = L the top, on the planes x = 0 and y = 0 (cut sectors) xmin and ymin; the rest the side.
void name_faces(const std::string& body, const OGrid& o) {
  const double tol = 1e-9 * std::max(o.radius, o.length);
  const auto all = [](const std::vector<Vec3>& x, auto on) { return std::ranges::all_of(x, on); };
  std::vector<int> base, top, side, xmin, ymin;
  for (const auto& [surface, x] : boundary_surfaces()) {
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
  const std::size_t quadrants = quadrant_count(o.sector), blocks = 3 * quadrants,
                    arcs = 2 * quadrants;
  // Each cut ray carries two faces: the core's and the ring's.
  const CutRays cuts = cut_rays(o.sector);
  const std::size_t x_cut = 2 * cuts.x, y_cut = 2 * cuts.y;
  SPHFEM_CHECK(base.size() == blocks && top.size() == blocks && side.size() == arcs &&
                   xmin.size() == x_cut && ymin.size() == y_cut,
               "unexpected cylinder boundary (", base.size(), " base, ", top.size(), " top, ",
               side.size(), " side, ", xmin.size(), " xmin, ", ymin.size(), " ymin surfaces)");
  add_named_face(body + "/base", base);
  add_named_face(body + "/top", top);
  add_named_face(body + "/side", side);
  if (x_cut > 0)
    add_named_face(body + "/xmin", xmin);
  if (y_cut > 0)
    add_named_face(body + "/ymin", ymin);
}

} // namespace

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

int quadrant_count(Sector sector) {
  return sector == Sector::Full ? 4 : sector == Sector::Half ? 2 : 1;
}

CutRays cut_rays(Sector sector) {
  switch (sector) {
  case Sector::Quarter:
    return {1, 1};
  case Sector::Half:
    return {0, 2};
  case Sector::Full:
    break;
  }
  return {0, 0};
}

Mat3 sector_rotation(Sector sector, const Vec3& axis) {
  switch (sector) {
  case Sector::Quarter:
    return Mat3::Identity();
  case Sector::Half: { // local y stays the world's y: a turn about y
    const Vec3 a = axis.normalized(), e1 = Vec3::UnitY().cross(a);
    Mat3 r;
    r << e1, Vec3::UnitY(), a;
    return r;
  }
  case Sector::Full:
    break;
  }
  return frame_along(axis);
}

void check_sector_axis(Sector sector, const Vec3& axis) {
  SPHFEM_CHECK(sector != Sector::Quarter ||
                   (axis.z() > 0 && axis.head<2>().norm() <= 1e-12 * axis.z()),
               "a quarter cylinder's axis must be along +z, got ", axis.transpose());
  SPHFEM_CHECK(sector != Sector::Half || std::abs(axis.y()) <= 1e-12 * axis.norm(),
               "a half cylinder's axis must lie in the x–z plane, got ", axis.transpose());
}

Placement build_cylinder(const BodySpec& body) {
  const CylinderGeometry& g = body.geometry.cylinder;
  SPHFEM_CHECK(g.radius > 0 && std::isfinite(g.radius), "cylinder radius must be positive");
  SPHFEM_CHECK(g.axis.allFinite() && g.axis.norm() > 0, "cylinder axis must be non-zero");
  SPHFEM_CHECK(g.base.allFinite(), "cylinder base must be finite");
  // The cut faces lie on the planes x = base.x and y = base.y.
  check_sector_axis(g.sector, g.axis);
  if (g.nose.shape != NoseGeometry::Shape::Flat)
    return build_nosed_cylinder(body); // mesher/nose.cpp
  const OGrid o = plan(g, body.element_size);

  gmsh::vectorpair disk, extruded;
  for (const int s : build_disk(o, quadrant_count(g.sector)))
    disk.emplace_back(2, s);
  geo::extrude(disk, 0, 0, o.length, extruded);
  geo::synchronize();
  make_structured(o);
  name_faces(body.name, o);
  return {sector_rotation(g.sector, g.axis), g.base};
}

} // namespace sphfem::mesher
