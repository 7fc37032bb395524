// Tests of mesher/interface_tags.hpp (METHOD.md §4.1): the background nodes and interface flags
// that meshing a coupled case gives, against counts predicted by hand from the geometry; the
// surface nodes of hex bodies; the point grid against brute force; the tags through model.h5.
#include "mesher/interface_tags.hpp"
#include "mesher/mesher.hpp"
#include "mesher/point_grid.hpp"
#include "solver/io/model_h5.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>

namespace sphfem {
namespace {

constexpr double mm = 1e-3;

BodySpec fem_box(const std::string& name, const Vec3& min, const Vec3& max, double size) {
  BodySpec b;
  b.name = name;
  b.method = Method::Fem;
  b.geometry.box = {min * mm, max * mm};
  b.element_size = size * mm;
  b.material = "steel";
  return b;
}

BodySpec sph_box(const std::string& name, const Vec3& min, const Vec3& max, double spacing) {
  BodySpec b = fem_box(name, min, max, 0);
  b.method = Method::Sph;
  b.spacing = spacing * mm;
  b.lattice = BodySpec::Lattice::Nodes;
  return b;
}

Case case_of(std::vector<BodySpec> bodies) {
  Case c;
  c.name = "interface_tags_test";
  c.materials.push_back({.name = "steel",
                         .model = "elastic",
                         .density = 7830,
                         .youngs_modulus = 207e9,
                         .poisson_ratio = 0.3});
  c.bodies = std::move(bodies);
  return c;
}

// The paper's set-up in small: an FE bar 0..4 × 0..4 × 5..8 mm (1 mm hexes: 5 × 5 × 4 = 100
// nodes at z = 5, 6, 7, 8 mm) glued on an SPH bar 0..4 × 0..4 × 0..5 mm (lattice nodes, Δp = 1 mm:
// 5 × 5 × 6 = 150 particles at z = 0 … 5 mm, h = 1.2 mm, 2h = 2.4 mm).
Case attached_bars() {
  Case c = case_of(
      {fem_box("bar_fe", {0, 0, 5}, {4, 4, 8}, 1), sph_box("bar_sph", {0, 0, 0}, {4, 4, 5}, 1)});
  c.attachments.push_back({"bar_fe", "bar_sph"});
  return c;
}

int count_ones(const std::vector<int>& flags) {
  return static_cast<int>(std::ranges::count(flags, 1));
}

TEST(InterfaceTags, AttachmentTagsTheNodesWithin2hOfTheParticles) {
  const Model m = mesh_case(attached_bars());
  ASSERT_EQ(m.node_count(), 100);
  ASSERT_EQ(m.particle_count(), 150);
  // Nodes and particles share the 1 mm grid in x and y, so the particle nearest to an FE node
  // (x, y, z) is (x, y, 5 mm), at z − 5 mm: 0, 1, 2 mm for the layers z = 5, 6, 7 mm (< 2.4 mm)
  // and 3 mm for z = 8 mm. Predicted: 3 layers × 25 = 75 background nodes, the top layer free.
  ASSERT_EQ(m.background_nodes.size(), 75u);
  ASSERT_EQ(m.h_background.size(), 75u);
  ASSERT_EQ(m.spacing_background.size(), 75u);
  EXPECT_TRUE(std::ranges::is_sorted(m.background_nodes));
  for (std::size_t b = 0; b < m.background_nodes.size(); ++b) {
    EXPECT_LT(m.x_n[static_cast<std::size_t>(m.background_nodes[b])].z(), 7.5 * mm);
    // The SPH bar's h = 1.2 · 1 mm and Δp = 1 mm; gmsh places nodes to ~1e-16 m, the values
    // are set, not computed from positions: exact up to the product's rounding.
    EXPECT_NEAR(m.h_background[b], 1.2 * mm, 1e-15);
    EXPECT_NEAR(m.spacing_background[b], 1.0 * mm, 1e-15);
  }
  // A particle (x, y, z) is closest to the background node (x, y, 5 mm), at 5 mm − z; it is at
  // the interface if that is below h_i + h_b = 2.4 mm: the layers z = 5, 4, 3 mm (0, 1, 2 mm),
  // not z = 2 mm (3 mm). Predicted: 3 layers × 25 = 75 interface particles.
  ASSERT_EQ(m.interface_p.size(), 150u);
  EXPECT_EQ(count_ones(m.interface_p), 75);
  for (Index i = 0; i < m.particle_count(); ++i)
    EXPECT_EQ(m.interface_p[i], m.x_p[i].z() > 2.5 * mm ? 1 : 0) << "particle " << i;
}

// Two separated FE boxes in contact: exactly their surface nodes, count = all − interior.
TEST(InterfaceTags, ContactTagsTheSurfaceNodesOfFeBodies) {
  BodySpec upper = fem_box("upper", {0, 0, 5}, {2, 2, 7}, 1);
  upper.h_factor = 1.5;
  Case c = case_of({fem_box("lower", {0, 0, 0}, {4, 4, 3}, 1), upper});
  c.contacts.push_back({{"lower", "upper"}, ContactModel::Surface, 1e11});
  const Model m = mesh_case(c);
  // lower: 5 × 5 × 4 = 100 nodes, interior 3 × 3 × 2 = 18, surface 82;
  // upper: 3 × 3 × 3 = 27 nodes, interior 1, surface 26. Together 108.
  ASSERT_EQ(m.node_count(), 127);
  ASSERT_EQ(m.background_nodes.size(), 108u);
  std::set<Index> interior;
  for (Index n = 0; n < m.node_count(); ++n) {
    const Vec3 x = m.x_n[n] / mm;
    const bool in_lower = m.body_n[n] == 0;
    const Vec3 high = in_lower ? Vec3(4, 4, 3) : Vec3(2, 2, 7);
    const Vec3 low = in_lower ? Vec3(0, 0, 0) : Vec3(0, 0, 5);
    if (((x - low).array() > 0.5).all() && ((high - x).array() > 0.5).all())
      interior.insert(n);
  }
  EXPECT_EQ(interior.size(), 19u);
  for (std::size_t b = 0; b < m.background_nodes.size(); ++b) {
    const Index n = m.background_nodes[b];
    EXPECT_FALSE(interior.contains(n)) << "node " << n;
    // h = h_factor · element_size (1.2 default, 1.5 for upper); spacing = element_size.
    EXPECT_NEAR(m.h_background[b], (m.body_n[n] == 0 ? 1.2 : 1.5) * mm, 1e-15);
    EXPECT_NEAR(m.spacing_background[b], 1.0 * mm, 1e-15);
  }
  EXPECT_TRUE(m.interface_p.empty()); // no particles
}

// A body both attached and in contact: attachment values win where both tag a node.
TEST(InterfaceTags, AttachmentValuesWinOverContact) {
  Case c = attached_bars();
  c.bodies[0].h_factor = 1.5;
  c.bodies.push_back(fem_box("anvil", {0, 0, 20}, {2, 2, 22}, 1));
  c.contacts.push_back({{"anvil", "bar_fe"}, ContactModel::Kernel, 1e11, 2});
  const Model m = mesh_case(c);
  // bar_fe: its 75 attached nodes (z ≤ 7 mm, h 1.2 mm, which include its interior nodes at z = 6
  // and 7 mm) and its remaining surface, the top layer z = 8 mm (25 nodes, h 1.5 · 1 mm);
  // anvil: 27 − 1 interior = 26 nodes, h 1.2 mm. Together 126.
  ASSERT_EQ(m.background_nodes.size(), 126u);
  for (std::size_t b = 0; b < m.background_nodes.size(); ++b) {
    const Vec3& x = m.x_n[static_cast<std::size_t>(m.background_nodes[b])];
    const bool top = x.z() > 7.5 * mm && x.z() < 8.5 * mm;
    EXPECT_NEAR(m.h_background[b], (top ? 1.5 : 1.2) * mm, 1e-15);
  }
  // The top layer is 3 mm from the nearest particles, beyond 1.2 + 1.5 = 2.7 mm: the interface
  // particles are the same 75.
  EXPECT_EQ(count_ones(m.interface_p), 75);
}

// An FE bar glued to two SPH bars: a node both reach takes the larger h, in either list order.
TEST(InterfaceTags, NodeOfTwoAttachmentsTakesTheLargerH) {
  Case c = attached_bars();
  c.bodies.push_back(sph_box("cap", {0, 0, 8}, {4, 4, 12}, 2)); // h 2.4 mm, reach 4.8 mm
  c.attachments.push_back({"bar_fe", "cap"});
  const Model m = mesh_case(c);
  // cap's particles at z = 8, 10, 12 mm, x, y on a 2 mm grid: every bar_fe node is within
  // √(1² + 1² + 3²) = 3.3 mm < 4.8 mm of one.
  ASSERT_EQ(m.background_nodes.size(), 100u);
  for (std::size_t b = 0; b < 100; ++b) {
    EXPECT_NEAR(m.h_background[b], 2.4 * mm, 1e-15);
    EXPECT_NEAR(m.spacing_background[b], 2.0 * mm, 1e-15);
  }
  std::swap(c.attachments[0], c.attachments[1]);
  const Model swapped = mesh_case(c);
  EXPECT_EQ(swapped.background_nodes, m.background_nodes);
  EXPECT_EQ(swapped.h_background, m.h_background);
  EXPECT_EQ(swapped.spacing_background, m.spacing_background);
  EXPECT_EQ(swapped.interface_p, m.interface_p);
}

TEST(InterfaceTags, UncoupledModelsHaveNoTags) {
  const Model m = mesh_case(case_of(
      {fem_box("plate", {0, 0, 0}, {4, 4, 1}, 1), sph_box("ball", {0, 0, 2}, {2, 2, 4}, 1)}));
  EXPECT_TRUE(m.background_nodes.empty());
  EXPECT_TRUE(m.h_background.empty());
  EXPECT_TRUE(m.spacing_background.empty());
  EXPECT_EQ(m.interface_p, std::vector<int>(27, 0));
}

// The boundary found from the hexahedra equals the union of the named faces' node sets.
TEST(InterfaceTags, SurfaceNodesAreTheNamedFacesNodes) {
  BodySpec rod;
  rod.name = "rod";
  rod.geometry.kind = GeometrySpec::Kind::Cylinder;
  rod.geometry.cylinder = {Vec3(0, 0, 0.01), Vec3(0.002, 0, 0.02), 0.005};
  rod.element_size = 1e-3;
  rod.material = "steel";
  const Model m = mesh_case(case_of({fem_box("block", {0, 0, 0}, {5, 3, 2}, 1), rod}));
  for (const auto& [body, faces] :
       {std::pair<int, std::vector<std::string>>{
            0,
            {"block/xmin", "block/xmax", "block/ymin", "block/ymax", "block/zmin", "block/zmax"}},
        {1, {"rod/base", "rod/top", "rod/side"}}}) {
    std::set<Index> expected;
    for (const std::string& face : faces)
      expected.insert(m.node_sets.at(face).begin(), m.node_sets.at(face).end());
    const std::vector<Index> found = mesher::surface_nodes(m, body);
    EXPECT_EQ(std::set<Index>(found.begin(), found.end()), expected) << "body " << body;
    EXPECT_TRUE(std::ranges::is_sorted(found));
    EXPECT_EQ(std::set<Index>(found.begin(), found.end()).size(), found.size());
  }
  EXPECT_EQ(mesher::surface_nodes(m, 0).size(), 6u * 4u * 3u - 4u * 2u * 1u); // all − interior
}

// The grid answers "any point within r of x?" exactly as an all-pairs search does.
TEST(PointGrid, AgreesWithBruteForce) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> points(2000);
  for (Vec3& p : points)
    p = Vec3(u(random), 0.3 * u(random), 2 * u(random));
  for (const double r : {0.01, 0.05, 0.2, 3.0}) {
    const mesher::PointGrid grid(points, r);
    int hits = 0;
    for (int q = 0; q < 3000; ++q) {
      const Vec3 x(1.2 * u(random), 0.4 * u(random), 2.2 * u(random));
      const auto near = [&](const Vec3& p) { return (p - x).norm() < r; };
      const bool expected = std::ranges::any_of(points, near);
      const bool found = grid.any_near(x, [&](Index j) { return near(grid.point(j)); });
      EXPECT_EQ(found, expected) << "r " << r << " query " << q;
      hits += expected;
    }
    EXPECT_GT(hits, 0) << r; // the radii are not all trivially empty or full
  }
  const mesher::PointGrid empty({}, 1.0);
  EXPECT_FALSE(empty.any_near(Vec3::Zero(), [](Index) { return true; }));
}

// The tags that meshing gives survive model.h5 exactly.
TEST(InterfaceTags, RoundTripThroughModelH5) {
  const Model m = mesh_case(attached_bars());
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "sphfem_interface_tags_test.h5";
  write_model_h5(m, file);
  const Model read = read_model_h5(file);
  std::filesystem::remove(file);
  EXPECT_EQ(read.background_nodes, m.background_nodes);
  EXPECT_EQ(read.h_background, m.h_background);
  EXPECT_EQ(read.spacing_background, m.spacing_background);
  EXPECT_EQ(read.interface_p, m.interface_p);
  EXPECT_EQ(read.signature, m.signature);
}

} // namespace
} // namespace sphfem
