// Tests of the SPH lattices (mesher/lattice.hpp through mesh_case): box lattices checked exactly
// (counts, positions, masses, h), the node lattice also against the hex mesh of the same box
// (node positions, lumped masses), box particle faces (layers, tributary areas, normals),
// cylinders and geometry files against independent inside tests and volume bounds, the
// ray-parity classifier on surfaces whose edges and vertices lie exactly on lattice columns, and
// the errors naming the body.
#include "mesher/lattice.hpp"
#include "mesher/mesher.hpp"

#include "solver/core/error.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>
#include <random>
#include <set>

namespace sphfem {
namespace {

namespace fs = std::filesystem;

constexpr double rho0 = 7830; // kg/m³
const fs::path data_dir = fs::path(SPHFEM_SOURCE_DIR) / "tests" / "mesher" / "data";

BodySpec sph_body(const std::string& name, double spacing) {
  BodySpec b;
  b.name = name;
  b.method = Method::Sph;
  b.spacing = spacing;
  b.material = "steel";
  return b;
}

BodySpec sph_box(const std::string& name, const Vec3& min, const Vec3& max, double spacing) {
  BodySpec b = sph_body(name, spacing);
  b.geometry.kind = GeometrySpec::Kind::Box;
  b.geometry.box = {min, max};
  return b;
}

BodySpec sph_cylinder(const std::string& name, const CylinderGeometry& g, double spacing) {
  BodySpec b = sph_body(name, spacing);
  b.geometry.kind = GeometrySpec::Kind::Cylinder;
  b.geometry.cylinder = g;
  return b;
}

BodySpec sph_file(const std::string& name, const fs::path& file, double spacing) {
  BodySpec b = sph_body(name, spacing);
  b.geometry.kind = GeometrySpec::Kind::File;
  b.geometry.file = file;
  return b;
}

Case case_of(std::vector<BodySpec> bodies) {
  Case c;
  c.name = "lattice_test";
  c.materials.push_back({.name = "steel",
                         .model = "elastic",
                         .density = rho0,
                         .youngs_modulus = 207e9,
                         .poisson_ratio = 0.3});
  c.bodies = std::move(bodies);
  return c;
}

double total_mass(const Model& m) {
  return std::accumulate(m.m_p.begin(), m.m_p.end(), 0.0);
}

// Every particle array has one entry per particle; all particles belong to body `body`, have
// density ρ0, mass ρ0·`volume` and h = `h`.
void expect_uniform_particles(const Model& m, int body, double volume, double h) {
  const std::size_t p = m.x_p.size();
  ASSERT_EQ(m.m_p.size(), p);
  ASSERT_EQ(m.rho_p.size(), p);
  ASSERT_EQ(m.h_p.size(), p);
  ASSERT_EQ(m.body_p.size(), p);
  for (std::size_t i = 0; i < p; ++i) {
    EXPECT_EQ(m.body_p[i], body);
    EXPECT_EQ(m.rho_p[i], rho0);
    EXPECT_NEAR(m.m_p[i], rho0 * volume, 1e-12 * rho0 * volume);
    EXPECT_NEAR(m.h_p[i], h, 1e-15 * h);
  }
}

// The sorted distinct values of coordinate `axis` over the particles.
std::vector<double> levels(const Model& m, int axis) {
  std::set<double> values;
  for (const Vec3& x : m.x_p)
    values.insert(x[axis]);
  return {values.begin(), values.end()};
}

// ---- box ------------------------------------------------------------------------------------

TEST(BoxLattice, TilesTheBoxWithCellCentredParticles) {
  const Vec3 min(0.1, -0.2, 0.3), max(0.15, -0.16, 0.33);
  const double dp = 0.01;
  const Model m = mesh_case(case_of({sph_box("block", min, max, dp)}));
  ASSERT_EQ(m.body_names, std::vector<std::string>{"block"});
  EXPECT_EQ(m.spacing_b, std::vector<double>{dp});
  EXPECT_EQ(m.node_count(), 0);
  EXPECT_EQ(m.element_count(), 0);
  ASSERT_EQ(m.particle_count(), 5 * 4 * 3);
  expect_uniform_particles(m, 0, dp * dp * dp, 1.2 * dp);
  const double volume = (max - min).prod();
  EXPECT_NEAR(total_mass(m), rho0 * volume, 1e-12 * rho0 * volume);
  // The positions are exactly the lattice min + (k + ½)Δp, each once.
  const std::array<int, 3> n{5, 4, 3};
  for (int a = 0; a < 3; ++a) {
    const std::vector<double> x = levels(m, a);
    ASSERT_EQ(x.size(), static_cast<std::size_t>(n[a]));
    for (int k = 0; k < n[a]; ++k)
      EXPECT_NEAR(x[k], min[a] + (k + 0.5) * dp, 1e-12);
    EXPECT_NEAR(x.front(), min[a] + 0.5 * dp, 1e-12);
    EXPECT_NEAR(x.back(), max[a] - 0.5 * dp, 1e-12);
  }
  std::set<std::array<long, 3>> cells;
  for (const Vec3& x : m.x_p)
    cells.insert({std::lround((x.x() - min.x()) / dp - 0.5),
                  std::lround((x.y() - min.y()) / dp - 0.5),
                  std::lround((x.z() - min.z()) / dp - 0.5)});
  EXPECT_EQ(cells.size(), m.x_p.size()); // no cell twice
}

TEST(BoxLattice, BarOfFiveByFiveByHundredMillimetres) {
  BodySpec bar = sph_box("bar", {0, 0, 0}, {0.005, 0.005, 0.1}, 0.001);
  bar.h_factor = 1.5;
  const Model m = mesh_case(case_of({bar}));
  ASSERT_EQ(m.particle_count(), 2500);
  expect_uniform_particles(m, 0, 1e-9, 1.5e-3);
  EXPECT_NEAR(total_mass(m), rho0 * 2.5e-6, 1e-12 * rho0 * 2.5e-6);
  for (const Vec3& x : m.x_p) {
    EXPECT_GT(x.minCoeff(), 0);
    EXPECT_LT(x.x(), 0.005);
    EXPECT_LT(x.z(), 0.1);
  }
}

// L/Δp not an integer: n = round(L/Δp) cells of L/n per direction, so the box is still tiled
// exactly, the particle volume is the product of the three spacings and h stays h_factor·Δp.
TEST(BoxLattice, NonIntegerLengthsAdjustTheSpacingPerDirection) {
  const Vec3 min(0, 0, 0), max(0.047, 0.024, 0.012);
  const double dp = 0.01;
  const Model m = mesh_case(case_of({sph_box("odd", min, max, dp)}));
  const std::array<int, 3> n{5, 2, 1}; // round(4.7), round(2.4), round(1.2)
  ASSERT_EQ(m.particle_count(), 5 * 2 * 1);
  const Vec3 step(0.047 / 5, 0.024 / 2, 0.012);
  expect_uniform_particles(m, 0, step.prod(), 1.2 * dp);
  EXPECT_EQ(m.spacing_b, std::vector<double>{dp});
  const double volume = max.prod();
  EXPECT_NEAR(total_mass(m), rho0 * volume, 1e-12 * rho0 * volume);
  for (int a = 0; a < 3; ++a) {
    const std::vector<double> x = levels(m, a);
    ASSERT_EQ(x.size(), static_cast<std::size_t>(n[a]));
    for (int k = 0; k < n[a]; ++k)
      EXPECT_NEAR(x[k], (k + 0.5) * step[a], 1e-12);
  }
}

// 100k particles (timing is reported by the test, not asserted: see bench/ for timings).
TEST(BoxLattice, HundredThousandParticles) {
  const Model m = mesh_case(case_of({sph_box("big", {0, 0, 0}, {0.05, 0.05, 0.04}, 0.001)}));
  EXPECT_EQ(m.particle_count(), 100000);
}

// ---- node lattice ---------------------------------------------------------------------------

BodySpec sph_node_box(const std::string& name, const Vec3& min, const Vec3& max, double spacing) {
  BodySpec b = sph_box(name, min, max, spacing);
  b.lattice = BodySpec::Lattice::Nodes;
  return b;
}

// How many of a particle's coordinates lie on the box's faces (0 inside, 1 on a face, 2 on an
// edge, 3 at a corner).
int on_faces(const Vec3& x, const Vec3& min, const Vec3& max) {
  int count = 0;
  for (int a = 0; a < 3; ++a)
    count += x[a] == min[a] || x[a] == max[a];
  return count;
}

// The paper's bar: 5 × 5 × 100 mm at Δp = 1 mm, 6 × 6 × 101 particles on the grid nodes.
TEST(NodeLattice, BarOfFiveByFiveByHundredMillimetres) {
  const Vec3 min(0, 0, 0), max(0.005, 0.005, 0.1);
  const double dp = 0.001;
  BodySpec bar = sph_node_box("bar", min, max, dp);
  bar.h_factor = 1.5;
  const Model m = mesh_case(case_of({bar}));
  ASSERT_EQ(m.particle_count(), 6 * 6 * 101);
  EXPECT_EQ(m.spacing_b, std::vector<double>{dp});
  EXPECT_EQ(m.node_count(), 0);
  const double volume = 2.5e-6;
  EXPECT_NEAR(total_mass(m), rho0 * volume, 1e-12 * rho0 * volume);
  // Lumped masses: ρ0Δp³ inside, halved once per coordinate on a face (corners ρ0Δp³/8).
  const double full = rho0 * dp * dp * dp;
  for (Index i = 0; i < m.particle_count(); ++i) {
    EXPECT_EQ(m.body_p[i], 0);
    EXPECT_EQ(m.rho_p[i], rho0);
    EXPECT_NEAR(m.h_p[i], 1.5 * dp, 1e-15 * dp);
    const double expected = full / (1 << on_faces(m.x_p[i], min, max));
    EXPECT_NEAR(m.m_p[i], expected, 1e-12 * expected) << m.x_p[i].transpose();
  }
  EXPECT_NEAR(m.m_p.front(), full / 8, 1e-12 * full); // the corner at min
  EXPECT_NEAR(m.m_p.back(), full / 8, 1e-12 * full);  // the corner at max
  // Positions: exactly the grid nodes min + kΔp, the ends exactly min and max, each node once.
  const std::array<int, 3> n{5, 5, 100};
  for (int a = 0; a < 3; ++a) {
    const std::vector<double> x = levels(m, a);
    ASSERT_EQ(x.size(), static_cast<std::size_t>(n[a] + 1));
    for (int k = 0; k <= n[a]; ++k)
      EXPECT_NEAR(x[k], min[a] + k * dp, 1e-15);
    EXPECT_EQ(x.front(), min[a]);
    EXPECT_EQ(x.back(), max[a]);
  }
  std::set<std::array<long, 3>> nodes;
  for (const Vec3& x : m.x_p)
    nodes.insert({std::lround(x.x() / dp), std::lround(x.y() / dp), std::lround(x.z() / dp)});
  EXPECT_EQ(nodes.size(), m.x_p.size());
}

// Independent check against the FE mesher: the particles of a node lattice sit on the nodes of
// the hex mesh of the same box (element_size Δp), and their masses are that mesh's row-sum
// lumped nodal masses ρ0 Σ V_e/8 (each hex a rectangular box: V_e from its nodes' extent).
TEST(NodeLattice, MatchesTheNodesAndLumpedMassesOfTheHexMesh) {
  const Vec3 min(0, 0, 0), max(0.005, 0.005, 0.1);
  const double dp = 0.001;
  BodySpec fe;
  fe.name = "fe";
  fe.geometry.box = {min, max};
  fe.element_size = dp;
  fe.material = "steel";
  const Model mesh = mesh_case(case_of({fe}));
  const Model sph = mesh_case(case_of({sph_node_box("bar", min, max, dp)}));
  ASSERT_EQ(sph.particle_count(), mesh.node_count());
  std::vector<double> lumped(mesh.x_n.size(), 0.0);
  for (const Hex& hex : mesh.hex_e) {
    Vec3 low = mesh.x_n[hex[0]], high = low;
    for (const Index i : hex) {
      low = low.cwiseMin(mesh.x_n[i]);
      high = high.cwiseMax(mesh.x_n[i]);
    }
    for (const Index i : hex)
      lumped[i] += rho0 * (high - low).prod() / 8;
  }
  // Nodes by position, rounded to a 1 µm grid (far below Δp, far above rounding).
  const auto key = [](const Vec3& x) {
    return std::array<long, 3>{std::lround(x.x() * 1e6), std::lround(x.y() * 1e6),
                               std::lround(x.z() * 1e6)};
  };
  std::map<std::array<long, 3>, Index> node_at;
  for (Index i = 0; i < mesh.node_count(); ++i)
    node_at[key(mesh.x_n[i])] = i;
  ASSERT_EQ(node_at.size(), mesh.x_n.size());
  for (Index p = 0; p < sph.particle_count(); ++p) {
    const auto node = node_at.find(key(sph.x_p[p]));
    ASSERT_NE(node, node_at.end()) << "no FE node at " << sph.x_p[p].transpose();
    EXPECT_LT((mesh.x_n[node->second] - sph.x_p[p]).norm(), 1e-12) << sph.x_p[p].transpose();
    EXPECT_NEAR(sph.m_p[p], lumped[node->second], 1e-9 * lumped[node->second]);
  }
}

// L/Δp not an integer: n_i = round(L_i/Δp) cells of L_i/n_i, n_i + 1 particles per direction.
TEST(NodeLattice, NonIntegerLengthsAdjustTheSpacingPerDirection) {
  const Vec3 min(0.1, -0.2, 0.3), max(0.147, -0.176, 0.312);
  const double dp = 0.01;
  const Model m = mesh_case(case_of({sph_node_box("odd", min, max, dp)}));
  const std::array<int, 3> n{5, 2, 1}; // round(4.7), round(2.4), round(1.2)
  ASSERT_EQ(m.particle_count(), 6 * 3 * 2);
  const Vec3 size = max - min;
  EXPECT_NEAR(total_mass(m), rho0 * size.prod(), 1e-12 * rho0 * size.prod());
  for (int a = 0; a < 3; ++a) {
    const std::vector<double> x = levels(m, a);
    ASSERT_EQ(x.size(), static_cast<std::size_t>(n[a] + 1));
    for (int k = 0; k <= n[a]; ++k)
      EXPECT_NEAR(x[k], min[a] + k * size[a] / n[a], 1e-15);
    EXPECT_EQ(x.front(), min[a]);
    EXPECT_EQ(x.back(), max[a]);
  }
  const double cell = (size.array() / Eigen::Array3d(5, 2, 1)).prod();
  for (Index i = 0; i < m.particle_count(); ++i) {
    const double expected = rho0 * cell / (1 << on_faces(m.x_p[i], min, max));
    EXPECT_NEAR(m.m_p[i], expected, 1e-12 * expected);
  }
}

// ---- particle faces -------------------------------------------------------------------------

const std::array<std::string, 6> face_names{"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};

// Checks the six particle faces of box body `body` (box [min, max], particles of body id `id`):
// each face is the layer of the body's particles nearest to it (every particle at the extreme
// coordinate, none else), normals are outward unit vectors, areas positive and summing to the
// face's area to 1e-12. Returns the faces' particle counts.
std::array<std::size_t, 6> expect_box_faces(const Model& m, const std::string& body, int id,
                                            const Vec3& min, const Vec3& max) {
  std::array<std::size_t, 6> counts{};
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const bool high = f % 2 == 1;
    const std::string name = body + "/" + face_names[f];
    SCOPED_TRACE(name);
    const auto it = m.particle_faces.find(name);
    if (it == m.particle_faces.end()) {
      ADD_FAILURE() << "no particle face " << name;
      continue;
    }
    const ParticleFace& face = it->second;
    Vec3 normal = Vec3::Zero();
    normal[axis] = high ? 1 : -1;
    EXPECT_EQ(face.normal, normal);
    EXPECT_EQ(face.area.size(), face.particles.size());
    // The extreme coordinate of the body's particles along the axis, and who has it.
    double extreme = high ? -INFINITY : INFINITY;
    for (Index i = 0; i < m.particle_count(); ++i)
      if (m.body_p[i] == id)
        extreme = high ? std::max(extreme, m.x_p[i][axis]) : std::min(extreme, m.x_p[i][axis]);
    std::vector<Index> layer;
    for (Index i = 0; i < m.particle_count(); ++i)
      if (m.body_p[i] == id && m.x_p[i][axis] == extreme)
        layer.push_back(i);
    EXPECT_EQ(face.particles, layer); // in particle order
    double sum = 0;
    for (const double a : face.area) {
      EXPECT_GT(a, 0);
      sum += a;
    }
    const double area = (max - min).prod() / (max - min)[axis];
    EXPECT_NEAR(sum, area, 1e-12 * area);
    counts[f] = face.particles.size();
  }
  return counts;
}

TEST(ParticleFaces, NodeLatticeFacesAreTheParticlesOnTheFaces) {
  const Vec3 min(0, 0, 0), max(0.005, 0.005, 0.1);
  const double dp = 0.001;
  const Model m = mesh_case(case_of({sph_node_box("bar", min, max, dp)}));
  EXPECT_EQ(m.particle_faces.size(), 6u);
  EXPECT_EQ(expect_box_faces(m, "bar", 0, min, max),
            (std::array<std::size_t, 6>{606, 606, 606, 606, 36, 36}));
  // On the face, with the lumped face areas: Δp² inside, halved on each edge of the face.
  const ParticleFace& top = m.particle_faces.at("bar/zmax");
  for (std::size_t n = 0; n < top.particles.size(); ++n) {
    const Vec3& x = m.x_p[top.particles[n]];
    EXPECT_EQ(x.z(), max.z());
    const double expected = dp * dp / (1 << (on_faces(x, min, max) - 1));
    EXPECT_NEAR(top.area[n], expected, 1e-12 * expected) << x.transpose();
  }
  EXPECT_NEAR(top.area.front(), dp * dp / 4, 1e-12 * dp * dp); // a corner
  for (const Index i : m.particle_faces.at("bar/xmin").particles)
    EXPECT_EQ(m.x_p[i].x(), min.x());
}

TEST(ParticleFaces, CentredLatticeFacesAreTheFirstLayer) {
  const Vec3 min(0, 0, 0), max(0.005, 0.005, 0.1);
  const double dp = 0.001;
  const Model m = mesh_case(case_of({sph_box("bar", min, max, dp)}));
  EXPECT_EQ(m.particle_faces.size(), 6u);
  EXPECT_EQ(expect_box_faces(m, "bar", 0, min, max),
            (std::array<std::size_t, 6>{500, 500, 500, 500, 25, 25}));
  const ParticleFace& top = m.particle_faces.at("bar/zmax");
  for (std::size_t n = 0; n < top.particles.size(); ++n) {
    EXPECT_NEAR(m.x_p[top.particles[n]].z(), max.z() - 0.5 * dp, 1e-15);
    EXPECT_NEAR(top.area[n], dp * dp, 1e-12 * dp * dp);
  }
  for (const Index i : m.particle_faces.at("bar/ymin").particles)
    EXPECT_NEAR(m.x_p[i].y(), min.y() + 0.5 * dp, 1e-15);
}

// Adjusted spacings: the areas still sum to the face areas; with one cell across, both faces of
// that direction are the same layer.
TEST(ParticleFaces, NonIntegerLengthsKeepTheFaceAreas) {
  const Vec3 min(0.1, -0.2, 0.3), max(0.147, -0.176, 0.312);
  const double dp = 0.01;
  for (const BodySpec& body : {sph_box("odd", min, max, dp), sph_node_box("odd", min, max, dp)}) {
    const bool nodes = body.lattice == BodySpec::Lattice::Nodes;
    SCOPED_TRACE(nodes ? "nodes" : "centred");
    const Model m = mesh_case(case_of({body}));
    const std::array<std::size_t, 6> counts = expect_box_faces(m, "odd", 0, min, max);
    EXPECT_EQ(counts, nodes ? (std::array<std::size_t, 6>{6, 6, 12, 12, 18, 18})
                            : (std::array<std::size_t, 6>{2, 2, 5, 5, 10, 10}));
    if (!nodes) {
      EXPECT_EQ(m.particle_faces.at("odd/zmin").particles,
                m.particle_faces.at("odd/zmax").particles);
    }
  }
}

// Faces index the whole model's particle arrays: a second body's faces point past the first
// body's particles. Cylinders and geometry files have no particle faces.
TEST(ParticleFaces, OnlyBoxesHaveFacesIndexedIntoTheWholeModel) {
  const CylinderGeometry rod{{0, 0, 0.02}, {0, 0, 0.01}, 0.003};
  const Vec3 min(0, 0, 0), max(0.004, 0.003, 0.002);
  const Model m =
      mesh_case(case_of({sph_cylinder("rod", rod, 0.001), sph_node_box("block", min, max, 0.001),
                         sph_file("ball", data_dir / "sphere.geo", 0.002)}));
  EXPECT_EQ(m.particle_faces.size(), 6u);
  for (const auto& [name, face] : m.particle_faces)
    EXPECT_TRUE(name.starts_with("block/")) << name;
  EXPECT_EQ(expect_box_faces(m, "block", 1, min, max),
            (std::array<std::size_t, 6>{12, 12, 15, 15, 20, 20}));
  for (const auto& [name, face] : m.particle_faces)
    for (const Index i : face.particles)
      EXPECT_EQ(m.body_p.at(static_cast<std::size_t>(i)), 1) << name;
}

// ---- cylinder -------------------------------------------------------------------------------

bool inside_cylinder(const CylinderGeometry& g, const Vec3& x) {
  const double length = g.axis.norm();
  const Vec3 a = g.axis / length, d = x - g.base;
  const double t = d.dot(a);
  return t >= 0 && t < length && (d - t * a).norm() < g.radius;
}

// Every particle lies on one lattice of spacing Δp (that of the first particle) and inside;
// every point of that lattice within the cylinder's bounds that is inside is a particle.
void expect_exact_lattice_fill(const Model& m, const CylinderGeometry& g, double dp) {
  ASSERT_GT(m.particle_count(), 0);
  const Vec3 origin = m.x_p[0];
  std::set<std::array<long, 3>> cells;
  for (const Vec3& x : m.x_p) {
    const Vec3 u = (x - origin) / dp;
    const std::array<long, 3> cell{std::lround(u.x()), std::lround(u.y()), std::lround(u.z())};
    for (int a = 0; a < 3; ++a)
      ASSERT_NEAR(u[a], static_cast<double>(cell[a]), 1e-6) << "off the lattice";
    EXPECT_TRUE(inside_cylinder(g, x)) << x.transpose();
    cells.insert(cell);
  }
  EXPECT_EQ(cells.size(), m.x_p.size());
  // Brute force over a box around the cylinder.
  const Vec3 top = g.base + g.axis;
  const Vec3 low = g.base.cwiseMin(top).array() - g.radius - dp;
  const Vec3 high = g.base.cwiseMax(top).array() + g.radius + dp;
  const Vec3 lo = ((low - origin) / dp).array().floor(), hi = ((high - origin) / dp).array().ceil();
  std::size_t count = 0;
  for (long i = static_cast<long>(lo.x()); i <= static_cast<long>(hi.x()); ++i)
    for (long j = static_cast<long>(lo.y()); j <= static_cast<long>(hi.y()); ++j)
      for (long k = static_cast<long>(lo.z()); k <= static_cast<long>(hi.z()); ++k)
        if (inside_cylinder(g, origin + dp * Vec3(i, j, k))) {
          ++count;
          EXPECT_TRUE(cells.contains({i, j, k}))
              << "missed lattice point " << i << " " << j << " " << k;
        }
  EXPECT_EQ(count, m.x_p.size());
}

// Along z with L a multiple of Δp: L/Δp identical layers. Per layer, the cells whose centres lie
// in the disc cover the disc shrunk by the half-diagonal Δp/√2 and lie within the disc grown by
// it, so π(R/Δp − 1/√2)² ≤ N_layer ≤ π(R/Δp + 1/√2)² (±7 % at R = 20 Δp). The actual error is a
// sum of ~2πR/Δp boundary cells' random-signed parts, ~√(2πR/Δp) ≈ 11 of 1257 here: assert 3 %.
TEST(CylinderLattice, AlongZIsLayeredAndWithinTheAreaBounds) {
  const double dp = 0.001, r = 0.02, length = 0.04;
  const CylinderGeometry g{{0.01, -0.02, 0.1}, {0, 0, length}, r};
  const Model m = mesh_case(case_of({sph_cylinder("rod", g, dp)}));
  expect_exact_lattice_fill(m, g, dp);
  expect_uniform_particles(m, 0, dp * dp * dp, 1.2 * dp);
  const std::vector<double> z = levels(m, 2);
  ASSERT_EQ(z.size(), 40u);
  EXPECT_NEAR(z.front(), 0.1 + 0.5 * dp, 1e-12);
  EXPECT_NEAR(z.back(), 0.1 + length - 0.5 * dp, 1e-12);
  ASSERT_EQ(m.particle_count() % 40, 0);
  const double layer = static_cast<double>(m.particle_count() / 40), rho = r / dp;
  const double half_diagonal = 1 / std::numbers::sqrt2;
  EXPECT_GE(layer, std::numbers::pi * std::pow(rho - half_diagonal, 2));
  EXPECT_LE(layer, std::numbers::pi * std::pow(rho + half_diagonal, 2));
  EXPECT_NEAR(layer / (std::numbers::pi * rho * rho), 1, 0.03);
  // Mass: the lattice-count approximation of ρ0 π R² L.
  EXPECT_NEAR(total_mass(m), rho0 * m.particle_count() * dp * dp * dp, 1e-9 * total_mass(m));
  // The lattice is centred on the axis: the particles' centroid is on it.
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& x : m.x_p)
    centroid += x;
  centroid /= static_cast<double>(m.particle_count());
  EXPECT_NEAR(centroid.x(), 0.01, 1e-12);
  EXPECT_NEAR(centroid.y(), -0.02, 1e-12);
}

// Any axis: the cells with centres inside lie within the cylinder grown by the half-diagonal
// r = √3/2 Δp and cover it shrunk by r, so π(R − r)²(L − 2r) ≤ N Δp³ ≤ π(R + r)²(L + 2r).
// As above the actual count is far closer: 3 % for R ≥ 10 Δp. The thin oblique rod (R = 2 Δp,
// its bounding box 30 000 times its volume in cells) checks the per-column cell ranges.
TEST(CylinderLattice, ObliqueAxesFillExactlyTheInsideLatticePoints) {
  const double dp = 0.001;
  for (const CylinderGeometry& g :
       {CylinderGeometry{{0, 0, 0}, Vec3(1, 2, -0.5).normalized() * 0.05, 0.012},
        CylinderGeometry{{0.3, 0.1, -0.2}, {0.04, 0, 0}, 0.015},
        CylinderGeometry{{0, 0, 0}, Vec3(1, 1, 1).normalized() * 0.2, 0.002}}) {
    SCOPED_TRACE(::testing::Message() << "axis " << g.axis.transpose());
    const Model m = mesh_case(case_of({sph_cylinder("rod", g, dp)}));
    expect_exact_lattice_fill(m, g, dp);
    const double r = std::sqrt(3.0) / 2 * dp, length = g.axis.norm(), rr = g.radius;
    const double volume = m.particle_count() * dp * dp * dp;
    EXPECT_GE(volume, std::numbers::pi * (rr - r) * (rr - r) * (length - 2 * r));
    EXPECT_LE(volume, std::numbers::pi * (rr + r) * (rr + r) * (length + 2 * r));
    if (rr >= 10 * dp) {
      EXPECT_NEAR(volume / (std::numbers::pi * rr * rr * length), 1, 0.03);
    }
  }
}

TEST(CylinderLattice, HundredThousandParticles) {
  const CylinderGeometry g{{0, 0, 0}, {0, 0, 0.08}, 0.02};
  const Model m = mesh_case(case_of({sph_cylinder("rod", g, 0.001)}));
  EXPECT_NEAR(m.particle_count() / 100531.0, 1, 0.03); // π · 20² · 80
}

// ---- geometry files -------------------------------------------------------------------------

// The sphere's surface is triangulated with edges of about Δp, inscribed, so every particle is
// strictly inside the sphere. The count error is the lattice's (as for the cylinder, ~1/√(4π
// R²/Δp²) ≈ 3 % at most for R = 10 Δp) plus the inscribed polyhedron's volume deficit
// (≲ 3 · Δp²/(8R²) ≈ 0.4 %): assert 5 %.
TEST(FileLattice, SphereHasAllParticlesInsideAndAboutItsVolume) {
  const Vec3 centre(0.003, -0.002, 0.05);
  const double r = 0.01, dp = 0.001;
  const Model m = mesh_case(case_of({sph_file("ball", data_dir / "sphere.geo", dp)}));
  ASSERT_GT(m.particle_count(), 0);
  expect_uniform_particles(m, 0, dp * dp * dp, 1.2 * dp);
  double farthest = 0;
  for (const Vec3& x : m.x_p)
    farthest = std::max(farthest, (x - centre).norm());
  EXPECT_LT(farthest, r);
  EXPECT_GT(farthest, r - dp); // reaches the surface layer
  const double expected = 4.0 / 3.0 * std::numbers::pi * std::pow(r / dp, 3);
  EXPECT_NEAR(m.particle_count() / expected, 1, 0.05);
  // Lattice centred on the sphere: the particles' centroid is near its centre.
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& x : m.x_p)
    centroid += x;
  EXPECT_LT((centroid / static_cast<double>(m.particle_count()) - centre).norm(), 0.05 * dp);
}

