// Tests of `scene: plate_impact` (solver/scenes/plate_impact.hpp): the bodies, couplings and
// conditions it expands into, its presets and overrides, its errors, and — meshed — that the
// quarter model holds a quarter of the whole one's mass and its interface matches the lattice.
#include "solver/io/case_reader.hpp"
#include "solver/scenes/plate_impact.hpp"

#include "mesher/mesher.hpp"
#include "solver/core/error.hpp"
#include "solver/fem/hex8.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace sphfem {
namespace {

// Børvik's geometry with elastic stand-ins for the materials (the scene does not care), at 2 mm.
const std::string kScene = R"(name: plate
scene: plate_impact
preset: coarse
symmetry: quarter
time: {end: 1.0e-5, output_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.33}
  tool: {model: elastic, density: 7838, youngs_modulus: 200e9, poisson_ratio: 0.33}
plate: {thickness: 0.012, clamped_diameter: 0.5, material: steel}
core: {half_width: 0.024, spacing: 0.002}
projectile:
  diameter: 0.020
  length: 0.080
  nose: blunt
  material: tool
  element_size: 0.002
  velocity: 303.5
  contact: {model: kernel, penalty: 1.0e11, exponent: 2}
)";

Case scene(const std::vector<std::string>& overrides = {}) {
  return read_case_text(kScene, "plate.yaml", overrides);
}

