// Tests of mesher/mesher.hpp: box, cylinder and quarter-cylinder hex meshes checked against
// independent geometry (hex_checks.hpp: tetrahedral volumes, corner Jacobians, face normals and
// areas, conformity), two-body and mixed FE/SPH models, mesh signatures and errors. Rings:
// ring_test.cpp; SPH lattices: lattice_test.cpp.
#include "mesher/mesher.hpp"

#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"
#include "tests/mesher/hex_checks.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>
#include <set>

namespace sphfem {
namespace {

using test::expect_valid_mesh, test::hex_volume, test::min_corner_jacobian, test::quad_normal_area,
    test::total_volume;

// ---- case construction ----------------------------------------------------------------------

BodySpec box_body(const std::string& name, const Vec3& min, const Vec3& max, double h) {
  BodySpec b;
  b.name = name;
  b.geometry.kind = GeometrySpec::Kind::Box;
  b.geometry.box = {min, max};
  b.element_size = h;
  b.material = "steel";
  return b;
}

BodySpec cylinder_body(const std::string& name, const Vec3& base, const Vec3& axis, double radius,
                       double h) {
  BodySpec b;
  b.name = name;
  b.geometry.kind = GeometrySpec::Kind::Cylinder;
  b.geometry.cylinder = {base, axis, radius};
  b.element_size = h;
  b.material = "steel";
  return b;
}

BodySpec sph_box_body(const std::string& name, const Vec3& min, const Vec3& max, double dp) {
  BodySpec b = box_body(name, min, max, 0);
  b.method = Method::Sph;
  b.spacing = dp;
  return b;
}

Case case_of(std::vector<BodySpec> bodies) {
  sphfem::Case c;
  c.name = "mesher_test";
  c.materials.push_back({.name = "steel",
                         .model = "elastic",
                         .density = 7830,
                         .youngs_modulus = 207e9,
                         .poisson_ratio = 0.3});
  c.materials.push_back({.name = "aluminium",
                         .model = "elastic",
                         .density = 2700,
                         .youngs_modulus = 70e9,
                         .poisson_ratio = 0.33});
  c.bodies = std::move(bodies);
  return c;
}

// ---- box ------------------------------------------------------------------------------------

struct BoxCase {
  Vec3 min, max;
  double h;
  std::array<int, 3> n; // expected divisions
};

void PrintTo(const BoxCase& c, std::ostream* out) {
  *out << c.n[0] << "x" << c.n[1] << "x" << c.n[2] << " hexes";
}

class BoxMesh : public ::testing::TestWithParam<BoxCase> {};

TEST_P(BoxMesh, IsStructuredWithExactVolumeAndNamedFaces) {
  const BoxCase& p = GetParam();
  const Model m = mesh_case(case_of({box_body("plate", p.min, p.max, p.h)}));
  const auto [nx, ny, nz] = p.n;
  const Vec3 size = p.max - p.min;

  ASSERT_EQ(m.body_names, std::vector<std::string>{"plate"});
  EXPECT_EQ(m.element_count(), nx * ny * nz);
  EXPECT_EQ(m.node_count(), (nx + 1) * (ny + 1) * (nz + 1));
  EXPECT_TRUE(std::all_of(m.body_n.begin(), m.body_n.end(), [](int b) { return b == 0; }));
  EXPECT_TRUE(std::all_of(m.body_e.begin(), m.body_e.end(), [](int b) { return b == 0; }));
  const double volume = size.prod();
  EXPECT_NEAR(total_volume(m, 0), volume, 1e-12 * volume);
  expect_valid_mesh(m);

  const std::array<int, 3> n{nx, ny, nz};
  const char* axes = "xyz";
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (const bool high : {false, true}) {
      const std::string name = std::string("plate/") + axes[a] + (high ? "max" : "min");
      ASSERT_TRUE(m.face_sets.contains(name)) << name;
      const auto& quads = m.face_sets.at(name);
      const auto& nodes = m.node_sets.at(name);
      EXPECT_EQ(quads.size(), static_cast<std::size_t>(n[b] * n[c])) << name;
      EXPECT_EQ(nodes.size(), static_cast<std::size_t>((n[b] + 1) * (n[c] + 1))) << name;
      const double plane = high ? p.max[a] : p.min[a];
      for (const Index i : nodes)
        EXPECT_NEAR(m.x_n[i][a], plane, 1e-12 * size.norm()) << name;
      Vec3 area = Vec3::Zero();
      for (const Quad& q : quads)
        area += quad_normal_area(m, q);
      const Vec3 expected = (high ? 1.0 : -1.0) * size[b] * size[c] * Vec3::Unit(a);
      EXPECT_NEAR((area - expected).norm(), 0, 1e-12 * size[b] * size[c]) << name;
    }
  }
  EXPECT_EQ(m.face_sets.size(), 6u);
}

INSTANTIATE_TEST_SUITE_P(
    Boxes, BoxMesh,
    ::testing::Values(BoxCase{{0, 0, 0}, {0.05, 0.04, 0.03}, 0.01, {5, 4, 3}},
                      BoxCase{{0.1, -0.2, 0.3}, {0.147, -0.176, 0.312}, 0.01, {5, 2, 1}},
                      BoxCase{{-1, -1, -1}, {1, 1, 1}, 5.0, {1, 1, 1}}));

// ---- cylinder -------------------------------------------------------------------------------

// Checks the mesh of body 0 against the cylinder it should fill.
void expect_cylinder(const Model& m, const CylinderGeometry& g, double h) {
  expect_valid_mesh(m);
  const double length = g.axis.norm(), r = g.radius;
  const Vec3 a = g.axis / length;
  const auto axial = [&](Index i) { return (m.x_n[i] - g.base).dot(a); };
  const auto radial = [&](Index i) {
    const Vec3 d = m.x_n[i] - g.base;
    return (d - d.dot(a) * a).norm();
  };
  for (const std::string face : {"base", "top", "side"})
    ASSERT_TRUE(m.node_sets.contains("rod/" + face)) << face;
  for (const Index i : m.node_sets.at("rod/side"))
    EXPECT_NEAR(radial(i), r, 1e-9 * r);
  for (const Index i : m.node_sets.at("rod/base"))
    EXPECT_NEAR(axial(i), 0, 1e-12 * length);
  for (const Index i : m.node_sets.at("rod/top"))
    EXPECT_NEAR(axial(i), length, 1e-12 * length);
  for (Index i = 0; i < m.node_count(); ++i) {
    EXPECT_LE(radial(i), r * (1 + 1e-12));
    EXPECT_GE(axial(i), -1e-12 * length);
    EXPECT_LE(axial(i), length * (1 + 1e-12));
  }

  // Layers along the axis, and the rim polygon (its vertices are the side nodes on the base).
  const int layers = std::max(1, static_cast<int>(std::lround(length / h)));
  const std::size_t rim = m.node_sets.at("rod/side").size() / (layers + 1);
  EXPECT_EQ(m.node_sets.at("rod/side").size(), rim * (layers + 1));
  EXPECT_EQ(rim % 4, 0u);
  // Straight-edged hexes fill the prism over the inscribed rim polygon, whose area A_N =
  // (N/2) R² sin(2π/N) satisfies πR²(1 − (2π/N)²/6) ≤ A_N ≤ πR².
  const double n = static_cast<double>(rim), exact = std::numbers::pi * r * r * length;
  const double volume = total_volume(m, 0);
  EXPECT_LE(volume, exact);
  EXPECT_GE(volume, exact * (1 - std::pow(2 * std::numbers::pi / n, 2) / 6));
  EXPECT_NEAR(volume, 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n) * length,
              1e-12 * exact); // the rim nodes are equally spaced in angle

