// Tests of half sectors (Sector::Half, for oblique shots with a symmetry plane y = 0): a half
// cylinder, ring and nosed cylinder are valid meshes holding exactly half of the whole one's
// hexahedra and volume, with the cut face ymin on the plane y = base.y (and no xmin); a half
// cylinder's axis may lean in the x–z plane and its cut face stays on y = base.y; an axis out of
// that plane is refused with a message.
#include "hex_checks.hpp"

#include "mesher/mesher.hpp"
#include "solver/core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace sphfem {
namespace {

Case one_body(const GeometrySpec& g, double h) {
  Case c;
  c.name = "half_sector_test";
  c.materials.push_back({.name = "steel",
                         .model = "elastic",
                         .density = 7850,
                         .youngs_modulus = 200e9,
                         .poisson_ratio = 0.33});
  BodySpec b;
  b.name = "body";
  b.geometry = g;
  b.element_size = h;
  b.material = "steel";
  c.bodies = {b};
  return c;
}

GeometrySpec cylinder(const Vec3& axis, Sector sector, NoseGeometry::Shape nose) {
  GeometrySpec g;
  g.kind = GeometrySpec::Kind::Cylinder;
  g.cylinder.base = Vec3(0.01, -0.02, 0.003);
  g.cylinder.axis = axis;
  g.cylinder.radius = 0.01;
  g.cylinder.sector = sector;
  g.cylinder.nose.shape = nose;
  return g;
}

GeometrySpec ring(Sector sector) {
  GeometrySpec g;
  g.kind = GeometrySpec::Kind::Ring;
  g.ring = {Vec3(0, 0, -0.012), 0.024, 0.1, 0.012, 0.0, sector};
  return g;
}

void expect_half_of(const GeometrySpec& half, const GeometrySpec& whole, double h) {
  const Model mh = mesh_case(one_body(half, h)), mw = mesh_case(one_body(whole, h));
  test::expect_valid_mesh(mh);
  EXPECT_EQ(2 * mh.element_count(), mw.element_count());
  EXPECT_NEAR(2 * test::total_volume(mh, 0) / test::total_volume(mw, 0), 1.0, 1e-9);
  EXPECT_EQ(mh.face_sets.count("body/xmin"), 0u);
  ASSERT_EQ(mh.node_sets.count("body/ymin"), 1u);
  const double y0 =
      half.kind == GeometrySpec::Kind::Ring ? half.ring.base.y() : half.cylinder.base.y();
  for (const Index n : mh.node_sets.at("body/ymin"))
    EXPECT_NEAR(mh.x_n[static_cast<std::size_t>(n)].y(), y0, 1e-12);
  for (const Vec3& x : mh.x_n)
    EXPECT_GE(x.y(), y0 - 1e-12);
}

TEST(HalfSector, CylinderRingAndNoseAreHalves) {
  using Shape = NoseGeometry::Shape;
  {
    SCOPED_TRACE("cylinder along +z");
    expect_half_of(cylinder({0, 0, 0.05}, Sector::Half, Shape::Flat),
                   cylinder({0, 0, 0.05}, Sector::Full, Shape::Flat), 0.002);
  }
  {
    SCOPED_TRACE("ring");
    expect_half_of(ring(Sector::Half), ring(Sector::Full), 0.003);
  }
  {
    SCOPED_TRACE("hemispherical nose leaning 30° in the x–z plane");
    const Vec3 axis = 0.05 * Vec3(std::sin(0.5236), 0, std::cos(0.5236));
    const GeometrySpec half = cylinder(axis, Sector::Half, Shape::Hemispherical);
    const Model m = mesh_case(one_body(half, 0.002));
    test::expect_valid_mesh(m);
    // Its volume is half of the solid's, less the chords' loss (3 chords a 45° arc at 2 mm: the
    // polygon holds 1.1% less than the circle).
    const double solid =
        std::numbers::pi * 0.01 * 0.01 * (0.05 - 0.01) + 2.0 / 3 * std::numbers::pi * 1e-6;
    EXPECT_NEAR(2 * test::total_volume(m, 0) / solid, 1.0 - 0.011, 0.004);
    for (const Index n : m.node_sets.at("body/ymin"))
      EXPECT_NEAR(m.x_n[static_cast<std::size_t>(n)].y(), -0.02, 1e-12);
  }
}

TEST(HalfSector, AxisOutOfThePlaneIsRefused) {
  try {
    mesh_case(one_body(cylinder({0, 0.01, 0.05}, Sector::Half, NoseGeometry::Shape::Flat), 0.002));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a half cylinder's axis must lie in the x–z plane"),
              std::string::npos)
        << e.what();
  }
}

} // namespace
} // namespace sphfem
