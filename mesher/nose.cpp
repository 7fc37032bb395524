// Structured hex mesh of a cylinder with a pointed nose at its base (NoseGeometry in
// solver/io/case.hpp: hemispherical, conical, ogival). The shank is the flat cylinder's O-grid
// (mesher/cylinder.cpp: the core square of half-width c = R/2 and the ring blocks over each 45°),
// extruded from the shoulder to the top; the nose continues it with a three-dimensional O-grid,
// as a sphere's O-grid continues a cylinder's, so that no element degenerates at the tip.
// Local frame: the tip at the origin, the axis +z, the shoulder at z = Ln (the nose's length).
// Per quadrant, four blocks below the shoulder:
//   core        under the shank's core square, tapering to a flat square of half-width r_l/2;
//   side shells under the shank's two ring blocks, between the core and the nose's surface,
//               from the shoulder down to the lower curve, which runs round the nose from its
//               height z_l on the axes (where the radius is r_l = 0.6 R) up to the diagonals;
//   cap         under the core, from its bottom to the nose's surface around the tip.
// Counts: `along` = round(c / h) elements along the core's sides, the rim's 45° arcs, the lower
// curve's pieces and the cap's meridians; `radial` = the shank's across the ring, shells and cap;
// `down` from the shoulder to the lower curve, from the mean of the surface's meridian and the
// core's edge there; `layers` along the shank. The nose's surface patches are gmsh surface
// fillings bounded by its meridians (circle arcs about the sphere's or the ogive's centre, lines
// on a cone), the shoulder's arcs and the lower curve (splines through points of the surface):
// spherical on a hemisphere; on a cone or an ogive Coons patches, whose nodes are then moved out
// onto the surface. Faces: base (the nose), top, side (the shank), a half also ymin, a quarter
// xmin and ymin.
// Verified by tests/mesher/nose_test.cpp.
#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

namespace sphfem::mesher {
namespace {

namespace geo = gmsh::model::geo;
using Shape = NoseGeometry::Shape;

// The nose's meridian: radius r(z) from the tip (z = 0) to the shoulder (z = Ln, r = R).
struct Profile {
  NoseGeometry nose;
  double radius, length;
  double ogive = 0; // the ogive's arc radius ρ = crh × 2R

  Profile(const NoseGeometry& n, double r)
      : nose(n), radius(r), length(n.nose_length(r)), ogive(2 * n.crh * r) {}

  double r(double z) const { return nose.radius_at(z, radius); }

  // The height where the radius is `target` (r grows monotonically from the tip): bisection.
  double z_at(double target) const {
    double lo = 0, hi = length;
    for (int i = 0; i < 100; ++i)
      (r(0.5 * (lo + hi)) < target ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  }

  // Length of the meridian between two heights (chords of 200 pieces).
  double arc(double z0, double z1) const {
    double s = 0;
    for (int i = 0; i < 200; ++i) {
      const double a = z0 + (z1 - z0) * i / 200, b = z0 + (z1 - z0) * (i + 1) / 200;
      s += std::hypot(b - a, r(b) - r(a));
    }
    return s;
  }
};

// gmsh geo entities by their corner points: curves between two points (with their element
// count set as they are made) and surfaces through four, each made once and shared.
class Blocks {
public:
  int point(const Vec3& x) { return geo::addPoint(x.x(), x.y(), x.z()); }

  void line(int a, int b, int n) { add(a, b, geo::addLine(a, b), n); }
  void arc(int a, int centre, int b, int n) { add(a, b, geo::addCircleArc(a, centre, b), n); }
  void spline(const std::vector<int>& through, int n) {
    add(through.front(), through.back(), geo::addSpline(through), n);
  }

  // The surface through the four corners in order (its curves made before), a spherical patch
  // about `sphere` if given; the same surface when asked again in any order.
  int face(std::array<int, 4> corners, int sphere = -1) {
    std::array<int, 4> key = corners;
    std::ranges::sort(key);
    if (const auto found = faces_.find(key); found != faces_.end())
      return found->second;
    std::vector<int> loop;
    for (int i = 0; i < 4; ++i)
      loop.push_back(curve(corners[i], corners[(i + 1) % 4]));
    const int surface = geo::addSurfaceFilling({geo::addCurveLoop(loop)}, -1, sphere);
    faces_[key] = surface;
    return surface;
  }

  void block(const std::array<int, 6>& faces) {
    volumes_.push_back(geo::addVolume({geo::addSurfaceLoop({faces.begin(), faces.end()})}));
  }
  const std::vector<int>& volumes() const { return volumes_; }
  std::vector<int> surfaces() const {
    std::vector<int> out;
    for (const auto& [corners, surface] : faces_)
      out.push_back(surface);
    return out;
  }
  const std::map<std::pair<int, int>, std::pair<int, int>>& curves() const { return curves_; }

private:
  std::map<std::pair<int, int>, std::pair<int, int>> curves_; // (a, b) → (tag, elements)
  std::map<std::array<int, 4>, int> faces_;
  std::vector<int> volumes_;