  // Element size close to the requested one: the core's sides (2c = R, n/4 elements each) get
  // about h, the rim arcs π/2 · R/(n/4), about π/2 h.
  const double core_side = 4 * r / n, circumferential = 2 * std::numbers::pi * r / n;
  EXPECT_GT(core_side, 0.7 * h);
  EXPECT_LT(core_side, 1.4 * h);
  EXPECT_NEAR(circumferential, 0.5 * std::numbers::pi * core_side, 1e-12 * r);
  EXPECT_NEAR(length / layers, h, 0.5 * h);
}

TEST(CylinderMesh, AlongZIsHexOnlyWithRoundSideAndFlatEnds) {
  const CylinderGeometry g{{0, 0, 0}, {0, 0, 0.1}, 0.02};
  const Model m = mesh_case(case_of({cylinder_body("rod", g.base, g.axis, g.radius, 0.005)}));
  EXPECT_EQ(m.face_sets.size(), 3u);
  expect_cylinder(m, g, 0.005);
}

TEST(CylinderMesh, ArbitraryAxesWork) {
  for (const CylinderGeometry& g :
       {CylinderGeometry{{1, 2, 3}, {0.08, 0, 0}, 0.01},
        CylinderGeometry{{0, 0, 0}, {0, -0.05, 0}, 0.012},
        CylinderGeometry{{-0.1, 0.2, 0}, Vec3(1, 2, -0.5).normalized() * 0.06, 0.015}}) {
    SCOPED_TRACE(::testing::Message() << "axis " << g.axis.transpose());
    const Model m = mesh_case(case_of({cylinder_body("rod", g.base, g.axis, g.radius, 0.004)}));
    expect_cylinder(m, g, 0.004);
  }
}