// A volume with an inner boundary: particles in the block and outside the hole (up to the
// inscribed triangulation's sagitta, < 0.1 Δp here).
TEST(FileLattice, BlockWithHoleLeavesTheHoleEmpty) {
  const Vec3 centre(0.02, 0.015, 0.01);
  const double r = 0.006, dp = 0.001;
  const Model m = mesh_case(case_of({sph_file("block", data_dir / "block_with_hole.geo", dp)}));
  for (const Vec3& x : m.x_p) {
    EXPECT_GT(x.minCoeff(), 0);
    EXPECT_LT(x.x(), 0.04);
    EXPECT_LT(x.y(), 0.03);
    EXPECT_LT(x.z(), 0.02);
    EXPECT_GT((x - centre).norm(), r - 0.1 * dp);
  }
  const double hole = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double expected = (0.04 * 0.03 * 0.02 - hole) / (dp * dp * dp);
  EXPECT_NEAR(m.particle_count() / expected, 1, 0.02);
}

class TempFiles : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sphfem_lattice_test_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }

  fs::path dir_;
};

// Two boxes, 30 × 20 × 20 mm together, at Δp = 2 mm: the union is tiled by 15 × 10 × 10 cells
// whose centres lie on no face, so exactly 1500 particles whether the volumes share a face or
// overlap (a point is inside if any volume encloses it).
TEST_F(TempFiles, SeveralVolumesFillTheirUnion) {
  const std::string boxes = "SetFactory(\"OpenCASCADE\");\n"
                            "Box(1) = {0, 0, 0, 0.02, 0.02, 0.02};\n";
  const fs::path shared = write("shared.geo", boxes + "Box(2) = {0.02, 0, 0, 0.01, 0.02, 0.02};\n"
                                                      "Coherence;\n");
  const fs::path overlapping =
      write("overlapping.geo", boxes + "Box(2) = {0.01, 0, 0, 0.02, 0.02, 0.02};\n");
  for (const fs::path& file : {shared, overlapping}) {
    SCOPED_TRACE(file.filename().string());
    const Model m = mesh_case(case_of({sph_file("pair", file, 0.002)}));
    EXPECT_EQ(m.particle_count(), 1500);
    EXPECT_NEAR(total_mass(m), rho0 * 0.03 * 0.02 * 0.02, 1e-9 * total_mass(m));
  }
}

