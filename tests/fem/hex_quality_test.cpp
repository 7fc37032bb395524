// Tests of hexahedron quality (solver/fem/hex_quality.hpp) against closed forms: a box has
// scaled Jacobian 1 and L_e its shortest side; a hexahedron sheared by angle θ in one plane has
// cos θ at every corner; flattening a corner to a plane gives 0, inverting the hex a negative
// value; the model-wide search finds the worst element of the body asked for.
#include "solver/fem/hex_quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sphfem {
namespace {

// A box a × b × c in gmsh order, sheared by `shear` (x += shear · z).
HexPoints box(double a, double b, double c, double shear = 0) {
  HexPoints x{Vec3(0, 0, 0), Vec3(a, 0, 0), Vec3(a, b, 0), Vec3(0, b, 0),
              Vec3(0, 0, c), Vec3(a, 0, c), Vec3(a, b, c), Vec3(0, b, c)};
  for (Vec3& p : x)
    p.x() += shear * p.z();
  return x;
}

TEST(HexQuality, BoxShearFlatAndInverted) {
  EXPECT_NEAR(hex8_scaled_jacobian(box(1, 2, 3)), 1.0, 1e-14);
  EXPECT_NEAR(hex8_characteristic_length(box(1, 2, 3), 6.0), 1.0, 1e-14); // V / largest face
  const double theta = std::numbers::pi / 6; // 30° lean of the z edges
  EXPECT_NEAR(hex8_scaled_jacobian(box(1, 1, 1, std::tan(theta))), std::cos(theta), 1e-14);
  HexPoints flat = box(1, 1, 1);
  flat[4].z() = 0; // corner 0's three edges in the plane z = 0
  EXPECT_NEAR(hex8_scaled_jacobian(flat), 0.0, 1e-14);
  HexPoints inverted = box(1, 1, 1);
  std::swap(inverted[1], inverted[3]);
  std::swap(inverted[5], inverted[7]);
  EXPECT_LT(hex8_scaled_jacobian(inverted), 0.0);
}

TEST(HexQuality, ModelSearchFindsTheWorstElementOfTheBody) {
  Model m;
  const auto add = [&m](const HexPoints& x, int body) {
    Hex h;
    for (int a = 0; a < 8; ++a) {
      h[a] = static_cast<Index>(m.x_n.size());
      m.x_n.push_back(x[a] + Vec3(10.0 * m.hex_e.size(), 0, 0));
    }
    m.hex_e.push_back(h);
    m.body_e.push_back(body);
  };
  add(box(1, 1, 1), 0);
  add(box(1, 1, 0.5, 0.5), 0); // sheared and thin: worst of body 0 on both counts
  add(box(0.1, 1, 1, 2.0), 1); // worse still, but in body 1
  const HexQuality q = hex_quality(m, 0);
  EXPECT_EQ(q.elements, 2);
  EXPECT_EQ(q.worst_jacobian, 1);
  EXPECT_EQ(q.shortest, 1);
  EXPECT_NEAR(q.scaled_jacobian, std::cos(std::atan(0.5)), 1e-14);
  EXPECT_NEAR(q.length, 0.5, 1e-12); // V = 0.5, largest face 1 × 1
  EXPECT_EQ(hex_quality(m).worst_jacobian, 2);
}

} // namespace
} // namespace sphfem
