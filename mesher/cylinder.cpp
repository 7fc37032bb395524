// Structured hex mesh of a cylinder: an O-grid disk (square core + 4 ring blocks) extruded
// along local z into 5 transfinite, recombined blocks, then placed on the axis; faces base,
// top, side. Verified by tests/mesher/mesher_test.cpp.
#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"

#include <Eigen/Geometry>
#include <gmsh.h>

#include <array>
#include <cmath>
#include <numbers>

namespace sphfem::mesher {
namespace {

namespace geo = gmsh::model::geo;

// Element counts of the O-grid: `quarter` along each quarter of the rim and each core side,
// `radial` across the ring, `layers` along the axis.
struct OGrid {
  double radius = 0, core = 0, length = 0; // core: half-width of the square core
  int quarter = 1, radial = 1, layers = 1;
};

OGrid plan(const CylinderGeometry& g, double h) {
  OGrid o;
  o.radius = g.radius;
  o.length = g.axis.norm();
  o.core = 0.5 * g.radius;
  o.quarter = divisions(0.5 * std::numbers::pi * g.radius, h);
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

Vec3 point(int tag) {
  std::vector<double> x;
  gmsh::model::getValue(0, tag, {}, x);
  return {x[0], x[1], x[2]};
}

// Node counts by curve kind: axial edges (ends at different z) get `layers`, spokes (ends at
// different radii) `radial`, core sides and rim arcs (ends at one radius) `quarter` elements.
// Then every surface and block is transfinite and recombined, giving hexahedra.
void make_structured(const OGrid& o) {
  gmsh::vectorpair curves, surfaces, volumes;
  gmsh::model::getEntities(curves, 1);
  for (const auto& [dim, curve] : curves) {
    std::vector<int> faces, ends;
    gmsh::model::getAdjacencies(1, curve, faces, ends);
    SPHFEM_CHECK(ends.size() == 2, "curve ", curve, " is not a simple edge");
    const Vec3 a = point(ends[0]), b = point(ends[1]);
    const bool axial = std::abs(a.z() - b.z()) > 0.5 * o.length;
    const bool same_radius = std::abs(a.head<2>().norm() - b.head<2>().norm()) < 1e-6 * o.radius;
    const int n = axial ? o.layers : same_radius ? o.quarter : o.radial;
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

// Boundary surfaces (bounding one volume): flat ones at z = 0 are the base, at z = L the top;
// the curved rest is the side.
void name_faces(const std::string& body, double length) {
  gmsh::vectorpair dim_tags;
  gmsh::model::getEntities(dim_tags, 2);
  std::vector<int> base, top, side;
  for (const auto& [dim, surface] : dim_tags) {
    std::vector<int> volumes, curves;
    gmsh::model::getAdjacencies(2, surface, volumes, curves);
    if (volumes.size() != 1)
      continue;
    double x0, y0, z0, x1, y1, z1;
    gmsh::model::getBoundingBox(2, surface, x0, y0, z0, x1, y1, z1);
    if (z1 - z0 > 0.5 * length)
      side.push_back(surface);
    else
      (z0 + z1 < length ? base : top).push_back(surface);
  }
  SPHFEM_CHECK(base.size() == 5 && top.size() == 5 && side.size() == 4,
               "unexpected cylinder boundary (", base.size(), " base, ", top.size(), " top, ",
               side.size(), " side surfaces)");
  add_named_face(body + "/base", base);
  add_named_face(body + "/top", top);
  add_named_face(body + "/side", side);
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
  const OGrid o = plan(g, body.element_size);

  gmsh::vectorpair disk, extruded;
  for (const int s : build_disk(o))
    disk.emplace_back(2, s);
  geo::extrude(disk, 0, 0, o.length, extruded);
  geo::synchronize();
  make_structured(o);
  name_faces(body.name, o.length);
  return {frame_along(g.axis), g.base};
}

} // namespace sphfem::mesher