TEST(CylinderMesh, CoarseCylinderStillValid) {
  const CylinderGeometry g{{0, 0, 0}, {0, 0, 0.01}, 0.004};
  const Model m = mesh_case(case_of({cylinder_body("rod", g.base, g.axis, g.radius, 0.02)}));
  expect_valid_mesh(m);
  EXPECT_EQ(m.element_count(), 12); // 4 quadrants of core + 2 ring blocks, one layer
}

// ---- quarter cylinder -----------------------------------------------------------------------

BodySpec quarter_cylinder_body(const Vec3& base, double length, double radius, double h) {
  BodySpec b = cylinder_body("rod", base, {0, 0, length}, radius, h);
  b.geometry.cylinder.sector = Sector::Quarter;
  return b;
}

// R = 10 mm, L = 80 mm, h = 1 mm: n = round(c / h) = 5 hexes along each 45° arc and core
// side (c = R/2), round(R − c(1 + √2)/2) = 4 radially, 80 layers.
TEST(QuarterCylinderMesh, IsTheQuarterOGridWithFlatCutFaces) {
  const Vec3 base(0.01, -0.02, 0.003);
  const double r = 0.01, length = 0.08, h = 0.001;
  const int n = 5, radial = 4, layers = 80;
  const Model m = mesh_case(case_of({quarter_cylinder_body(base, length, r, h)}));
  expect_valid_mesh(m);
  // Per layer: the core's n² and the two ring blocks' n·radial hexes; per plane: the core's
  // (n + 1)² nodes and the ring's (2n + 1)·radial beyond the core.
  const int plane = (n + 1) * (n + 1) + (2 * n + 1) * radial;
  EXPECT_EQ(m.element_count(), (n * n + 2 * n * radial) * layers);
  EXPECT_EQ(m.node_count(), plane * (layers + 1));

  const std::map<std::string, std::size_t> expected_nodes{
      {"rod/base", plane},
      {"rod/top", plane},
      {"rod/side", (2 * n + 1) * (layers + 1)},
      {"rod/xmin", (n + radial + 1) * (layers + 1)},
      {"rod/ymin", (n + radial + 1) * (layers + 1)}};
  ASSERT_EQ(m.node_sets.size(), expected_nodes.size());
  for (const auto& [name, count] : expected_nodes) {
    ASSERT_TRUE(m.node_sets.contains(name)) << name;
    EXPECT_EQ(m.node_sets.at(name).size(), count) << name;
  }
  // Nodes on their planes and the rim to round-off (1e-15 m is a few ulps of 0.08 m).
  const auto d = [&](Index i) { return Vec3(m.x_n[i] - base); };
  for (const Index i : m.node_sets.at("rod/xmin"))
    EXPECT_NEAR(d(i).x(), 0, 1e-15);
  for (const Index i : m.node_sets.at("rod/ymin"))
    EXPECT_NEAR(d(i).y(), 0, 1e-15);
  for (const Index i : m.node_sets.at("rod/base"))
    EXPECT_NEAR(d(i).z(), 0, 1e-15);
  for (const Index i : m.node_sets.at("rod/top"))
    EXPECT_NEAR(d(i).z(), length, 1e-15);
  for (const Index i : m.node_sets.at("rod/side"))
    EXPECT_NEAR(d(i).head<2>().norm(), r, 1e-15);
  for (Index i = 0; i < m.node_count(); ++i) {
    EXPECT_GE(d(i).x(), -1e-15);
    EXPECT_GE(d(i).y(), -1e-15);
    EXPECT_LE(d(i).head<2>().norm(), r + 1e-15);
  }
  // Outward normals of the cut faces are −x and −y; their areas are those of the rectangles.
  for (const auto& [name, axis] : {std::pair{"rod/xmin", 0}, std::pair{"rod/ymin", 1}}) {
    Vec3 area = Vec3::Zero();
    for (const Quad& q : m.face_sets.at(name))
      area += quad_normal_area(m, q);
    EXPECT_NEAR((area + r * length * Vec3::Unit(axis)).norm(), 0, 1e-12 * r * length) << name;
  }

  // The hexes fill the prism over the inscribed polygon of the quarter rim: 2n chords of
  // θ = π/(4n), area n R² sin θ, short of π R²/4 by at most (π R²/4)·θ²/6 (θ − sin θ ≤ θ³/6).
  const double theta = std::numbers::pi / (4 * n);
  const double exact = 0.25 * std::numbers::pi * r * r * length;
  const double volume = total_volume(m, 0);
  EXPECT_NEAR(volume, n * r * r * std::sin(theta) * length, 1e-12 * exact);
  EXPECT_LE(volume, exact);
  EXPECT_GE(volume, exact * (1 - theta * theta / 6));
}