// STEP and BREP files, written by gmsh itself from a .geo script while the .geo is read.
TEST_F(TempFiles, StepAndBrepFilesAreRead) {
  const fs::path geo = write("cube.geo", "SetFactory(\"OpenCASCADE\");\n"
                                         "Box(1) = {0, 0, 0, 0.01, 0.01, 0.01};\n"
                                         "Save \"" +
                                             (dir_ / "cube.step").string() +
                                             "\";\n"
                                             "Save \"" +
                                             (dir_ / "cube.brep").string() + "\";\n");
  EXPECT_EQ(mesh_case(case_of({sph_file("cube", geo, 0.001)})).particle_count(), 1000);
  for (const char* name : {"cube.step", "cube.brep"}) {
    ASSERT_TRUE(fs::exists(dir_ / name)) << name;
    EXPECT_EQ(mesh_case(case_of({sph_file("cube", dir_ / name, 0.001)})).particle_count(), 1000)
        << name;
  }
}

// ---- errors ---------------------------------------------------------------------------------

void expect_error(const Case& c, const std::string& body, const std::string& what) {
  try {
    mesh_case(c);
    ADD_FAILURE() << "no error for body " << body;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("body '" + body + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

TEST_F(TempFiles, BadBodiesAreNamed) {
  expect_error(case_of({sph_box("thin", {0, 0, 0}, {0.1, 0.1, 0.004}, 0.005)}), "thin",
               "spacing 0.005 m is larger than the body");
  expect_error(case_of({sph_cylinder("wire", {{0, 0, 0}, {0, 0, 1}, 0.001}, 0.003)}), "wire",
               "is larger than the body");
  // 2R ≥ Δp, but the 2 × 2 lattice columns at (±Δp/2, ±Δp/2) lie outside the radius.
  expect_error(case_of({sph_cylinder("needle", {{0, 0, 0}, {0, 0, 0.01}, 0.0006}, 0.001)}),
               "needle", "no lattice point of spacing 0.001 m lies inside the body");
  expect_error(case_of({sph_box("dust", {0, 0, 0}, {1, 1, 1}, 1e-4)}), "dust", "too fine");
  expect_error(case_of({sph_file("ball", data_dir / "sphere.geo", 0.03)}), "ball",
               "is larger than the body");
  const fs::path flat =
      write("flat.geo", "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 1, 1};\n");
  expect_error(case_of({sph_file("sheet", flat, 0.1)}), "sheet", "defines no volume");
  const fs::path broken = write("broken.geo", "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0;\n");
  expect_error(case_of({sph_file("typo", broken, 0.1)}), "typo", "syntax error");
  // gmsh still reads files after reporting an error.
  EXPECT_GT(mesh_case(case_of({sph_file("ball", data_dir / "sphere.geo", 0.002)})).particle_count(),
            0);
}

// Options a geometry file's script sets (here a scaling to millimetres) apply to it only.
TEST_F(TempFiles, FileOptionsDoNotLeakToLaterBodies) {
  const fs::path geo = write("cube.geo", "SetFactory(\"OpenCASCADE\");\n"
                                         "Box(1) = {0, 0, 0, 0.01, 0.01, 0.01};\n"
                                         "Save \"" +
                                             (dir_ / "cube.brep").string() + "\";\n");
  mesh_case(case_of({sph_file("cube", geo, 0.001)}));
  const fs::path scaled = write("scaled.geo", "Geometry.OCCScaling = 0.5;\nMerge \"cube.brep\";\n");
  const Model m = mesh_case(
      case_of({sph_file("half", scaled, 0.001), sph_file("whole", dir_ / "cube.brep", 0.001)}));
  EXPECT_EQ(std::count(m.body_p.begin(), m.body_p.end(), 0), 125);
  EXPECT_EQ(std::count(m.body_p.begin(), m.body_p.end(), 1), 1000);
}

TEST(LatticeErrors, NodeLatticeNeedsABox) {
  BodySpec rod = sph_cylinder("rod", {{0, 0, 0}, {0, 0, 0.01}, 0.003}, 0.001);
  rod.lattice = BodySpec::Lattice::Nodes;
  expect_error(case_of({rod}), "rod", "lattice nodes is only possible for a box geometry");
  BodySpec ball = sph_file("ball", data_dir / "sphere.geo", 0.002);
  ball.lattice = BodySpec::Lattice::Nodes;
  expect_error(case_of({ball}), "ball", "lattice nodes is only possible for a box geometry");
}

TEST(LatticeErrors, MissingMaterialIsNamed) {
  Case c = case_of({sph_box("block", {0, 0, 0}, {0.01, 0.01, 0.01}, 0.005)});
  c.bodies[0].material = "unobtainium";
  expect_error(c, "block", "unobtainium");
}

// ---- ray parity -----------------------------------------------------------------------------

// The boundary of the box [0, 1]³ split into m × m squares per face, each cut into two
// triangles along a diagonal (alternating), vertices shared between faces.
mesher::Triangulation cube_surface(int m) {
  mesher::Triangulation s;
  std::map<std::array<int, 3>, Index> index;
  const auto vertex = [&](std::array<int, 3> g) {
    const auto [at, added] = index.try_emplace(g, static_cast<Index>(s.x.size()));
    if (added)
      s.x.emplace_back(g[0] / double(m), g[1] / double(m), g[2] / double(m));
    return at->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int level : {0, m})
      for (int u = 0; u < m; ++u)
        for (int v = 0; v < m; ++v) {
          std::array<Index, 4> q{};
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> g{};
            g[axis] = level;
            g[(axis + 1) % 3] = u + du[c];
            g[(axis + 2) % 3] = v + dv[c];
            q[c] = vertex(g);
          }
          if ((u + v) % 2 == 0) {
            s.triangles.push_back({q[0], q[1], q[2]});
            s.triangles.push_back({q[0], q[2], q[3]});
          } else {
            s.triangles.push_back({q[0], q[1], q[3]});
            s.triangles.push_back({q[1], q[2], q[3]});
          }
        }
  return s;
}

// Lattice columns through the surface mesh's vertices and along its edges and diagonals (the
// lattice is finer than the mesh and shares its grid lines): strictly inside points are in,
// strictly outside points are out, and boundary points either way.
TEST(RayParity, ColumnsThroughVerticesAndEdgesAreCountedOnce) {
  const mesher::Triangulation cube = cube_surface(4);
  mesher::Lattice l;
  l.first = Vec3(-0.25, -0.25, -0.1);
  l.step = Vec3(0.125, 0.125, 0.1);
  l.n = {13, 13, 13};
  std::vector<char> enclosed(l.cell_count(), 0);
  mesher::mark_enclosed(cube, l, enclosed);
  std::size_t cell = 0, strictly_inside = 0;
  for (Index i = 0; i < l.n[0]; ++i)
    for (Index j = 0; j < l.n[1]; ++j)
      for (Index k = 0; k < l.n[2]; ++k, ++cell) {
        const Vec3 x = l.centre(i, j, k);
        const double eps = 1e-9;
        const bool in = (x.array() > eps).all() && (x.array() < 1 - eps).all();
        const bool out = (x.array() < -eps).any() || (x.array() > 1 + eps).any();
        strictly_inside += in;
        if (in) {
          EXPECT_TRUE(enclosed[cell]) << x.transpose();
        }
        if (out) {
          EXPECT_FALSE(enclosed[cell]) << x.transpose();
        }
      }
  EXPECT_EQ(strictly_inside, 7u * 7u * 9u);
}

// A rotated cube against the exact inside test, away from its surface.
TEST(RayParity, RotatedCubeMatchesTheExactTest) {
  std::mt19937 random(42);
  std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 rotation = (Eigen::AngleAxisd(angle(random), Vec3::UnitZ()) *
                           Eigen::AngleAxisd(angle(random), Vec3::UnitY()) *
                           Eigen::AngleAxisd(angle(random), Vec3::UnitX()))
                              .toRotationMatrix();
    mesher::Triangulation cube = cube_surface(3);
    for (Vec3& x : cube.x)
      x = rotation * (x - Vec3::Constant(0.5));
    const mesher::Lattice l =
        mesher::covering_lattice(Vec3::Constant(-0.9), Vec3::Constant(0.9), 0.05);
    std::vector<char> enclosed(l.cell_count(), 0);
    mesher::mark_enclosed(cube, l, enclosed);
    std::size_t cell = 0, count = 0;
    for (Index i = 0; i < l.n[0]; ++i)
      for (Index j = 0; j < l.n[1]; ++j)
        for (Index k = 0; k < l.n[2]; ++k, ++cell) {
          const Vec3 local = rotation.transpose() * l.centre(i, j, k);
          const double depth = 0.5 - local.cwiseAbs().maxCoeff(); // > 0 inside
          count += enclosed[cell];
          if (std::abs(depth) > 1e-9) {
            EXPECT_EQ(static_cast<bool>(enclosed[cell]), depth > 0) << local.transpose();
          }
        }
    EXPECT_NEAR(count * std::pow(0.05, 3), 1.0, 0.1);
  }
}

TEST(RayParity, OrsIntoExistingFlags) {
  const mesher::Triangulation cube = cube_surface(1);
  mesher::Lattice l;
  l.first = Vec3(-0.5, 0.5, 0.5);
  l.step = Vec3::Ones();
  l.n = {3, 1, 1}; // outside, inside, outside
  std::vector<char> enclosed{1, 0, 0};
  mesher::mark_enclosed(cube, l, enclosed);
  EXPECT_EQ(enclosed, (std::vector<char>{1, 1, 0}));
  std::vector<char> wrong_size(2, 0);
  EXPECT_THROW(mesher::mark_enclosed(cube, l, wrong_size), Error);
}

TEST(CoveringLattice, IsCentredAndCoversTheBox) {
  const mesher::Lattice l = mesher::covering_lattice({0, 0, 0}, {0.04, 0.0125, 0.001}, 0.01);
  EXPECT_EQ(l.n, (std::array<Index, 3>{4, 2, 1}));
  EXPECT_NEAR(l.first.x(), 0.005, 1e-15);
  EXPECT_NEAR(l.first.y(), 0.00125, 1e-15); // 2 cells over 12.5 mm, centred: −3.75 … 16.25 mm
  EXPECT_NEAR(l.first.z(), 0.0005, 1e-15);
  EXPECT_EQ(l.step, Vec3::Constant(0.01));
}

} // namespace
} // namespace sphfem