  void add(int a, int b, int tag, int n) { curves_[{a, b}] = {tag, n}; }
  int curve(int a, int b) const {
    if (const auto found = curves_.find({a, b}); found != curves_.end())
      return found->second.first;
    const auto reverse = curves_.find({b, a});
    SPHFEM_CHECK(reverse != curves_.end(), "nose: no curve between points ", a, " and ", b);
    return -reverse->second.first;
  }
};

struct Plan {
  double radius = 0, core = 0, length = 0, nose = 0; // R, c, L, Ln
  double lower = 0, lower_radius = 0;                // z_l, r_l: the lower curve on the axes
  double lower_diagonal = 0;                         // its height on the diagonals
  double inner = 0;                                  // height of the core's flat bottom
  int along = 1, radial = 1, down = 1, layers = 1;
  Sector sector = Sector::Full;
};

Plan plan(const CylinderGeometry& g, const Profile& p, double h) {
  Plan o;
  o.radius = g.radius;
  o.core = 0.5 * g.radius;
  o.length = g.axis.norm();
  o.nose = p.length;
  o.sector = g.sector;
  o.lower_radius = 0.6 * g.radius;
  o.lower = p.z_at(o.lower_radius);
  // The lower curve rises from the axes to the diagonals by tan 30° × its 45° of parallel, so
  // that the cap and the two shells meet at 120° on the diagonal, as on a sphere's O-grid.
  const double rl = o.lower_radius, cl = 0.5 * rl;
  const double rise = std::tan(std::numbers::pi / 6) * 0.25 * std::numbers::pi * rl;
  const double s_lower = p.arc(0, o.lower);
  double lo = o.lower, hi = o.nose;
  for (int i = 0; i < 100; ++i)
    (p.arc(0, 0.5 * (lo + hi)) - s_lower < rise ? lo : hi) = 0.5 * (lo + hi);
  o.lower_diagonal = 0.5 * (lo + hi);
  // The core's bottom: the square of half-width r_l/2, flat, up and in at 45° or more from the
  // lower curve's points on the axes and on the diagonals (so that the cap's corner under the
  // core's is not flat where the lower curve has risen), at most 0.65 of the way up to the
  // shoulder (blunt noses). Measured at R 10 mm, h 1 mm (hemisphere / cone of 15 mm / ogive CRH
  // 3): smallest scaled Jacobian 0.50 / 0.31 / 0.29, shortest L_e 0.42 / 0.37 / 0.52 h; with the
  // core's bottom at 45° from the axes' points only: 0.28 / 0.22 / 0.16 and 0.39 / 0.37 / 0.35 h.
  const double rc = p.r(o.lower_diagonal);
  o.inner = std::max(o.lower + rl - cl, o.lower_diagonal + (rc - std::numbers::sqrt2 * cl));
  o.inner = std::min(o.inner, o.lower + 0.65 * (o.nose - o.lower));
  o.along = divisions(o.core, h);
  o.radial = divisions(g.radius - 0.5 * (1 + std::numbers::sqrt2) * o.core, h);
  const double core_edge = std::hypot(o.core - cl, o.nose - o.inner);
  o.down = divisions(0.5 * (p.arc(o.lower, o.nose) + core_edge), h);
  o.layers = divisions(o.length - o.nose, h);
  return o;
}

// Builds the nose's blocks; returns the shoulder's surfaces (core squares and ring blocks, in
// the plane z = Ln), which the shank is extruded from.
std::vector<int> build_nose(const Plan& o, const Profile& p, Blocks& b) {
  const double c = o.core, R = o.radius, Ln = o.nose, rl = o.lower_radius, cl = 0.5 * rl;
  const int quadrants = quadrant_count(o.sector), rays = quadrants == 4 ? 4 : quadrants + 1;
  const double ogive_offset = p.ogive - R; // the ogive's centre lies this far beyond the axis

  const int shoulder = b.point(Vec3(0, 0, Ln)), bottom = b.point(Vec3(0, 0, o.inner)),
            tip = b.point(Vec3::Zero());
  // A meridian of the nose from point `high` down to point `low`, at azimuth φ.
  const auto meridian = [&](int high, int low, double phi, int n) {
    switch (p.nose.shape) {
    case Shape::Hemispherical:
      b.arc(high, shoulder, low, n);
      return;
    case Shape::Ogival:
      b.arc(high, b.point(Vec3(-ogive_offset * std::cos(phi), -ogive_offset * std::sin(phi), Ln)),
            low, n);
      return;
    default:
      b.line(high, low, n);
    }
  };
  const auto on = [](double r, double phi, double z) {
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  // The lower curve between an axis (azimuth φ_axis) and a diagonal, on the nose: its height
  // linear in the azimuth, a spline through nine points of the surface; `turn` +1 from the
  // axis to the diagonal, −1 from the diagonal to the axis.
  const auto lower_curve = [&](int from, int to, double phi_axis, int turn) {
    std::vector<int> points{from};
    for (int i = 1; i < 8; ++i) {
      const double t = turn > 0 ? i / 8.0 : 1 - i / 8.0; // 0 on the axis, 1 on the diagonal
      const double z = o.lower + t * (o.lower_diagonal - o.lower);
      points.push_back(b.point(on(p.r(z), phi_axis + turn * 0.25 * std::numbers::pi * t, z)));
    }
    points.push_back(to);
    b.spline(points, o.along);
  };

  b.line(shoulder, bottom, o.down);
  b.line(bottom, tip, o.radial);
  std::array<int, 4> edge{}, rim{}, inner{}, outer{}; // per ray: E, rim, Ia, Oa
  for (int k = 0; k < rays; ++k) {
    const double phi = 0.5 * std::numbers::pi * k;
    edge[k] = b.point(on(c, phi, Ln));
    rim[k] = b.point(on(R, phi, Ln));
    inner[k] = b.point(on(cl, phi, o.inner));
    outer[k] = b.point(on(rl, phi, o.lower));
    b.line(shoulder, edge[k], o.along);
    b.line(edge[k], rim[k], o.radial);
    b.line(edge[k], inner[k], o.down);
    meridian(rim[k], outer[k], phi, o.down);
    b.line(inner[k], outer[k], o.radial);
    b.line(bottom, inner[k], o.along);
    meridian(outer[k], tip, phi, o.along);
  }
  const int sphere = p.nose.shape == Shape::Hemispherical ? shoulder : -1;
  std::vector<int> top;
  for (int k = 0; k < quadrants; ++k) {
    const int next = (k + 1) % rays;
    const double phi = 0.5 * std::numbers::pi * (k + 0.5);
    const double cs = std::numbers::sqrt2 * c, cls = std::numbers::sqrt2 * cl;
    const int corner = b.point(on(cs, phi, Ln)), rim_d = b.point(on(R, phi, Ln));
    const int inner_d = b.point(on(cls, phi, o.inner));
    const int outer_d = b.point(on(p.r(o.lower_diagonal), phi, o.lower_diagonal));
    b.line(edge[k], corner, o.along);
    b.line(corner, edge[next], o.along);
    b.line(corner, rim_d, o.radial);
    b.arc(rim[k], shoulder, rim_d, o.along);
    b.arc(rim_d, shoulder, rim[next], o.along);
    b.line(corner, inner_d, o.down);
    meridian(rim_d, outer_d, phi, o.down);
    b.line(inner_d, outer_d, o.radial);
    b.line(inner[k], inner_d, o.along);
    b.line(inner_d, inner[next], o.along);
    lower_curve(outer[k], outer_d, 0.5 * std::numbers::pi * k, 1);
    lower_curve(outer_d, outer[next], 0.5 * std::numbers::pi * (k + 1), -1);

    const int core_top = b.face({shoulder, edge[k], corner, edge[next]});
    const int ring_a = b.face({edge[k], rim[k], rim_d, corner});
    const int ring_b = b.face({corner, rim_d, rim[next], edge[next]});
    const int core_bottom = b.face({bottom, inner[k], inner_d, inner[next]});
    const int side_a = b.face({edge[k], corner, inner_d, inner[k]});
    const int side_b = b.face({corner, edge[next], inner[next], inner_d});
    const int diagonal = b.face({corner, rim_d, outer_d, inner_d});
    const int shell_a_bottom = b.face({inner[k], outer[k], outer_d, inner_d});
    const int shell_b_bottom = b.face({inner_d, outer_d, outer[next], inner[next]});
    b.block({core_top, core_bottom, side_a, side_b, b.face({shoulder, edge[k], inner[k], bottom}),
             b.face({shoulder, edge[next], inner[next], bottom})});
    b.block({ring_a, side_a, diagonal, shell_a_bottom,
             b.face({rim[k], rim_d, outer_d, outer[k]}, sphere),
             b.face({edge[k], rim[k], outer[k], inner[k]})});
    b.block({ring_b, side_b, diagonal, shell_b_bottom,
             b.face({rim_d, rim[next], outer[next], outer_d}, sphere),
             b.face({edge[next], rim[next], outer[next], inner[next]})});
    b.block({core_bottom, shell_a_bottom, shell_b_bottom,
             b.face({tip, outer[k], outer_d, outer[next]}, sphere),
             b.face({bottom, inner[k], outer[k], tip}),
             b.face({bottom, inner[next], outer[next], tip})});
    top.insert(top.end(), {core_top, ring_a, ring_b});
  }
  return top;
}

// Boundary surfaces by where their corners lie: the top (z = L), the cut planes of a sector
// (x = 0, y = 0), the shank's side (r = R at or above the shoulder); the rest is the nose.
void name_faces(const std::string& body, const Plan& o) {
  const double tol = 1e-9 * std::max(o.radius, o.length);
  const auto all = [](const std::vector<Vec3>& x, auto on) { return std::ranges::all_of(x, on); };
  std::vector<int> base, top, side, xmin, ymin;
  for (const auto& [surface, x] : boundary_surfaces()) {
    if (all(x, [&](const Vec3& c) { return std::abs(c.z() - o.length) < tol; }))
      top.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.x()) < tol; }))
      xmin.push_back(surface);
    else if (all(x, [&](const Vec3& c) { return std::abs(c.y()) < tol; }))
      ymin.push_back(surface);
    else if (all(x, [&](const Vec3& c) {
               return std::abs(c.head<2>().norm() - o.radius) < tol && c.z() > o.nose - tol;
             }))
      side.push_back(surface);
    else
      base.push_back(surface);
  }
  // Each cut ray carries five faces: the core's, the shell's and the cap's in the nose, the
  // core's and the ring's in the shank.
  const std::size_t quadrants = quadrant_count(o.sector), patches = 3 * quadrants,
                    arcs = 2 * quadrants;
  const CutRays cuts = cut_rays(o.sector);
  const std::size_t x_cut = 5 * cuts.x, y_cut = 5 * cuts.y;
  SPHFEM_CHECK(base.size() == patches && top.size() == patches && side.size() == arcs &&
                   xmin.size() == x_cut && ymin.size() == y_cut,
               "unexpected nosed cylinder boundary (", base.size(), " nose, ", top.size(), " top, ",
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

Placement build_nosed_cylinder(const BodySpec& body) {
  const CylinderGeometry& g = body.geometry.cylinder;
  const Profile profile(g.nose, g.radius);
  SPHFEM_CHECK(profile.length > 0 && std::isfinite(profile.length),
               "the nose's length must be positive, got ", profile.length, " m");
  SPHFEM_CHECK(g.axis.norm() > profile.length, "the cylinder (", g.axis.norm(),
               " m) must be longer than its nose (", profile.length, " m)");
  check_sector_axis(g.sector, g.axis);
  const Plan o = plan(g, profile, body.element_size);
  Blocks blocks;
  const std::vector<int> shoulder = build_nose(o, profile, blocks);
  // Set on the geo kernel's entities, where they outlast the synchronisations below.
  for (const auto& [ends, curve] : blocks.curves())
    geo::mesh::setTransfiniteCurve(curve.first, curve.second + 1);
  for (const int surface : blocks.surfaces()) {
    geo::mesh::setTransfiniteSurface(surface);
    geo::mesh::setRecombine(2, surface);
  }
  for (const int volume : blocks.volumes())
    geo::mesh::setTransfiniteVolume(volume);
  // The shank: the shoulder's O-grid extruded to the top in `layers` hexahedral layers.
  gmsh::vectorpair disk, extruded;
  for (const int s : shoulder)
    disk.emplace_back(2, s);
  geo::extrude(disk, 0, 0, o.length - o.nose, extruded, {o.layers}, {}, true);
  geo::synchronize();
  name_faces(body.name, o);
  // The surface fillings of a cone or an ogive are Coons patches between its curves, up to
  // 0.06 R inside it across the cap's 90°: the nose's surface nodes are moved out onto it
  // along the radius (a hemisphere's are on it already). Moving out, the outer layer thickens.
  const auto snap = [profile, body]() {
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, 2);
    for (const auto& [dim, group] : groups) {
      std::string name;
      gmsh::model::getPhysicalName(dim, group, name);
      if (name != body.name + "/base")
        continue;
      std::vector<std::size_t> nodes;
      std::vector<double> x;
      gmsh::model::mesh::getNodesForPhysicalGroup(dim, group, nodes, x);
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        const double r = std::hypot(x[3 * i], x[3 * i + 1]), z = x[3 * i + 2];
        if (r <= 0 || z >= profile.length)
          continue;
        const double scale = profile.r(z) / r;
        gmsh::model::mesh::setNode(nodes[i], {scale * x[3 * i], scale * x[3 * i + 1], z}, {});
      }
    }
  };
  return {sector_rotation(g.sector, g.axis), g.base, snap};
}

} // namespace sphfem::mesher