TEST(QuarterCylinderMesh, AxisMustBeAlongPlusZ) {
  for (const Vec3& axis : {Vec3(0, 0, -0.05), Vec3(0.05, 0, 0), Vec3(0.001, 0, 0.05)}) {
    BodySpec rod = quarter_cylinder_body(Vec3::Zero(), 0.05, 0.01, 0.002);
    rod.geometry.cylinder.axis = axis;
    try {
      mesh_case(case_of({rod}));
      ADD_FAILURE() << "no error for axis " << axis.transpose();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("along +z"), std::string::npos) << e.what();
    }
  }
}

// ---- several bodies -------------------------------------------------------------------------

TEST(MultiBody, BodiesHaveDistinctNodesAndRightIds) {
  const double h = 0.01;
  const Model m = mesh_case(case_of({box_body("a", {0, 0, 0}, {0.03, 0.02, 0.02}, h),
                                     box_body("b", {0, 0, 0.02}, {0.03, 0.02, 0.05}, h),
                                     cylinder_body("rod", {0, 0, 0.1}, {0, 0, 0.04}, 0.01, h)}));
  ASSERT_EQ(m.body_names, (std::vector<std::string>{"a", "b", "rod"}));
  expect_valid_mesh(m);
  // Body ids are contiguous blocks in body order.
  EXPECT_TRUE(std::is_sorted(m.body_n.begin(), m.body_n.end()));
  EXPECT_TRUE(std::is_sorted(m.body_e.begin(), m.body_e.end()));
  EXPECT_EQ(std::count(m.body_e.begin(), m.body_e.end(), 0), 3 * 2 * 2);
  EXPECT_EQ(std::count(m.body_e.begin(), m.body_e.end(), 1), 3 * 2 * 3);
  EXPECT_EQ(std::count(m.body_n.begin(), m.body_n.end(), 0), 4 * 3 * 3);
  EXPECT_EQ(std::count(m.body_n.begin(), m.body_n.end(), 1), 4 * 3 * 4);
  for (Index e = 0; e < m.element_count(); ++e)
    for (const Index i : m.hex_e[e])
      EXPECT_EQ(m.body_n[i], m.body_e[e]);
  // The touching faces a/zmax and b/zmin share positions but not nodes.
  const auto& top = m.node_sets.at("a/zmax");
  const auto& bottom = m.node_sets.at("b/zmin");
  ASSERT_EQ(top.size(), bottom.size());
  std::vector<Index> shared;
  std::set_intersection(top.begin(), top.end(), bottom.begin(), bottom.end(),
                        std::back_inserter(shared));
  EXPECT_TRUE(shared.empty());
  for (const Index i : bottom)
    EXPECT_NEAR(m.x_n[i].z(), 0.02, 1e-15);
  EXPECT_EQ(m.face_sets.size(), 6u + 6u + 3u);
  EXPECT_NEAR(total_volume(m, 0), 0.03 * 0.02 * 0.02, 1e-12 * 1.2e-5);
  EXPECT_NEAR(total_volume(m, 1), 0.03 * 0.02 * 0.03, 1e-12 * 1.8e-5);
}