std::string error_of(const std::vector<std::string>& overrides, const std::string& text = kScene) {
  try {
    read_case_text(text, "plate.yaml", overrides);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

const BodySpec& body(const Case& c, const std::string& name) {
  return c.bodies[static_cast<std::size_t>(c.body_index(name))];
}

TEST(PlateImpactScene, ExpandsIntoCoreRingAndProjectile) {
  const Case c = scene();
  ASSERT_EQ(c.bodies.size(), 3u);
  const BodySpec& core = body(c, "plate_core");
  EXPECT_EQ(core.method, Method::Sph);
  EXPECT_EQ(core.lattice, BodySpec::Lattice::Nodes);
  EXPECT_EQ(core.spacing, 0.002);
  EXPECT_TRUE(core.geometry.box.min.isApprox(Vec3(0, 0, -0.012)));
  EXPECT_TRUE(core.geometry.box.max.isApprox(Vec3(0.024, 0.024, 0)));

  const BodySpec& ring = body(c, "plate_ring");
  EXPECT_EQ(ring.method, Method::Fem);
  ASSERT_EQ(ring.geometry.kind, GeometrySpec::Kind::Ring);
  EXPECT_EQ(ring.geometry.ring.half_width, 0.024);
  EXPECT_EQ(ring.geometry.ring.radius, 0.25);
  EXPECT_EQ(ring.geometry.ring.thickness, 0.012);
  EXPECT_EQ(ring.geometry.ring.sector, Sector::Quarter);
  EXPECT_EQ(ring.element_size, 0.002);

  const BodySpec& projectile = body(c, "projectile");
  ASSERT_EQ(projectile.geometry.kind, GeometrySpec::Kind::Cylinder);
  const CylinderGeometry& g = projectile.geometry.cylinder;
  EXPECT_EQ(g.radius, 0.01);
  EXPECT_TRUE(g.axis.isApprox(Vec3(0, 0, 0.08)));
  // Just beyond the contact's reach h_core + h_projectile = 1.2 · 2 mm + 1.2 · 2 mm.
  EXPECT_GT(g.base.z(), 0.0048);
  EXPECT_LT(g.base.z(), 0.0048 + 0.001);
  EXPECT_TRUE(projectile.velocity.isApprox(Vec3(0, 0, -303.5)));

  ASSERT_EQ(c.attachments.size(), 1u);
  EXPECT_EQ(c.attachments[0].fem_body, "plate_ring");
  EXPECT_EQ(c.attachments[0].sph_body, "plate_core");
  ASSERT_EQ(c.contacts.size(), 1u);
  EXPECT_EQ(c.contacts[0].penalty, 1.0e11);
  // Clamped rim, then xmin and ymin symmetry on each of the three bodies.
  ASSERT_EQ(c.boundary_conditions.size(), 7u);
  EXPECT_EQ(c.boundary_conditions[0].type, BoundaryType::Fixed);
  EXPECT_EQ(c.boundary_conditions[0].face, "rim");
  for (std::size_t k = 1; k < 7; ++k)
    EXPECT_EQ(c.boundary_conditions[k].type, BoundaryType::Symmetry);
  ASSERT_TRUE(c.output.section.has_value());
  EXPECT_TRUE(c.output.section->normal.isApprox(-Vec3::UnitY())); // u = z × n = +x
}

TEST(PlateImpactScene, NosesGoToTheProjectilesCylinder) {
  const Case blunt = scene();
  EXPECT_EQ(body(blunt, "projectile").geometry.cylinder.nose.shape, NoseGeometry::Shape::Flat);
  const Case ogive = scene({"projectile.nose=ogival", "projectile.crh=3"});
  const CylinderGeometry& g = body(ogive, "projectile").geometry.cylinder;
  EXPECT_EQ(g.nose.shape, NoseGeometry::Shape::Ogival);
  EXPECT_DOUBLE_EQ(g.nose.crh, 3.0);
  // The tip starts where the blunt face did: the gap is measured from the nose's tip.
  EXPECT_DOUBLE_EQ(g.base.z(), body(blunt, "projectile").geometry.cylinder.base.z());
  const Case cone = scene({"projectile.nose=conical", "projectile.nose_length=0.015"});
  EXPECT_DOUBLE_EQ(body(cone, "projectile").geometry.cylinder.nose.length, 0.015);
}

// A shot at 30° on a half model: the core and ring cut at y = 0, the projectile along
// â = (sin 30°, 0, cos 30°) through the plate's centre, moving along −â, its blunt face's lowest
// edge (R sin 30° below the face's centre) where a normal shot's face would be.
TEST(PlateImpactScene, ObliqueShotOnAHalfModel) {
  const Case normal = scene({"symmetry=half"});
  const Case c = scene({"symmetry=half", "projectile.obliquity=30"});
  const double a = 0.024, beta = std::numbers::pi / 6;
  EXPECT_TRUE(body(c, "plate_core").geometry.box.min.isApprox(Vec3(-a, 0, -0.012)));
  EXPECT_EQ(body(c, "plate_ring").geometry.ring.sector, Sector::Half);
  const CylinderGeometry& g = body(c, "projectile").geometry.cylinder;
  const Vec3 along(std::sin(beta), 0, std::cos(beta));
  EXPECT_EQ(g.sector, Sector::Half);
  EXPECT_TRUE(g.axis.isApprox(0.08 * along));
  EXPECT_NEAR(g.base.cross(along).norm(), 0, 1e-15); // on the line through the plate's centre
  const double gap = body(normal, "projectile").geometry.cylinder.base.z();
  EXPECT_NEAR(g.base.z() - 0.01 * std::sin(beta), gap, 1e-15);
  EXPECT_TRUE(body(c, "projectile").velocity.isApprox(-303.5 * along));
  // The clamped rim, then ymin symmetry on each of the three bodies.
  ASSERT_EQ(c.boundary_conditions.size(), 4u);
  for (std::size_t k = 1; k < 4; ++k) {
    EXPECT_EQ(c.boundary_conditions[k].type, BoundaryType::Symmetry);
    EXPECT_EQ(c.boundary_conditions[k].face, "ymin");
  }
  ASSERT_TRUE(c.scene.has_value());
  EXPECT_EQ(c.scene->symmetry, "half");
  EXPECT_EQ(c.scene->obliquity, 30.0);
}

// Without core.half_width the scene sizes the core: the footprint swept through the plate,
// R / cos β + t tan β, plus 0.75 t, rounded up to whole spacings. Here R 10 mm, t 12 mm, Δp 1.5 mm
// (the coarse preset): 19 mm → 19.5 mm at normal impact; at 30°, 11.55 + 6.93 + 9 = 27.5 mm →
// 28.5 mm. (Measured at the coarse preset, 303.5 m/s: the projectile leaves at 213.6, 214.1,
// 214.4, 214.0 and 214.4 m/s with half-widths of 16.5, 19.5, 22.5, 24 and 27 mm.)
TEST(PlateImpactScene, CoreIsSizedByTheSceneUnlessGiven) {
  std::string text = kScene;
  const std::string core = "core: {half_width: 0.024, spacing: 0.002}\n";
  text.erase(text.find(core), core.size());
  const Case normal = read_case_text(text, "plate.yaml");
  EXPECT_NEAR(body(normal, "plate_core").geometry.box.max.x(), 0.0195, 1e-12);
  EXPECT_NEAR(normal.scene->core_half_width, 0.0195, 1e-12);
  const Case oblique =
      read_case_text(text, "plate.yaml", {"symmetry=half", "projectile.obliquity=30"});
  EXPECT_NEAR(body(oblique, "plate_core").geometry.box.max.x(), 0.0285, 1e-12);
  EXPECT_NEAR(body(oblique, "plate_core").geometry.box.min.x(), -0.0285, 1e-12);
  // Given, it wins.
  EXPECT_NEAR(body(scene(), "plate_core").geometry.box.max.x(), 0.024, 1e-12);
}

// A pointed nose at an angle: its lowest node, meshed, lies the gap above the plate.
TEST(PlateImpactScene, ObliqueOgiveStartsTheGapAbove) {
  const Case normal = scene({"symmetry=half"});
  const double gap = body(normal, "projectile").geometry.cylinder.base.z();
  const Case c = scene(
      {"symmetry=half", "projectile.obliquity=40", "projectile.nose=ogival", "projectile.crh=2"});
  const Model m = mesh_case(c);
  double lowest = 1;
  for (std::size_t n = 0; n < m.x_n.size(); ++n)
    if (m.body_n[n] == c.body_index("projectile"))
      lowest = std::min(lowest, m.x_n[n].z());
  // An ogive of CRH 2 meets its axis at 41.4° and leans 40°: its tip, a node, is the lowest point.
  EXPECT_NEAR(lowest, gap, 1e-9);
}

// Without a contact block the projectile meets the core through the surface contact, whose
// penalty defaults to the softer P-wave modulus E (1 − ν)/((1 + ν)(1 − 2ν)) of the two materials
// (both 200 GPa, ν 0.33 here: 296.3 GPa), and it starts a quarter element beyond the top of the
// core's contact spheres, Δp/2 above the plate: 1 + 0.5 mm at 2 mm.
TEST(PlateImpactScene, SurfaceContactIsTheDefault) {
  std::string text = kScene;
  const std::string kernel = "  contact: {model: kernel, penalty: 1.0e11, exponent: 2}\n";
  text.erase(text.find(kernel), kernel.size());
  const Case c = read_case_text(text, "plate.yaml");
  ASSERT_EQ(c.contacts.size(), 1u);
  EXPECT_EQ(c.contacts[0].model, ContactModel::Surface);
  EXPECT_NEAR(c.contacts[0].penalty, 200e9 * 0.67 / (1.33 * 0.34), 1e-6 * 200e9);
  EXPECT_EQ(c.contacts[0].friction, 0.0);
  EXPECT_NEAR(body(c, "projectile").geometry.cylinder.base.z(), 0.0015, 1e-12);
  const Case rough = read_case_text(text, "plate.yaml", {"projectile.contact.friction=0.1"});
  EXPECT_EQ(rough.contacts[0].friction, 0.1);
  // The contact's own keys are checked as in a case's contact list.
  EXPECT_NE(error_of({"projectile.contact.exponent=4"}, text)
                .find("projectile.contact.exponent: only for model: kernel"),
            std::string::npos)
      << error_of({"projectile.contact.exponent=4"}, text);
  EXPECT_NE(error_of({"projectile.gap=0.0009"}, text).find("core's contact spheres"),
            std::string::npos)
      << error_of({"projectile.gap=0.0009"}, text);
}

TEST(PlateImpactScene, PresetsOverridesAndTheWholeModel) {
  // Without explicit sizes the preset decides.
  std::string text = kScene;
  for (const std::string given : {", spacing: 0.002", "  element_size: 0.002\n"})
    text.erase(text.find(given), given.size());
  for (const ResolutionPreset& preset : resolution_presets) {
    const Case c = read_case_text(text, "plate.yaml", {std::string("preset=") + preset.name});
    EXPECT_EQ(body(c, "plate_core").spacing, preset.spacing) << preset.name;
    EXPECT_EQ(body(c, "plate_ring").element_size, preset.spacing) << preset.name;
    EXPECT_EQ(body(c, "projectile").element_size, preset.spacing) << preset.name;
  }
  // An explicit spacing wins over the preset.
  const Case explicit_spacing = scene({"core.spacing=0.0015", "projectile.element_size=0.003"});
  EXPECT_EQ(body(explicit_spacing, "plate_core").spacing, 0.0015);
  EXPECT_EQ(body(explicit_spacing, "projectile").element_size, 0.003);

  EXPECT_TRUE(
      body(scene({"projectile.velocity=250"}), "projectile").velocity.isApprox(Vec3(0, 0, -250)));
  const Case whole = scene({"symmetry=none"});
  EXPECT_TRUE(body(whole, "plate_core").geometry.box.min.isApprox(Vec3(-0.024, -0.024, -0.012)));
  EXPECT_EQ(body(whole, "plate_ring").geometry.ring.sector, Sector::Full);
  EXPECT_EQ(body(whole, "projectile").geometry.cylinder.sector, Sector::Full);
  ASSERT_EQ(whole.boundary_conditions.size(), 1u);
}

TEST(PlateImpactScene, BadScenesAreNamed) {
  EXPECT_NE(error_of({"preset=medium"}).find("--set preset: preset: unknown preset 'medium'"),
            std::string::npos)
      << error_of({"preset=medium"});
  EXPECT_NE(error_of({"symmetry=eighth"}).find("symmetry"), std::string::npos);
  EXPECT_NE(error_of({"projectile.obliquity=20"})
                .find("symmetry: quarter needs a normal impact; a shot at obliquity 20° is "
                      "symmetric about y = 0 only (symmetry: half)"),
            std::string::npos)
      << error_of({"projectile.obliquity=20"});
  EXPECT_NE(error_of({"symmetry=half", "projectile.obliquity=90"})
                .find("projectile.obliquity: must be in [0, 90) degrees"),
            std::string::npos)
      << error_of({"symmetry=half", "projectile.obliquity=90"});
  EXPECT_NE(error_of({"symmetry=half", "projectile.obliquity=60", "core.half_width=0.018"})
                .find("footprint's half-length R / cos β = 0.02"),
            std::string::npos)
      << error_of({"symmetry=half", "projectile.obliquity=60", "core.half_width=0.018"});
  EXPECT_NE(error_of({"core.half_width=0.008"})
                .find("core.half_width: must exceed the "
                      "projectile's radius"),
            std::string::npos)
      << error_of({"core.half_width=0.008"});
  EXPECT_NE(error_of({"projectile.gap=0.002"}).find("projectile.gap"), std::string::npos)
      << error_of({"projectile.gap=0.002"});
  EXPECT_NE(error_of({"projectile.velocity=-10"}).find("projectile.velocity"), std::string::npos);
  EXPECT_NE(error_of({"projectile.nose=ogive"})
                .find("unknown nose 'ogive' (expected one of: blunt, hemispherical, conical, "
                      "ogival)"),
            std::string::npos)
      << error_of({"projectile.nose=ogive"});
  EXPECT_NE(error_of({"projectile.nose=conical"}).find("projectile.nose_length: missing key"),
            std::string::npos)
      << error_of({"projectile.nose=conical"});
  EXPECT_NE(error_of({"projectile.crh=3"}).find("projectile.crh: only for nose: ogival"),
            std::string::npos)
      << error_of({"projectile.crh=3"});
  EXPECT_NE(error_of({"projectile.nose=conical", "projectile.nose_length=0.09"})
                .find("must exceed the nose's length"),
            std::string::npos);
  EXPECT_NE(error_of({"plate.clamped_diameter=0.05"}).find("plate.clamped_diameter"),
            std::string::npos);
  EXPECT_NE(error_of({"core.spacing=0.0032"}).find("ends in .5"), std::string::npos)
      << error_of({"core.spacing=0.0032"});
  // The scene's own checks are reported at the top of the file, under "scene plate_impact".
  EXPECT_EQ(error_of({"core.spacing=0.013"}),
            "plate.yaml:1: scene plate_impact: core.spacing: 0.013 m is coarser than the core's "
            "half-width or the plate's thickness");
  // Bodies are the scene's to make; an unknown scene is named.
  EXPECT_NE(error_of({"bodies.extra.method=fem"}).find("bodies: unknown key"), std::string::npos)
      << error_of({"bodies.extra.method=fem"});
  EXPECT_NE(error_of({"scene=plate"}).find("scene: unknown scene 'plate'"), std::string::npos)
      << error_of({"scene=plate"});
}

// Mass of the bodies named: their particles' masses plus ρ0 × their hexahedra's volumes.
double mass_of(const Case& c, const Model& m, const std::vector<std::string>& bodies) {
  const auto wanted = [&](int body) {
    return std::ranges::find(bodies, c.bodies[static_cast<std::size_t>(body)].name) != bodies.end();
  };
  double mass = 0;
  for (std::size_t p = 0; p < m.m_p.size(); ++p)
    if (wanted(m.body_p[p]))
      mass += m.m_p[p];
  for (std::size_t e = 0; e < m.hex_e.size(); ++e) {
    if (!wanted(m.body_e[e]))
      continue;
    HexPoints x;
    for (int a = 0; a < 8; ++a)
      x[a] = m.x_n[static_cast<std::size_t>(m.hex_e[e][a])];
    const BodySpec& b = c.bodies[static_cast<std::size_t>(m.body_e[e])];
    mass += c.material(b.material).density * hex8_gradient(x).volume;
  }
  return mass;
}

TEST(PlateImpactScene, QuarterAndHalfModelsHoldTheirShareOfTheMass) {
  const Case quarter = scene(), half = scene({"symmetry=half"}), whole = scene({"symmetry=none"});
  const Model mq = mesh_case(quarter), mh = mesh_case(half), mw = mesh_case(whole);
  const std::vector<std::string> plate{"plate_core", "plate_ring"}, projectile{"projectile"};
  // Straight-edged hexahedra fill prisms over polygons inscribed in the circles, of area
  // (N/2) R² sin(2π/N): the plate's rim has N = 8 · 12 sides at 2 mm (less the 48 mm square
  // hole, which the core fills exactly), the projectile's N = 8 · 3 (3 = round(2.5) per 45°).
  const auto polygon = [](double n, double r) {
    return 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n);
  };
  const double plate_exact = 7850 * polygon(96, 0.25) * 0.012;
  const double projectile_exact = 7838 * polygon(24, 0.01) * 0.08;
  EXPECT_NEAR(mass_of(whole, mw, plate), plate_exact, 1e-9 * plate_exact);
  EXPECT_NEAR(mass_of(whole, mw, projectile), projectile_exact, 1e-9 * projectile_exact);
  // Plate and projectile are meshed quadrant by quadrant: the quarter is exactly a quarter.
  EXPECT_NEAR(mass_of(quarter, mq, plate), 0.25 * mass_of(whole, mw, plate), 1e-12 * plate_exact);
  EXPECT_NEAR(mass_of(quarter, mq, projectile), 0.25 * mass_of(whole, mw, projectile),
              1e-12 * projectile_exact);
  EXPECT_NEAR(mass_of(half, mh, plate), 0.5 * mass_of(whole, mw, plate), 1e-12 * plate_exact);
  EXPECT_NEAR(mass_of(half, mh, projectile), 0.5 * mass_of(whole, mw, projectile),
              1e-12 * projectile_exact);
  // The core's lattice likewise: its particles' masses (lumped on the nodes) sum to the box's.
  EXPECT_NEAR(mass_of(half, mh, {"plate_core"}), 7850 * 0.048 * 0.024 * 0.012,
              1e-9 * 7850 * 0.048 * 0.024 * 0.012);
}

// The ring's hole nodes coincide with the core's outer lattice nodes, so the mesher ties them
// (METHOD.md §4.2): every node of plate_ring/inner has a particle at its place.
TEST(PlateImpactScene, InterfaceMatchesTheLattice) {
  for (const std::string symmetry : {"quarter", "half", "none"}) {
    const Case c = scene({"symmetry=" + symmetry});
    const Model m = mesh_case(c);
    const auto& inner = m.node_sets.at("plate_ring/inner");
    ASSERT_FALSE(inner.empty());
    for (const Index n : inner) {
      const Vec3& x = m.x_n[static_cast<std::size_t>(n)];
      const bool matched =
          std::ranges::any_of(m.x_p, [&](const Vec3& p) { return (p - x).norm() < 1e-9; });
      ASSERT_TRUE(matched) << symmetry << ": node at " << x.transpose();
    }
    // 24 mm / 2 mm = 12 elements per half side, 6 layers: the hole's side nodes.
    // A quarter's two sides (13 + 13 − 1 nodes a layer), a half's three (13 + 25 + 13 − 2), the
    // whole's four (4 · 25 − 4).
    const std::size_t per_layer = symmetry == "quarter" ? 25 : symmetry == "half" ? 49 : 96;
    EXPECT_EQ(inner.size(), per_layer * 7);
  }
}

} // namespace
} // namespace sphfem
