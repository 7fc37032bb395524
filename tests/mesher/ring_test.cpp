// Tests of the ring mesh (mesher/ring.cpp through mesh_case): the plate ring a = 24 mm,
// R = 250 mm, t = 12 mm around a square hole, full and quarter, at 2 and 1 mm. Counts against
// the header's formulas, hexes valid at every corner (hex_checks.hpp), volume against the
// inscribed polygon and the analytic area, faces on their planes and circle, the radial grading
// at the hole and the rim, the quarter as the x, y ≥ base part of the full mesh, the hole's nodes
// on the nodes of a `lattice: nodes` SPH box filling it, the signature and the errors.
#include "mesher/mesher.hpp"

#include "solver/core/error.hpp"
#include "tests/mesher/hex_checks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

namespace sphfem {
namespace {

using test::expect_valid_mesh, test::total_volume;

const Vec3 base(0.01, -0.02, 0.003);
constexpr double a = 0.024, radius = 0.25, thickness = 0.012;

RingGeometry ring(Sector sector, double rim_element_size = 0) {
  return {.base = base,
          .half_width = a,
          .radius = radius,
          .thickness = thickness,
          .rim_element_size = rim_element_size,
          .sector = sector};
}

BodySpec ring_body(const RingGeometry& g, double h) {
  BodySpec b;
  b.name = "ring";
  b.geometry.kind = GeometrySpec::Kind::Ring;
  b.geometry.ring = g;
  b.element_size = h;
  b.material = "steel";
  return b;
}

// The SPH core filling the hole of `g` (its quarter for a quarter ring), on the lattice nodes.
BodySpec core_body(const RingGeometry& g, double spacing) {
  BodySpec b;
  b.name = "core";
  b.method = Method::Sph;
  b.lattice = BodySpec::Lattice::Nodes;
  b.spacing = spacing;
  b.geometry.kind = GeometrySpec::Kind::Box;
  const Vec3 reach(g.half_width, g.half_width, 0);
  b.geometry.box = {g.sector == Sector::Quarter ? g.base : Vec3(g.base - reach),
                    g.base + reach + Vec3(0, 0, g.thickness)};
  b.material = "steel";
  return b;
}

Case case_of(std::vector<BodySpec> bodies) {
  Case c;
  c.name = "ring_test";
  c.materials.push_back({.name = "steel",
                         .model = "elastic",
                         .density = 7830,
                         .youngs_modulus = 207e9,
                         .poisson_ratio = 0.3});
  c.bodies = std::move(bodies);
  return c;
}

int sectors(Sector s) {
  return s == Sector::Full ? 8 : 2;
}

// The counts of mesher/ring.cpp's header, computed here from its rules.
struct Counts {
  int along, radial, layers;
  double rim; // the rim element size s
};

Counts expected_counts(double h, double rim_element_size) {
  Counts n;
  n.along = static_cast<int>(std::lround(a / h));
  n.layers = static_cast<int>(std::lround(thickness / h));
  n.rim = rim_element_size > 0 ? rim_element_size : std::numbers::pi * radius / (4 * n.along);
  const double mean_spoke = radius - 0.5 * (1 + std::numbers::sqrt2) * a;
  n.radial = static_cast<int>(
      std::lround(1 + std::log(n.rim / h) / std::log((mean_spoke - h) / (mean_spoke - n.rim))));
  return n;
}

// Element lengths along the ray from base at angle `degrees` (0 or 45) on the bottom face, from
// the hole outwards.
std::vector<double> spoke_elements(const Model& m, int degrees) {
  const Vec3 dir = degrees == 0 ? Vec3(1, 0, 0) : Vec3(1, 1, 0).normalized();
  std::vector<double> along;
  for (const Index i : m.node_sets.at("ring/bottom")) {
    const Vec3 d = m.x_n[i] - base;
    if (d.dot(dir) > 0 && (d - d.dot(dir) * dir).norm() < 1e-12)
      along.push_back(d.dot(dir));
  }
  std::sort(along.begin(), along.end());
  std::vector<double> lengths;
  for (std::size_t k = 1; k < along.size(); ++k)
    lengths.push_back(along[k] - along[k - 1]);
  return lengths;
}

// ---- one ring at a time ---------------------------------------------------------------------

using RingCase = std::tuple<double, Sector>; // element size, sector

std::string case_name(const ::testing::TestParamInfo<RingCase>& info) {
  const auto [h, sector] = info.param;
  return (sector == Sector::Full ? "Full" : "Quarter") + std::to_string(std::lround(h * 1e3)) +
         "mm";
}

class RingMesh : public ::testing::TestWithParam<RingCase> {};

TEST_P(RingMesh, CountsVolumeFacesAndGrading) {
  const auto [h, sector] = GetParam();
  const bool full = sector == Sector::Full;
  const Model m = mesh_case(case_of({ring_body(ring(sector), h)}));
  const Counts n = expected_counts(h, 0);
  // Hand values of the rule: n_r = 32 at 2 mm, 64 at 1 mm.
  EXPECT_EQ(n.radial, h > 0.0015 ? 32 : 64);

  // Counts: hexes sectors · n_s · n_r · layers; nodes per plane 8 n_s (n_r + 1) for the closed
  // ring, (2 n_s + 1)(n_r + 1) for the quarter.
  const int around = full ? 8 * n.along : 2 * n.along + 1; // node columns around the ring
  EXPECT_EQ(m.element_count(), sectors(sector) * n.along * n.radial * n.layers);
  EXPECT_EQ(m.node_count(), around * (n.radial + 1) * (n.layers + 1));
  expect_valid_mesh(m);

  // Faces: nodes on their planes, the hole's sides and the rim circle, to round-off (1e-15 m
  // is a few ulps of the 0.25 m coordinates).
  std::map<std::string, std::size_t> expected{{"ring/inner", around * (n.layers + 1)},
                                              {"ring/rim", around * (n.layers + 1)},
                                              {"ring/bottom", around * (n.radial + 1)},
                                              {"ring/top", around * (n.radial + 1)}};
  if (!full) {
    expected["ring/xmin"] = (n.radial + 1) * (n.layers + 1);
    expected["ring/ymin"] = (n.radial + 1) * (n.layers + 1);
  }
  ASSERT_EQ(m.node_sets.size(), expected.size());
  for (const auto& [name, count] : expected) {
    ASSERT_TRUE(m.node_sets.contains(name)) << name;
    EXPECT_EQ(m.node_sets.at(name).size(), count) << name;
  }
  const auto d = [&](Index i) { return Vec3(m.x_n[i] - base); };
  constexpr double tol = 1e-15;
  for (const Index i : m.node_sets.at("ring/inner"))
    EXPECT_NEAR(d(i).head<2>().lpNorm<Eigen::Infinity>(), a, tol);
  for (const Index i : m.node_sets.at("ring/rim"))
    EXPECT_NEAR(d(i).head<2>().norm(), radius, tol);
  for (const Index i : m.node_sets.at("ring/bottom"))
    EXPECT_NEAR(d(i).z(), 0, tol);
  for (const Index i : m.node_sets.at("ring/top"))
    EXPECT_NEAR(d(i).z(), thickness, tol);
  if (!full) {
    for (const Index i : m.node_sets.at("ring/xmin"))
      EXPECT_NEAR(d(i).x(), 0, tol);
    for (const Index i : m.node_sets.at("ring/ymin"))
      EXPECT_NEAR(d(i).y(), 0, tol);
  }
  for (Index i = 0; i < m.node_count(); ++i) {
    EXPECT_GE(d(i).head<2>().lpNorm<Eigen::Infinity>(), a - tol);
    EXPECT_LE(d(i).head<2>().norm(), radius + tol);
    if (!full) {
      EXPECT_GE(d(i).x(), -tol);
      EXPECT_GE(d(i).y(), -tol);
    }
  }

  // Volume: the hexes fill the prism over the polygon inscribed in the rim (sectors · n_s
  // chords of θ = π/(4 n_s)) less the hole. It falls short of the analytic (πR² − 4a²)·t (a
  // quarter of it for the quarter) by sectors · n_s · R²(θ − sin θ)/2 · t ≤ (πR² t)·θ²/6
  // (quarter: /4), 7.1e-4 of πR²t at 2 mm, 1.8e-4 at 1 mm.
  const double theta = std::numbers::pi / (4 * n.along), share = full ? 1 : 0.25;
  const double polygon = sectors(sector) * n.along * 0.5 * radius * radius * std::sin(theta);
  const double disk = share * std::numbers::pi * radius * radius * thickness;
  const double exact = share * (std::numbers::pi * radius * radius - 4 * a * a) * thickness;
  const double volume = total_volume(m, 0);
  EXPECT_NEAR(volume, (polygon - share * 4 * a * a) * thickness, 1e-12 * exact);
  EXPECT_LE(volume, exact);
  EXPECT_GE(volume, exact - disk * theta * theta / 6);

  // Radial grading on an axis spoke and a diagonal one: n_r elements, the first h (gmsh places
  // the progression's nodes to ~1e-6), growing by a constant ratio q, the last about the rim
  // size s. The spokes are ±2.3 % longer or shorter than the mean length n_r was chosen for,
  // which moves their last element by up to ±4.2 % (measured: +3.3/−3.4 % at 2 mm, +4.2/−2.6 %
  // at 1 mm), and rounding n_r moves it by at most a factor q^½ (1.7 % at 1 mm, 3.5 % at 2 mm,
  // both spokes together); 8 % bounds the sum.
  for (const int degrees : {0, 45}) {
    SCOPED_TRACE(::testing::Message() << "spoke at " << degrees << "°");
    const std::vector<double> lengths = spoke_elements(m, degrees);
    ASSERT_EQ(lengths.size(), static_cast<std::size_t>(n.radial));
    EXPECT_NEAR(lengths.front(), h, 1e-6 * h);
    EXPECT_NEAR(lengths.back(), n.rim, 0.08 * n.rim);
    const double q = lengths[1] / lengths[0];
    for (std::size_t k = 1; k < lengths.size(); ++k)
      EXPECT_NEAR(lengths[k] / lengths[k - 1], q, 1e-6 * q) << "element " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Rings, RingMesh,
                         ::testing::Combine(::testing::Values(0.002, 0.001),
                                            ::testing::Values(Sector::Full, Sector::Quarter)),
                         case_name);

// An explicit rim size: the elements grow to it instead of the circumferential size.
TEST(RingGrading, RimElementSizeIsHonoured) {
  const double h = 0.002, rim = 0.005;
  const Model m = mesh_case(case_of({ring_body(ring(Sector::Quarter, rim), h)}));
  const Counts n = expected_counts(h, rim);
  EXPECT_EQ(m.element_count(), 2 * n.along * n.radial * n.layers);
  for (const int degrees : {0, 45}) {
    const std::vector<double> lengths = spoke_elements(m, degrees);
    ASSERT_EQ(lengths.size(), static_cast<std::size_t>(n.radial));
    EXPECT_NEAR(lengths.front(), h, 1e-6 * h);
    EXPECT_NEAR(lengths.back(), rim, 0.08 * rim); // as in CountsVolumeFacesAndGrading
  }
}

// ---- the quarter is part of the full ring ---------------------------------------------------

std::vector<Vec3> sorted_positions(std::vector<Vec3> x) {
  std::sort(x.begin(), x.end(), [](const Vec3& p, const Vec3& q) {
    return std::lexicographical_compare(p.begin(), p.end(), q.begin(), q.end());
  });
  return x;
}

class RingQuarter : public ::testing::TestWithParam<double> {};

TEST_P(RingQuarter, IsThePositiveQuadrantOfTheFullRing) {
  const double h = GetParam();
  const Model full = mesh_case(case_of({ring_body(ring(Sector::Full), h)}));
  const Model quarter = mesh_case(case_of({ring_body(ring(Sector::Quarter), h)}));
  std::vector<Vec3> part;
  for (const Vec3& x : full.x_n) // nodes on the cut planes are exactly on them
    if (x.x() >= base.x() && x.y() >= base.y())
      part.push_back(x);
  const std::vector<Vec3> expected = sorted_positions(part);
  const std::vector<Vec3> got = sorted_positions(quarter.x_n);
  ASSERT_EQ(got.size(), expected.size());
  double worst = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    worst = std::max(worst, (got[i] - expected[i]).norm());
  EXPECT_LT(worst, 1e-12); // the same sectors meshed the same way, to round-off
  EXPECT_EQ(4 * quarter.element_count(), full.element_count());
}

std::string size_name(const ::testing::TestParamInfo<double>& info) {
  return std::to_string(std::lround(info.param * 1e3)) + "mm";
}

INSTANTIATE_TEST_SUITE_P(Rings, RingQuarter, ::testing::Values(0.002, 0.001), size_name);

// ---- the hole's nodes are the SPH core's lattice nodes --------------------------------------

// Meshes the SPH core (lattice nodes) with the ring and checks that the ring's inner nodes are
// the core's particles on the hole's sides, one for one, to 1e-9 m.
void expect_inner_nodes_on_core(Sector sector, double h) {
  const RingGeometry g = ring(sector);
  const BodySpec core = core_body(g, h);
  const Model m = mesh_case(case_of({core, ring_body(g, h)}));
  const Vec3 low = core.geometry.box.min;
  // The core's particles by lattice index (they sit at low + k·Δp' with Δp' within rounding of
  // h, so the rounded index is exact).
  std::map<std::array<long, 3>, Vec3> particle;
  std::array<long, 3> top{0, 0, 0};
  for (Index p = 0; p < m.particle_count(); ++p) {
    ASSERT_EQ(m.body_p[p], 0);
    std::array<long, 3> k{};
    for (int c = 0; c < 3; ++c) {
      k[c] = std::lround((m.x_p[p][c] - low[c]) / h);
      top[c] = std::max(top[c], k[c]);
    }
    particle[k] = m.x_p[p];
  }
  // Core particles on the hole's sides: the whole lateral boundary of the full core; for a
  // quarter only its sides x = base.x + a and y = base.y + a (the others are symmetry planes).
  std::size_t on_sides = 0;
  for (const auto& [k, x] : particle)
    on_sides +=
        k[0] == top[0] || k[1] == top[1] || (sector == Sector::Full && (k[0] == 0 || k[1] == 0));

  const std::vector<Index>& inner = m.node_sets.at("ring/inner");
  EXPECT_EQ(inner.size(), on_sides);
  double worst = 0;
  for (const Index i : inner) {
    ASSERT_EQ(m.body_n[i], 1);
    std::array<long, 3> k{};
    for (int c = 0; c < 3; ++c)
      k[c] = std::lround((m.x_n[i][c] - low[c]) / h);
    const auto found = particle.find(k);
    ASSERT_NE(found, particle.end()) << "inner node " << m.x_n[i].transpose();
    worst = std::max(worst, (found->second - m.x_n[i]).norm());
  }
  EXPECT_LT(worst, 1e-9);
}

class RingCore : public ::testing::TestWithParam<RingCase> {};

TEST_P(RingCore, InnerNodesAreTheCoreLatticeNodes) {
  const auto [h, sector] = GetParam();
  expect_inner_nodes_on_core(sector, h);
}

INSTANTIATE_TEST_SUITE_P(Rings, RingCore,
                         ::testing::Combine(::testing::Values(0.002, 0.001),
                                            ::testing::Values(Sector::Full, Sector::Quarter)),
                         case_name);

// ---- signature and errors -------------------------------------------------------------------

TEST(RingSignature, NamesEveryRingNumber) {
  Case c = case_of({ring_body(ring(Sector::Full, 0.008), 0.001)});
  EXPECT_EQ(mesh_signature(c), "sphfem-mesh 2\n"
                               "body ring method=fem ring base=0.01,-0.02,0.003 half_width=0.024 "
                               "radius=0.25 thickness=0.012 rim_element_size=0.008 sector=full "
                               "element_size=0.001\n");
  const std::string s = mesh_signature(c);
  c.bodies[0].geometry.ring.sector = Sector::Quarter;
  EXPECT_NE(mesh_signature(c).find("sector=quarter"), std::string::npos);
  const auto changed = [&](auto edit) {
    Case other = case_of({ring_body(ring(Sector::Full, 0.008), 0.001)});
    edit(other.bodies[0].geometry.ring);
    return mesh_signature(other) != s;
  };
  EXPECT_TRUE(changed([](RingGeometry& g) { g.base.z() = 0; }));
  EXPECT_TRUE(changed([](RingGeometry& g) { g.half_width = 0.025; }));
  EXPECT_TRUE(changed([](RingGeometry& g) { g.radius = 0.3; }));
  EXPECT_TRUE(changed([](RingGeometry& g) { g.thickness = 0.01; }));
  EXPECT_TRUE(changed([](RingGeometry& g) { g.rim_element_size = 0; }));
}

void expect_error(const BodySpec& body, const std::string& words) {
  try {
    mesh_case(case_of({body}));
    ADD_FAILURE() << "no error for " << words;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'" + body.name + "'"), std::string::npos) << what;
    EXPECT_NE(what.find(words), std::string::npos) << what;
  }
}

TEST(RingErrors, BadRingsAreErrors) {
  // a/h = 24.5: a lattice across the full hole would have 49 cells, not 2 · 25. A quarter's
  // hole has round(a/h) cells either way.
  RingGeometry g = ring(Sector::Full);
  g.half_width = 0.0245;
  expect_error(ring_body(g, 0.001), "must not end in .5");
  g.sector = Sector::Quarter;
  EXPECT_EQ(mesh_case(case_of({ring_body(g, 0.002)})).element_count() % 2, 0);

  g = ring(Sector::Full);
  g.radius = a * std::numbers::sqrt2 + 0.003; // less than 2 elements past the hole's corners
  expect_error(ring_body(g, 0.002), "radius");
  g = ring(Sector::Full);
  g.thickness = 0;
  expect_error(ring_body(g, 0.002), "thickness");
  g = ring(Sector::Full);
  g.half_width = -0.01;
  expect_error(ring_body(g, 0.002), "half_width");

  BodySpec particles = ring_body(ring(Sector::Full), 0);
  particles.method = Method::Sph;
  particles.spacing = 0.002;
  expect_error(particles, "ring can only be meshed with hexahedra");
}

} // namespace
} // namespace sphfem