// FE and SPH bodies in one case: nodes and hexes of the FE bodies, particles of the SPH body,
// each with the body id of its position in the case; spacing 0 for FE bodies.
TEST(MultiBody, FemAndSphBodiesTogether) {
  BodySpec projectile = sph_box_body("projectile", {0, 0, 0.021}, {0.01, 0.01, 0.031}, 0.001);
  projectile.material = "aluminium";
  projectile.h_factor = 1.3;
  const Model m =
      mesh_case(case_of({box_body("plate", {0, 0, 0}, {0.03, 0.02, 0.02}, 0.01), projectile,
                         cylinder_body("rod", {0, 0, 0.1}, {0, 0, 0.04}, 0.01, 0.01)}));
  ASSERT_EQ(m.body_names, (std::vector<std::string>{"plate", "projectile", "rod"}));
  EXPECT_EQ(m.spacing_b, (std::vector<double>{0, 0.001, 0}));
  expect_valid_mesh(m);
  EXPECT_EQ(std::count(m.body_e.begin(), m.body_e.end(), 0), 3 * 2 * 2);
  EXPECT_EQ(std::count(m.body_e.begin(), m.body_e.end(), 1), 0);
  EXPECT_GT(std::count(m.body_e.begin(), m.body_e.end(), 2), 0);
  EXPECT_EQ(std::count(m.body_n.begin(), m.body_n.end(), 1), 0);
  ASSERT_EQ(m.particle_count(), 1000);
  EXPECT_TRUE(std::all_of(m.body_p.begin(), m.body_p.end(), [](int b) { return b == 1; }));
  for (Index i = 0; i < m.particle_count(); ++i) {
    EXPECT_NEAR(m.rho_p[i], 2700, 1e-12);
    EXPECT_NEAR(m.h_p[i], 1.3e-3, 1e-15);
    EXPECT_GT(m.x_p[i].z(), 0.021);
    EXPECT_LT(m.x_p[i].z(), 0.031);
  }
  const double mass = std::accumulate(m.m_p.begin(), m.m_p.end(), 0.0);
  EXPECT_NEAR(mass, 2700 * 1e-6, 1e-12 * 2700 * 1e-6);
  EXPECT_EQ(m.face_sets.size(), 6u + 3u); // none for the SPH body
  EXPECT_FALSE(m.face_sets.contains("projectile/zmin"));
  EXPECT_FALSE(m.node_sets.contains("projectile/zmin"));
  // The SPH box has particle faces instead (lattice_test.cpp checks them); the FE bodies none.
  EXPECT_EQ(m.particle_faces.size(), 6u);
  EXPECT_EQ(m.particle_faces.at("projectile/zmin").particles.size(), 100u);
}

TEST(MultiBody, SphOnlyCaseNeedsNoMesh) {
  const Model m = mesh_case(case_of({sph_box_body("a", {0, 0, 0}, {0.002, 0.002, 0.002}, 0.001),
                                     sph_box_body("b", {0, 0, 1}, {0.003, 0.001, 1.001}, 0.001)}));
  EXPECT_EQ(m.node_count(), 0);
  EXPECT_EQ(m.element_count(), 0);
  EXPECT_EQ(m.body_p, (std::vector<int>{0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1}));
  EXPECT_EQ(m.spacing_b, (std::vector<double>{0.001, 0.001}));
}

