// Tests of nosed cylinders (mesher/nose.cpp): hemispherical, conical and ogival noses mesh into
// valid hexahedra (positive corners, conforming, named faces complete and outward), hold the
// solid's volume (πR² for the shank, the nose's from the closed forms below, computed here
// independently of the mesher) to the faceting error of a curved surface, put their surface
// nodes on the nose, keep the smallest scaled Jacobian above 0.25 and the shortest L_e above
// 0.33 h (measured 0.50 / 0.31 / 0.29 and 0.42 / 0.37 / 0.52 h for the hemisphere, the cone and
// the ogive; the blunt projectile's shortest, 0.67–0.72 h, are its ring's diagonal corners: a
// nosed projectile's step is 0.55–0.75 of the blunt one's), and a quarter is the quadrant of the
// whole.
#include "hex_checks.hpp"

#include "mesher/mesher.hpp"
#include "solver/core/error.hpp"
#include "solver/fem/hex_quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sphfem {
namespace {

using Shape = NoseGeometry::Shape;
constexpr double R = 0.01, L = 0.08, h = 0.001; // Børvik's projectile at the standard preset

Case nosed(const NoseGeometry& nose, Sector sector, double length = L, double size = h) {
  Case c;
  c.name = "nose_test";
  c.materials.push_back({.name = "steel",
                         .model = "elastic",
                         .density = 7850,
                         .youngs_modulus = 200e9,
                         .poisson_ratio = 0.33});
  BodySpec b;
  b.name = "projectile";
  b.geometry.kind = GeometrySpec::Kind::Cylinder;
  b.geometry.cylinder.axis = {0, 0, length};
  b.geometry.cylinder.radius = R;
  b.geometry.cylinder.sector = sector;
  b.geometry.cylinder.nose = nose;
  b.element_size = size;
  b.material = "steel";
  c.bodies = {b};
  return c;
}

// The nose's radius at height z above the tip, and its volume: closed forms.
double profile(const NoseGeometry& n, double z) {
  const double ln = n.nose_length(R);
  switch (n.shape) {
  case Shape::Hemispherical:
    return std::sqrt(R * R - (R - z) * (R - z));
  case Shape::Conical:
    return R * z / ln;
  case Shape::Ogival: {
    const double rho = 2 * n.crh * R;
    return std::sqrt(rho * rho - (ln - z) * (ln - z)) - (rho - R);
  }
  case Shape::Flat:
    break;
  }
  return R;
}

double solid_volume(const NoseGeometry& n) {
  const double ln = n.nose_length(R), shank = std::numbers::pi * R * R * (L - ln);
  switch (n.shape) {
  case Shape::Hemispherical:
    return shank + 2.0 / 3 * std::numbers::pi * R * R * R;
  case Shape::Conical:
    return shank + std::numbers::pi * R * R * ln / 3;
  case Shape::Ogival: { // π ∫ r² dz with r = √(ρ² − u²) − a, u = ln − z ∈ [0, ln], a = ρ − R
    const double rho = 2 * n.crh * R, a = rho - R;
    const double integral =
        (rho * rho + a * a) * ln - ln * ln * ln / 3 -
        a * (ln * std::sqrt(rho * rho - ln * ln) + rho * rho * std::asin(ln / rho));
    return shank + std::numbers::pi * integral;
  }
  case Shape::Flat:
    break;
  }
  return shank;
}

const NoseGeometry kNoses[] = {
    {Shape::Hemispherical, 0, 0}, {Shape::Conical, 0.015, 0}, {Shape::Ogival, 0, 3.0}};

TEST(NoseMesh, ValidHexahedraHoldingTheSolid) {
  for (const NoseGeometry& nose : kNoses) {
    SCOPED_TRACE(::testing::Message() << "shape " << static_cast<int>(nose.shape));
    const Model m = mesh_case(nosed(nose, Sector::Full));
    test::expect_valid_mesh(m);
    const double volume = test::total_volume(m, 0), exact = solid_volume(nose);
    // A faceted round surface holds a little less than the solid: 5 chords of a 45° arc enclose
    // 0.41% less than the sector (printed below: the meshes hold 0.43–0.47% less).
    EXPECT_NEAR(volume / exact, 1.0, 5e-3) << volume << " against " << exact;
    const HexQuality q = hex_quality(m);
    std::cout << "nose " << static_cast<int>(nose.shape) << ": " << q.elements
              << " hexahedra, smallest scaled Jacobian " << q.scaled_jacobian << " at "
              << q.worst_jacobian_at.transpose() << ", shortest L_e " << q.length << " at "
              << q.shortest_at.transpose() << ", volume / solid's " << volume / exact << "\n";
    EXPECT_GT(q.scaled_jacobian, 0.25);
    EXPECT_GT(q.length, 0.33 * h);
    // The nose's surface nodes lie on it: r = r(z) at their height.
    double worst = 0;
    const double ln = nose.nose_length(R);
    for (const Quad& quad : m.face_sets.at("projectile/base"))
      for (const Index i : quad) {
        const Vec3& x = m.x_n[static_cast<std::size_t>(i)];
        ASSERT_LE(x.z(), ln * (1 + 1e-9));
        worst = std::max(worst, std::abs(x.head<2>().norm() - profile(nose, x.z())));
      }
    EXPECT_LT(worst, 0.02 * h) << "a node of the nose lies " << worst << " m off its surface";
  }
}

TEST(NoseMesh, QuarterIsTheQuadrantOfTheWhole) {
  for (const NoseGeometry& nose : kNoses) {
    SCOPED_TRACE(::testing::Message() << "shape " << static_cast<int>(nose.shape));
    const Model whole = mesh_case(nosed(nose, Sector::Full));
    const Model quarter = mesh_case(nosed(nose, Sector::Quarter));
    test::expect_valid_mesh(quarter);
    EXPECT_EQ(4 * quarter.element_count(), whole.element_count());
    EXPECT_NEAR(4 * test::total_volume(quarter, 0) / test::total_volume(whole, 0), 1.0, 1e-9);
    EXPECT_EQ(quarter.face_sets.count("projectile/xmin"), 1u);
    EXPECT_EQ(quarter.face_sets.count("projectile/ymin"), 1u);
  }
}

} // namespace
} // namespace sphfem