TEST(MultiBody, MeshingIsDeterministic) {
  const Case c = case_of({cylinder_body("rod", {0, 0, 0}, {0.01, 0.02, 0.03}, 0.01, 0.004)});
  const Model a = mesh_case(c), b = mesh_case(c);
  EXPECT_EQ(a.x_n, b.x_n);
  EXPECT_EQ(a.hex_e, b.hex_e);
  EXPECT_EQ(a.face_sets, b.face_sets);
}

// ---- hex ordering -----------------------------------------------------------------------

TEST(HexOrder, InvertedHexesAreMirroredToPositiveVolume) {
  Model m;
  m.x_n = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}, {0, 0, 3}, {2, 0, 3}, {2, 1, 3}, {0, 1, 3}};
  const Hex good{0, 1, 2, 3, 4, 5, 6, 7};
  EXPECT_EQ(mesher::with_positive_volume(m.x_n, good), good);
  for (const Hex& inverted : {Hex{0, 3, 2, 1, 4, 7, 6, 5}, Hex{4, 5, 6, 7, 0, 1, 2, 3}}) {
    EXPECT_LT(hex_volume(m, inverted), 0);
    const Hex fixed = mesher::with_positive_volume(m.x_n, inverted);
    EXPECT_NEAR(hex_volume(m, fixed), 6, 1e-14);
    EXPECT_GT(min_corner_jacobian(m, fixed), 0);
    EXPECT_TRUE(std::is_permutation(fixed.begin(), fixed.end(), good.begin()));
  }
  m.x_n[4] = m.x_n[5] = m.x_n[6] = m.x_n[7] = Vec3(1, 0.5, 0); // flattened
  EXPECT_THROW(mesher::with_positive_volume(m.x_n, good), Error);
}

// ---- signature and errors -------------------------------------------------------------------

TEST(MeshSignature, ChangesWithMeshInputsOnly) {
  const Case base = case_of({box_body("plate", {0, 0, 0}, {0.5, 0.5, 0.012}, 0.004),
                             cylinder_body("rod", {0, 0, 0.1}, {0, 0, 0.04}, 0.01, 0.002)});
  const std::string s = mesh_signature(base);
  EXPECT_EQ(mesh_signature(base), s);

  Case other = base; // keys that do not affect the mesh
  other.name = "renamed_case";
  other.bodies[0].velocity = {0, 0, -300};
  other.bodies[1].material = "aluminium";
  other.time.end = 1;
  EXPECT_EQ(mesh_signature(other), s);

  const auto changed = [&](auto edit) {
    Case c = base;
    edit(c);
    return mesh_signature(c) != s;
  };
  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].element_size = 0.005; }));
  EXPECT_TRUE(changed([](Case& c) {
    c.bodies[0].element_size = std::nextafter(c.bodies[0].element_size, 1.0); // full precision
  }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].geometry.box.max.z() = 0.01; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[1].geometry.cylinder.radius = 0.011; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[1].geometry.cylinder.axis = {0, 0.04, 0}; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[1].geometry.cylinder.base.x() = 1e-3; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[1].name = "bolt"; }));
  EXPECT_TRUE(changed([](Case& c) { std::swap(c.bodies[0], c.bodies[1]); }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies.pop_back(); }));
}

// FE-only signatures keep their earlier text, so model files made before SPH bodies existed
// are not stale.
TEST(MeshSignature, FemSignatureTextIsUnchanged) {
  const Case c = case_of({box_body("plate", {0, 0, 0}, {0.5, 0.5, 0.012}, 0.004),
                          cylinder_body("rod", {0, 0, 0.1}, {0, 0, 0.04}, 0.01, 0.002)});
  EXPECT_EQ(mesh_signature(c),
            "sphfem-mesh 2\n"
            "body plate method=fem box min=0,0,0 max=0.5,0.5,0.012 element_size=0.004\n"
            "body rod method=fem cylinder base=0,0,0.1 axis=0,0,0.04 radius=0.01 "
            "element_size=0.002\n");
}

// A quarter cylinder says so; a full one keeps the text above.
TEST(MeshSignature, QuarterCylinderIsNamed) {
  Case c = case_of({quarter_cylinder_body({0, 0, 0.1}, 0.04, 0.01, 0.002)});
  EXPECT_EQ(mesh_signature(c), "sphfem-mesh 2\n"
                               "body rod method=fem cylinder base=0,0,0.1 axis=0,0,0.04 "
                               "radius=0.01 sector=quarter element_size=0.002\n");
  c.bodies[0].geometry.cylinder.sector = Sector::Full;
  EXPECT_EQ(mesh_signature(c).find("sector"), std::string::npos);
}

TEST(MeshSignature, ChangesWithSphInputs) {
  const std::filesystem::path shape =
      std::filesystem::temp_directory_path() / "sphfem_mesher_test_signature.geo";
  std::ofstream(shape) << "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0, 0, 0.01};\n";
  BodySpec ball = sph_box_body("ball", {0, 0, 0}, {0.01, 0.01, 0.01}, 0.001);
  ball.geometry.kind = GeometrySpec::Kind::File;
  ball.geometry.file = shape;
  const Case base = case_of({sph_box_body("block", {0, 0, 0}, {0.1, 0.1, 0.01}, 0.002), ball});
  const std::string s = mesh_signature(base);
  // The lattice is named also when it is the default, so SPH models written before particle
  // faces existed are stale.
  EXPECT_NE(s.find("body block method=sph box min=0,0,0 max=0.1,0.1,0.01 spacing=0.002 "
                   "h_factor=1.2 lattice=centred density=7830\n"),
            std::string::npos)
      << s;
  EXPECT_EQ(mesh_signature(base), s);
  const auto changed = [&](auto edit) {
    Case c = base;
    edit(c);
    return mesh_signature(c) != s;
  };
  Case other = base; // keys that do not affect the model
  other.bodies[0].velocity = {0, 0, -300};
  other.sph.cfl = 0.1;
  other.materials[0].youngs_modulus = 1;
  EXPECT_EQ(mesh_signature(other), s);

  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].spacing = 0.0025; }));
  EXPECT_TRUE(changed([](Case& c) {
    c.bodies[0].spacing = std::nextafter(c.bodies[0].spacing, 1.0); // full precision
  }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].h_factor = 1.3; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].lattice = BodySpec::Lattice::Nodes; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].method = Method::Fem; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].geometry.box.max.z() = 0.02; }));
  // Particle masses and densities come from the material's density.
  EXPECT_TRUE(changed([](Case& c) { c.materials[0].density = 7800; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[1].material = "aluminium"; }));
  const std::filesystem::path copy = shape.string() + ".copy.geo"; // same bytes, other path
  std::filesystem::copy_file(shape, copy, std::filesystem::copy_options::overwrite_existing);
  EXPECT_TRUE(changed([&](Case& c) { c.bodies[1].geometry.file = copy; }));
  std::filesystem::remove(copy);

  // The file's contents, not its time stamp.
  std::ofstream(shape) << "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0, 0, 0.02};\n";
  EXPECT_NE(mesh_signature(base), s);
  std::ofstream(shape) << "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0, 0, 0.01};\n";
  EXPECT_EQ(mesh_signature(base), s);
  std::filesystem::remove(shape);
  try {
    mesh_signature(base);
    ADD_FAILURE() << "no error for a missing geometry file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("body 'ball'"), std::string::npos) << e.what();
  }
}

// Attachments and contact pairs (and a pair's model) change the interface tags, so the
// signature; their order, the order within a pair, the penalty, exponent and friction do not. An FE
// body's h_factor counts only where it is in contact (elsewhere it changes nothing).
TEST(MeshSignature, ChangesWithCouplings) {
  Case base = case_of({box_body("plate", {0, 0, 0}, {0.1, 0.1, 0.01}, 0.002),
                       sph_box_body("core", {0, 0, 0.01}, {0.01, 0.01, 0.02}, 0.001),
                       box_body("rod", {0, 0, 0.1}, {0.01, 0.01, 0.12}, 0.002)});
  const std::string uncoupled = mesh_signature(base);
  Case plate_h = base;
  plate_h.bodies[0].h_factor = 2;
  EXPECT_EQ(mesh_signature(plate_h), uncoupled);

  base.attachments.push_back({"plate", "core"});
  base.contacts.push_back({{"rod", "plate"}, ContactModel::Kernel, 1e11, 2});
  base.contacts.push_back({{"rod", "core"}, ContactModel::Surface, 2e11});
  const std::string s = mesh_signature(base);
  EXPECT_NE(s, uncoupled);
  EXPECT_TRUE(s.ends_with(
      "attach fem=plate sph=core\ncontact core rod surface\ncontact plate rod kernel\n"))
      << s;
  EXPECT_NE(s.find("body plate method=fem box min=0,0,0 max=0.1,0.1,0.01 element_size=0.002 "
                   "h_factor=1.2\n"),
            std::string::npos)
      << s;

  Case other = base; // keys that do not change the tags
  std::swap(other.contacts[0], other.contacts[1]);
  std::swap(other.contacts[0].bodies[0], other.contacts[0].bodies[1]);
  other.contacts[1].penalty = 5e11;
  other.contacts[1].exponent = 4;
  other.contacts[0].friction = 0.3;
  EXPECT_EQ(mesh_signature(other), s);

  const auto changed = [&](auto edit) {
    Case c = base;
    edit(c);
    return mesh_signature(c) != s;
  };
  EXPECT_TRUE(changed([](Case& c) { c.attachments.clear(); }));
  EXPECT_TRUE(changed([](Case& c) { c.contacts.pop_back(); }));
  EXPECT_TRUE(changed([](Case& c) { c.contacts.erase(c.contacts.begin()); }));
  EXPECT_TRUE(changed([](Case& c) { c.contacts[0].model = ContactModel::Surface; }));
  EXPECT_TRUE(changed([](Case& c) { c.bodies[0].h_factor = 1.5; })); // plate: in contact
  EXPECT_TRUE(changed([](Case& c) { c.bodies[1].h_factor = 1.5; })); // core: SPH h
  EXPECT_TRUE(changed([](Case& c) { c.bodies[2].h_factor = 1.5; })); // rod: in contact
}

void expect_error_naming(const Case& c, const std::string& body) {
  try {
    mesh_case(c);
    ADD_FAILURE() << "no error for body " << body;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + body + "'"), std::string::npos) << e.what();
  }
}

TEST(MeshErrors, BadBodiesAreNamed) {
  const BodySpec ok = box_body("ok", {0, 0, 0}, {1, 1, 1}, 0.5);
  expect_error_naming(case_of({ok, box_body("flat", {0, 0, 0}, {1, 1, 0}, 0.1)}), "flat");
  expect_error_naming(case_of({ok, box_body("zero_size", {0, 0, 0}, {1, 1, 1}, 0)}), "zero_size");
  expect_error_naming(case_of({cylinder_body("thin", {0, 0, 0}, {0, 0, 1}, 0, 0.1)}), "thin");
  expect_error_naming(case_of({cylinder_body("short", {0, 0, 0}, {0, 0, 0}, 1, 0.1)}), "short");
  expect_error_naming(case_of({ok, ok}), "ok");
  expect_error_naming(case_of({box_body("too_fine", {0, 0, 0}, {1, 1, 1}, 1e-7)}), "too_fine");
  BodySpec sph_quarter = quarter_cylinder_body({0, 0, 0}, 0.01, 0.005, 0);
  sph_quarter.name = "sph_quarter";
  sph_quarter.method = Method::Sph;
  sph_quarter.spacing = 0.001;
  expect_error_naming(case_of({sph_quarter}), "sph_quarter"); // quarters are FE only
}

} // namespace
} // namespace sphfem

TEST(MeshThreads, MeshingLeavesTheOpenMPThreadCountAlone) {
  // gmsh sets its own thread count on initialise; the solver's must survive meshing.
  const int before = omp_get_max_threads();
  sphfem::Case c;
  sphfem::BodySpec body;
  body.name = "b";
  body.geometry.box = {sphfem::Vec3::Zero(), sphfem::Vec3(1, 1, 1)};
  body.element_size = 0.5;
  c.bodies.push_back(body);
  sphfem::mesh_case(c);
  EXPECT_EQ(omp_get_max_threads(), before);
}
