// Tests of the case-file reader: a full valid case, defaults, one test per class of bad
// input (each checking the reported location and key path), --set overrides, and material
// libraries (changed keys, bad references, libraries in a cycle).
#include "solver/io/case_reader.hpp"

#include "solver/core/error.hpp"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace sphfem {
namespace {

// The example of the schema, every section present.
const std::string kFullCase = R"(name: bar_pressed_fe
time:
  end: 14.0e-6
  cfl: 0.5
  output_interval: 0.5e-6
  history_interval: 1.0e-8
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}
  alu: {model: elastic, density: 2700, youngs_modulus: 70e9, poisson_ratio: 0.33}
bodies:
  bar:
    method: fem
    geometry:
      box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}
    element_size: 0.001
    material: steel
    velocity: [0, 0, -10]
  rod:
    method: fem
    geometry: {cylinder: {base: [0, 0, 0.2], axis: [0, 0, 0.08], radius: 0.01}}
    element_size: 0.002
    material: alu
boundary_conditions:
  - {type: fixed, body: bar, face: zmax}
  - {type: symmetry, body: bar, face: xmin}
  - {type: velocity, body: rod, face: top, velocity: [~, ~, -1.0], function: [[0, 0], [1e-6, 1]]}
loads:
  - {type: pressure, body: bar, face: zmin, pressure: 40.0e9, function: [[0,0],[1e-7,1],[9e-7,1],[1e-6,0]]}
probes:
  - {name: mid, body: bar, point: [0.0025, 0.0025, 0.05]}
  - {name: rod_tip, body: rod, point: [0, 0, 0.28]}
fem:
  hourglass: {form: stiffness, coefficient: 0.05}
  bulk_viscosity: {linear: 0.1, quadratic: 2.0}
output:
  frames: false
)";

// The smallest valid case; the bad-input tests edit one line of it. Line numbers:
// 1 name, 2 time, 3 materials, 4 steel, 5 bodies, 6 bar, 7 method, 8 geometry,
// 9 element_size, 10 material.
const std::string kMinimal = R"(name: bar
time: {end: 1.0e-5, output_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}
bodies:
  bar:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}}
    element_size: 0.001
    material: steel
)";

// `text` with its one occurrence of `from` replaced by `to`.
std::string edited(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the case";
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// The message of the Error that `read` throws.
template <class Read> std::string error_message(Read read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// The message of the Error that reading `text` as "case.yaml" throws.
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  return error_message([&] { read_case_text(text, "case.yaml", overrides); });
}

// Checks that `message` starts with `location_and_key` ("case.yaml:4: materials.steel: ")
// and contains `what`.
testing::AssertionResult reports(const std::string& message, const std::string& location_and_key,
                                 const std::string& what) {
  if (message.starts_with(location_and_key) && message.find(what) != std::string::npos)
    return testing::AssertionSuccess();
  return testing::AssertionFailure() << "message was: " << message;
}

TEST(CaseReader, ReadsFullCase) {
  const Case c = read_case_text(kFullCase, "cases/full.yaml");
  EXPECT_EQ(c.name, "bar_pressed_fe");
  EXPECT_EQ(c.file, std::filesystem::path("cases/full.yaml"));
  EXPECT_NEAR(c.time.end, 14.0e-6, 1e-18);
  EXPECT_NEAR(c.time.cfl, 0.5, 1e-15);
  EXPECT_NEAR(c.time.output_interval, 0.5e-6, 1e-18);
  EXPECT_NEAR(c.time.history_interval, 1.0e-8, 1e-20);

  ASSERT_EQ(c.materials.size(), 2u);
  EXPECT_EQ(c.materials[0].name, "steel");
  EXPECT_EQ(c.materials[0].model, "elastic");
  EXPECT_NEAR(c.materials[0].density, 7830, 1e-9);
  EXPECT_NEAR(c.materials[0].youngs_modulus, 207e9, 1e-3);
  EXPECT_NEAR(c.materials[0].poisson_ratio, 0.3, 1e-15);
  EXPECT_EQ(c.materials[1].name, "alu");

  ASSERT_EQ(c.bodies.size(), 2u); // in file order
  const BodySpec& bar = c.bodies[0];
  EXPECT_EQ(bar.name, "bar");
  EXPECT_EQ(bar.method, Method::Fem);
  EXPECT_EQ(bar.geometry.kind, GeometrySpec::Kind::Box);
  EXPECT_NEAR((bar.geometry.box.min - Vec3(0, 0, 0)).norm(), 0, 1e-15);
  EXPECT_NEAR((bar.geometry.box.max - Vec3(0.005, 0.005, 0.1)).norm(), 0, 1e-15);
  EXPECT_NEAR(bar.element_size, 0.001, 1e-15);
  EXPECT_EQ(bar.material, "steel");
  EXPECT_NEAR((bar.velocity - Vec3(0, 0, -10)).norm(), 0, 1e-15);
  const BodySpec& rod = c.bodies[1];
  EXPECT_EQ(rod.geometry.kind, GeometrySpec::Kind::Cylinder);
  EXPECT_NEAR((rod.geometry.cylinder.base - Vec3(0, 0, 0.2)).norm(), 0, 1e-15);
  EXPECT_NEAR((rod.geometry.cylinder.axis - Vec3(0, 0, 0.08)).norm(), 0, 1e-15);
  EXPECT_NEAR(rod.geometry.cylinder.radius, 0.01, 1e-15);
  EXPECT_NEAR(rod.velocity.norm(), 0, 1e-15);

  ASSERT_EQ(c.boundary_conditions.size(), 3u);
  EXPECT_EQ(c.boundary_conditions[0].type, BoundaryType::Fixed);
  EXPECT_EQ(c.boundary_conditions[0].face, "zmax");
  EXPECT_EQ(c.boundary_conditions[1].type, BoundaryType::Symmetry);
  EXPECT_EQ(c.boundary_conditions[1].face, "xmin");
  const BoundaryConditionSpec& moved = c.boundary_conditions[2];
  EXPECT_EQ(moved.type, BoundaryType::Velocity);
  EXPECT_EQ(moved.body, "rod");
  EXPECT_EQ(moved.face, "top");
  EXPECT_FALSE(moved.velocity[0].has_value());
  EXPECT_FALSE(moved.velocity[1].has_value());
  ASSERT_TRUE(moved.velocity[2].has_value());
  EXPECT_NEAR(*moved.velocity[2], -1.0, 1e-15);
  ASSERT_EQ(moved.function.table().size(), 2u);
  EXPECT_NEAR(moved.function(0.5e-6), 0.5, 1e-12);

  ASSERT_EQ(c.loads.size(), 1u);
  EXPECT_EQ(c.loads[0].body, "bar");
  EXPECT_EQ(c.loads[0].face, "zmin");
  EXPECT_NEAR(c.loads[0].pressure, 40.0e9, 1e-3);
  ASSERT_EQ(c.loads[0].function.table().size(), 4u);
  EXPECT_NEAR(c.loads[0].function(5e-7), 1.0, 1e-12);

  ASSERT_EQ(c.probes.size(), 2u);
  EXPECT_EQ(c.probes[0].name, "mid");
  EXPECT_EQ(c.probes[0].body, "bar");
  EXPECT_NEAR((c.probes[0].point - Vec3(0.0025, 0.0025, 0.05)).norm(), 0, 1e-15);
  EXPECT_EQ(c.probes[1].body, "rod");

  EXPECT_EQ(c.fem.hourglass_form, HourglassForm::Stiffness);
  EXPECT_NEAR(c.fem.hourglass_coefficient, 0.05, 1e-15);
  EXPECT_NEAR(c.fem.bulk_viscosity_linear, 0.1, 1e-15);
  EXPECT_NEAR(c.fem.bulk_viscosity_quadratic, 2.0, 1e-15);
  EXPECT_FALSE(c.output.frames);

  EXPECT_EQ(&c.material("alu"), &c.materials[1]);
  EXPECT_THROW(c.material("copper"), Error);
  EXPECT_EQ(c.body_index("rod"), 1);
  EXPECT_EQ(c.body_index("plate"), -1);
}

TEST(CaseReader, FillsDefaults) {
  const Case c = read_case_text(kMinimal, "case.yaml");
  EXPECT_NEAR(c.time.cfl, 0.9, 1e-15);
  EXPECT_NEAR(c.time.history_interval, 0, 1e-15);
  EXPECT_NEAR(c.bodies[0].velocity.norm(), 0, 1e-15);
  EXPECT_TRUE(c.boundary_conditions.empty());
  EXPECT_TRUE(c.loads.empty());
  EXPECT_TRUE(c.probes.empty());
  EXPECT_EQ(c.fem.hourglass_form, HourglassForm::Viscous);
  EXPECT_NEAR(c.fem.hourglass_coefficient, 0.1, 1e-15);
  EXPECT_NEAR(c.fem.bulk_viscosity_linear, 0.06, 1e-15);
  EXPECT_NEAR(c.fem.bulk_viscosity_quadratic, 1.5, 1e-15);
  EXPECT_TRUE(c.output.frames);
}

TEST(CaseReader, RejectsUnknownTopLevelKey) {
  EXPECT_TRUE(reports(error_of(kMinimal + "colour: red\n"), "case.yaml:11: colour: ",
                      "unknown key (expected one of: name, time, materials, bodies,"));
}

TEST(CaseReader, RejectsUnknownNestedKey) {
  const std::string bad =
      edited(kMinimal, "max: [0.005, 0.005, 0.1]}", "max: [1, 1, 1], colour: red}");
  EXPECT_EQ(error_of(bad),
            "case.yaml:8: bodies.bar.geometry.box.colour: unknown key (expected one of: min, max)");
}

TEST(CaseReader, RejectsWrongTypes) {
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "density: 7830", "density: heavy")),
                      "case.yaml:4: materials.steel.density: ", "must be a number, got heavy"));
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "density: 7830", "density: '7830'")),
                      "case.yaml:4: materials.steel.density: ", "must be a number"));
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "density: 7830", "density: .inf")),
                      "case.yaml:4: materials.steel.density: ", "must be a finite number"));
  EXPECT_TRUE(reports(error_of(kMinimal + "probes: {mid: 1}\n"),
                      "case.yaml:11: probes: ", "must be a list, got a map"));
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "min: [0, 0, 0]", "min: [0, 0]")),
                      "case.yaml:8: bodies.bar.geometry.box.min: ",
                      "must be a list of 3 numbers [x, y, z], got a list of 2"));
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "material: steel", "material: [steel]")),
                      "case.yaml:10: bodies.bar.material: ", "must be a string, got a list"));
  EXPECT_TRUE(reports(error_of(kMinimal + "output: {frames: often}\n"),
                      "case.yaml:11: output.frames: ", "must be true or false, got often"));
  EXPECT_TRUE(reports(error_of("- just\n- a list\n"),
                      "case.yaml:1: (top level): ", "must be a map, got a list of 2"));
}

TEST(CaseReader, RejectsMissingKey) {
  const std::string bad = edited(kMinimal, "{end: 1.0e-5, ", "{");
  EXPECT_EQ(error_of(bad), "case.yaml:2: time.end: missing key (end time, s)");
  // The line of a block map is that of its first key.
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "    method: fem\n", "")),
                      "case.yaml:7: bodies.bar.method: ", "missing key"));
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "name: bar\n", "")),
                      "case.yaml:1: name: ", "missing key (case name)"));
}

TEST(CaseReader, RejectsNonPositiveDensity) {
  EXPECT_EQ(error_of(edited(kMinimal, "density: 7830", "density: -7830")),
            "case.yaml:4: materials.steel.density: must be > 0 kg/m³, got -7830");
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "density: 7830", "density: 0")),
                      "case.yaml:4: materials.steel.density: ", "got 0"));
}

TEST(CaseReader, RejectsNonPositiveYoungsModulus) {
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "youngs_modulus: 207e9", "youngs_modulus: 0")),
                      "case.yaml:4: materials.steel.youngs_modulus: ", "must be > 0 Pa, got 0"));
}

TEST(CaseReader, RejectsPoissonRatioOutOfRange) {
  EXPECT_TRUE(
      reports(error_of(edited(kMinimal, "poisson_ratio: 0.3", "poisson_ratio: 0.5")),
              "case.yaml:4: materials.steel.poisson_ratio: ", "must be in (-1, 0.5), got 0.5"));
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "poisson_ratio: 0.3", "poisson_ratio: -1")),
                      "case.yaml:4: materials.steel.poisson_ratio: ", "got -1"));
}

TEST(CaseReader, RejectsUnknownMaterialModel) {
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "model: elastic", "model: plastic")),
                      "case.yaml:4: materials.steel.model: ",
                      "unknown model 'plastic' (expected one of: elastic, johnson_cook)"));
}

TEST(CaseReader, RejectsNegativeEndTime) {
  EXPECT_EQ(error_of(edited(kMinimal, "end: 1.0e-5", "end: -1.0e-5")),
            "case.yaml:2: time.end: must be > 0 s, got -1.0e-5");
}

TEST(CaseReader, RejectsNegativeOutputInterval) {
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "output_interval: 1.0e-6", "output_interval: -1")),
                      "case.yaml:2: time.output_interval: ", "must be > 0 s, got -1"));
}

// output.section: the plane the report cuts, and the window along u its picture shows.
TEST(CaseReader, ReadsTheSectionPlaneAndItsWindow) {
  const Case c = read_case_text(
      kMinimal +
          "output: {section: {point: [0, 0.001, 0], normal: [0, -2, 0], u_range: [0, 0.05]}}\n",
      "case.yaml");
  ASSERT_TRUE(c.output.section.has_value());
  EXPECT_EQ(c.output.section->normal, Vec3(0, -1, 0)); // normalised
  ASSERT_TRUE(c.output.section->u_range.has_value());
  EXPECT_EQ(*c.output.section->u_range, (std::array<double, 2>{0, 0.05}));
  const std::string section = "output: {section: {point: [0, 0, 0], normal: [0, 1, 0], u_range: ";
  EXPECT_TRUE(reports(error_of(kMinimal + section + "[0.05]}}\n"),
                      "case.yaml:11: output.section.u_range: ",
                      "must be a list of 2 numbers [u0, u1] (m along the section's u axis), got "
                      "a list of 1"));
  EXPECT_TRUE(reports(
      error_of(kMinimal + section + "[0.05, 0]}}\n"),
      "case.yaml:11: output.section.u_range: ", "must be [u0, u1] with u0 < u1, got [0.05, 0]"));
}

// output.checkpoint: how often OUT/checkpoint.h5 is written; Case::keys: the case as parsed,
// which a checkpoint records and a restart compares.
TEST(CaseReader, ReadsTheCheckpointCadenceAndKeepsTheKeys) {
  const Case defaults = read_case_text(kMinimal, "case.yaml");
  EXPECT_EQ(defaults.output.checkpoint.steps, 0);
  EXPECT_EQ(defaults.output.checkpoint.wall_s, 600);
  const Case c = read_case_text(kMinimal + "output: {checkpoint: {steps: 50, wall_s: 0}}\n",
                                "case.yaml", {"time.cfl=0.5"});
  EXPECT_EQ(c.output.checkpoint.steps, 50);
  EXPECT_EQ(c.output.checkpoint.wall_s, 0);
  EXPECT_EQ(c.keys.at("time.cfl"), "0.5"); // the override, as given
  EXPECT_EQ(c.keys.at("bodies.bar.geometry.box.max.2"), "0.1");
  EXPECT_EQ(c.keys.at("output.checkpoint.steps"), "50");
  const std::string cadence = "output: {checkpoint: ";
  EXPECT_TRUE(reports(error_of(kMinimal + cadence + "{steps: 2.5}}\n"),
                      "case.yaml:11: output.checkpoint.steps: ",
                      "must be a whole number of steps >= 0 (0: not by steps), got 2.5"));
  EXPECT_TRUE(reports(
      error_of(kMinimal + cadence + "{wall_s: -1}}\n"),
      "case.yaml:11: output.checkpoint.wall_s: ", "must be >= 0 s (0: not by time), got -1"));
  EXPECT_TRUE(reports(error_of(kMinimal + cadence + "{every: 5}}\n"), "case.yaml:11: ", "every"));
}

TEST(CaseReader, RejectsEmptyBox) {
  EXPECT_TRUE(
      reports(error_of(edited(kMinimal, "max: [0.005, 0.005, 0.1]", "max: [0.005, 0, 0.1]")),
              "case.yaml:8: bodies.bar.geometry.box: ",
              "empty geometry: max must exceed min in every component"));
}

TEST(CaseReader, RejectsZeroRadiusCylinder) {
  const std::string bad =
      edited(kMinimal, "{box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}}",
             "\n      cylinder: {base: [0, 0, 0], axis: [0, 0, 0.1], radius: 0}");
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:9: bodies.bar.geometry.cylinder.radius: ",
                      "must be > 0 m (empty geometry), got 0"));
}

TEST(CaseReader, RejectsGeometryWithoutExactlyOneShape) {
  EXPECT_TRUE(
      reports(error_of(edited(kMinimal, "geometry: {box:", "geometry: {cylinder: {}, box:")),
              "case.yaml:8: bodies.bar.geometry: ", "exactly one of: box, cylinder"));
}

TEST(CaseReader, RejectsUnknownMaterialReference) {
  EXPECT_TRUE(reports(
      error_of(edited(kMinimal, "material: steel", "material: stel")),
      "case.yaml:10: bodies.bar.material: ", "unknown material 'stel' (expected one of: steel)"));
}

TEST(CaseReader, RejectsDuplicateMaterial) {
  const std::string bad = edited(kMinimal, "bodies:", "  steel: {model: elastic}\nbodies:");
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:5: materials.steel: ",
                      "duplicate key (first given at case.yaml:4)"));
}

TEST(CaseReader, RejectsUnknownFaceName) {
  const std::string bad =
      kMinimal + "loads:\n  - {type: pressure, body: bar, face: top, pressure: 1}\n";
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:12: loads.0.face: ",
                      "unknown face 'top' (expected one of: xmin, xmax, ymin, ymax, zmin, zmax)"));
}

TEST(CaseReader, RejectsUnknownBodyInBoundaryCondition) {
  const std::string bad =
      kMinimal + "boundary_conditions:\n  - {type: fixed, body: rod, face: zmin}\n";
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:12: boundary_conditions.0.body: ",
                      "unknown body 'rod' (expected one of: bar)"));
}

TEST(CaseReader, RejectsUnknownBodyInProbe) {
  const std::string bad = kMinimal + "probes:\n  - {name: a, body: bar, point: [0, 0, 0]}\n" +
                          "  - {name: b, body: rod, point: [0, 0, 0]}\n";
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:13: probes.1.body: ", "unknown body 'rod'"));
}

TEST(CaseReader, RejectsDuplicateProbeName) {
  const std::string bad = kMinimal + "probes:\n  - {name: a, body: bar, point: [0, 0, 0]}\n" +
                          "  - {name: a, body: bar, point: [0, 0, 0]}\n";
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:13: probes.1.name: ", "duplicate probe name 'a'"));
}

TEST(CaseReader, RejectsVelocityOnNonVelocityCondition) {
  const std::string bad =
      kMinimal +
      "boundary_conditions:\n  - {type: fixed, body: bar, face: zmin, velocity: [0, 0, 0]}\n";
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:12: boundary_conditions.0.velocity: ",
                      "only allowed for type velocity"));
}

TEST(CaseReader, RejectsBadTimeFunction) {
  const std::string load = "loads:\n  - {type: pressure, body: bar, face: zmin, pressure: 1,\n"
                           "     function: [[0, 0], [2e-6, 1], [1e-6, 0]]}\n";
  EXPECT_TRUE(reports(error_of(kMinimal + load), "case.yaml:13: loads.0.function.2.0: ",
                      "times must be strictly increasing, got 1e-6 after 2e-6"));
  const std::string negative = edited(load, "[[0, 0],", "[[-1e-6, 0],");
  EXPECT_TRUE(reports(error_of(kMinimal + negative),
                      "case.yaml:13: loads.0.function.0.0: ", "negative times are not allowed"));
  const std::string empty = edited(load, "[[0, 0], [2e-6, 1], [1e-6, 0]]", "[]");
  EXPECT_TRUE(
      reports(error_of(kMinimal + empty), "case.yaml:13: loads.0.function: ", "at least one row"));
}

TEST(CaseReader, ReportsYamlSyntaxError) {
  const std::string bad =
      edited(kMinimal, "max: [0.005, 0.005, 0.1]}}", "max: [0.005, 0.005, 0.1}}");
  EXPECT_TRUE(reports(error_of(bad), "case.yaml:", ": YAML syntax error: "));
  EXPECT_TRUE(reports(error_of("name: a\n  time: b\n"), "case.yaml:2: YAML syntax error: ", ""));
}

TEST(CaseReader, ReadsFileAndReportsMissingFile) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "sphfem_case_reader_test.yaml";
  std::ofstream(file) << kMinimal;
  EXPECT_EQ(read_case(file).file, file);
  std::filesystem::remove(file);
  EXPECT_TRUE(reports(error_message([&] { read_case(file); }), file.string() + ": ",
                      "cannot open the case file"));
  const std::filesystem::path folder = std::filesystem::temp_directory_path();
  EXPECT_EQ(error_message([&] { read_case(folder); }),
            folder.string() + ": cannot open the case file (it is a directory)");
}

TEST(CaseReader, ThrowsOnlyLocatedErrorsOnOddInput) {
  for (const std::string text : {"", "42", "[", "a: *undefined", "? [a, b]\n: 1\n", "\t- x",
                                 "name: [a\n", "name: !!binary x\n", "&a a: b"}) {
    SCOPED_TRACE(text);
    const std::string message = error_of(text);
    EXPECT_TRUE(reports(message, "case.yaml:", ": "));
    // A line number, not yaml-cpp's own text.
    EXPECT_EQ(message.find_first_of("0123456789"), std::string("case.yaml:").size()) << message;
    EXPECT_EQ(message.find("cannot read the case"), std::string::npos) << message;
  }
  EXPECT_EQ(error_of("42"), "case.yaml:1: (top level): must be a map, got 42");
  EXPECT_EQ(error_of("? [a, b]\n: 1\n"),
            "case.yaml:1: (top level): keys must be names, got a list of 2");
}

TEST(CaseReader, RejectsBadNamesAndEmptyMaps) {
  EXPECT_EQ(error_of(edited(kMinimal, "name: bar", "name: my bar")),
            "case.yaml:1: name: invalid case name 'my bar' (use letters, digits, _, - and .)");
  EXPECT_EQ(error_of(edited(kMinimal, "  bar:\n", "  bar-1:\n")),
            "case.yaml:6: bodies.bar-1: invalid body name (use letters, digits and _)");
  const std::string probe = "probes:\n  - {name: tip-1, body: bar, point: [0, 0, 0]}\n";
  EXPECT_EQ(error_of(kMinimal + probe),
            "case.yaml:12: probes.0.name: invalid probe name 'tip-1' (use letters, digits and _)");
  const std::string steel =
      "  steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}\n";
  EXPECT_EQ(error_of(edited(kMinimal, "materials:\n" + steel, "materials: {}\n")),
            "case.yaml:3: materials: must define at least one material");
  EXPECT_EQ(error_of(kMinimal.substr(0, kMinimal.find("bodies:")) + "bodies: {}\n"),
            "case.yaml:5: bodies: must define at least one body");
}

TEST(CaseReader, RejectsBadVelocityConditions) {
  const std::string condition =
      "boundary_conditions:\n  - {type: velocity, body: bar, face: zmin, ";
  EXPECT_EQ(error_of(kMinimal + condition + "velocity: -1}\n"),
            "case.yaml:12: boundary_conditions.0.velocity: must be a list of 3 entries [vx, vy, "
            "vz], each a number or ~, got -1");
  EXPECT_EQ(error_of(kMinimal + condition + "velocity: [~, ~, ~]}\n"),
            "case.yaml:12: boundary_conditions.0.velocity: must prescribe at least one "
            "component, got [~, ~, ~]");
  const std::string function = "velocity: [0, 0, -1], function: [[0, 0], [1e-6]]}\n";
  EXPECT_EQ(error_of(kMinimal + condition + function),
            "case.yaml:12: boundary_conditions.0.function.1: must be a row [t, f] of 2 numbers, "
            "got a list of 1");
  const std::string fixed =
      "boundary_conditions:\n  - {type: fixed, body: bar, face: zmin, function: [[0, 1]]}\n";
  EXPECT_EQ(error_of(kMinimal + fixed),
            "case.yaml:12: boundary_conditions.0.function: only allowed for type velocity");
}

// ---- SPH bodies and the sph section ---------------------------------------------------------

// kMinimal with its body made an SPH body. Line numbers as in kMinimal; line 9 is spacing.
const std::string kSph = R"(name: bar
time: {end: 1.0e-5, output_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}
bodies:
  bar:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}}
    spacing: 0.001
    material: steel
)";

TEST(CaseReaderSph, ReadsSphBodyWithDefaults) {
  const Case c = read_case_text(kSph, "case.yaml");
  ASSERT_EQ(c.bodies.size(), 1u);
  const BodySpec& bar = c.bodies[0];
  EXPECT_EQ(bar.method, Method::Sph);
  EXPECT_EQ(bar.geometry.kind, GeometrySpec::Kind::Box);
  EXPECT_NEAR(bar.spacing, 0.001, 1e-18);
  EXPECT_NEAR(bar.h_factor, 1.2, 1e-15);
  EXPECT_EQ(bar.lattice, BodySpec::Lattice::Centred);
  EXPECT_EQ(bar.element_size, 0);
  // The sph section's defaults: every term on.
  EXPECT_TRUE(c.sph.artificial_viscosity);
  EXPECT_NEAR(c.sph.alpha, 1.0, 1e-15);
  EXPECT_NEAR(c.sph.beta, 2.0, 1e-15);
  EXPECT_TRUE(c.sph.artificial_stress);
  EXPECT_NEAR(c.sph.epsilon, 0.3, 1e-15);
  EXPECT_NEAR(c.sph.stress_exponent, 4, 1e-15);
  EXPECT_TRUE(c.sph.xsph);
  EXPECT_NEAR(c.sph.xsph_epsilon, 0.5, 1e-15);
  EXPECT_TRUE(c.sph.variable_h);
  EXPECT_NEAR(c.sph.cfl, 0.3, 1e-15);
  EXPECT_NEAR(c.sph.skin, 0.1, 1e-15);
}

TEST(CaseReaderSph, ReadsHFactorAndMixedBodies) {
  const std::string text =
      edited(kSph, "spacing: 0.001", "spacing: 0.002\n    h_factor: 1.5") +
      "  anvil:\n    method: fem\n    geometry: {box: {min: [0, 0, -1], max: [1, 1, 0]}}\n"
      "    element_size: 0.1\n    material: steel\n";
  const Case c = read_case_text(text, "case.yaml");
  ASSERT_EQ(c.bodies.size(), 2u);
  EXPECT_NEAR(c.bodies[0].h_factor, 1.5, 1e-15);
  EXPECT_NEAR(c.bodies[0].spacing, 0.002, 1e-18);
  EXPECT_EQ(c.bodies[1].method, Method::Fem);
  EXPECT_NEAR(c.bodies[1].element_size, 0.1, 1e-15);
}

TEST(CaseReaderSph, ReadsTheSphSectionInAllForms) {
  const Case maps = read_case_text(kSph + R"(sph:
  artificial_viscosity: {alpha: 0.5, beta: 1.0}
  artificial_stress: {epsilon: 0.2, n: 6}
  xsph: {epsilon: 0.25}
  variable_smoothing_length: false
  cfl: 0.2
  skin: 0.05
)",
                                   "case.yaml");
  EXPECT_TRUE(maps.sph.artificial_viscosity);
  EXPECT_NEAR(maps.sph.alpha, 0.5, 1e-15);
  EXPECT_NEAR(maps.sph.beta, 1.0, 1e-15);
  EXPECT_TRUE(maps.sph.artificial_stress);
  EXPECT_NEAR(maps.sph.epsilon, 0.2, 1e-15);
  EXPECT_NEAR(maps.sph.stress_exponent, 6, 1e-15);
  EXPECT_TRUE(maps.sph.xsph);
  EXPECT_NEAR(maps.sph.xsph_epsilon, 0.25, 1e-15);
  EXPECT_FALSE(maps.sph.variable_h);
  EXPECT_NEAR(maps.sph.cfl, 0.2, 1e-15);
  EXPECT_NEAR(maps.sph.skin, 0.05, 1e-15);

  const Case off = read_case_text(
      kSph + "sph: {artificial_viscosity: false, artificial_stress: false, xsph: false}\n",
      "case.yaml");
  EXPECT_FALSE(off.sph.artificial_viscosity);
  EXPECT_FALSE(off.sph.artificial_stress);
  EXPECT_FALSE(off.sph.xsph);

  // true and partial maps: on, missing parameters default; skin 0 is allowed.
  const Case on = read_case_text(
      kSph + "sph: {artificial_viscosity: {beta: 1.5}, artificial_stress: true, xsph: {},\n"
             "      skin: 0}\n",
      "case.yaml");
  EXPECT_TRUE(on.sph.artificial_viscosity);
  EXPECT_NEAR(on.sph.alpha, 1.0, 1e-15);
  EXPECT_NEAR(on.sph.beta, 1.5, 1e-15);
  EXPECT_TRUE(on.sph.artificial_stress);
  EXPECT_NEAR(on.sph.epsilon, 0.3, 1e-15);
  EXPECT_TRUE(on.sph.xsph);
  EXPECT_NEAR(on.sph.xsph_epsilon, 0.5, 1e-15);
  EXPECT_EQ(on.sph.skin, 0);
}

TEST(CaseReaderSph, RejectsBadSpacing) {
  EXPECT_EQ(error_of(edited(kSph, "spacing: 0.001", "spacing: 0")),
            "case.yaml:9: bodies.bar.spacing: must be > 0 m, got 0");
  EXPECT_TRUE(reports(error_of(edited(kSph, "spacing: 0.001", "spacing: -1e-3")),
                      "case.yaml:9: bodies.bar.spacing: ", "must be > 0 m"));
  EXPECT_TRUE(reports(error_of(edited(kSph, "spacing: 0.001", "spacing: fine")),
                      "case.yaml:9: bodies.bar.spacing: ", "must be a number, got fine"));
  EXPECT_TRUE(reports(error_of(edited(kSph, "    spacing: 0.001\n", "")),
                      "case.yaml:7: bodies.bar.spacing: ", "missing key (particle spacing"));
}

TEST(CaseReaderSph, RejectsHFactorOutOfRange) {
  for (const std::string bad : {"0.99", "2.01", "0", "-1.2"})
    EXPECT_TRUE(
        reports(error_of(edited(kSph, "spacing: 0.001", "spacing: 0.001\n    h_factor: " + bad)),
                "case.yaml:10: bodies.bar.h_factor: ", "must be in [1.0, 2.0], got " + bad));
  for (const std::string good : {"1.0", "2.0"})
    EXPECT_NO_THROW(read_case_text(
        edited(kSph, "spacing: 0.001", "spacing: 0.001\n    h_factor: " + good), "case.yaml"));
}

TEST(CaseReaderSph, RejectsKeysOfTheOtherMethod) {
  EXPECT_TRUE(
      reports(error_of(edited(kSph, "spacing: 0.001", "spacing: 0.001\n    element_size: 0.001")),
              "case.yaml:10: bodies.bar.element_size: ",
              "only allowed for method fem (an sph body takes spacing)"));
  EXPECT_TRUE(reports(
      error_of(edited(kMinimal, "element_size: 0.001", "element_size: 0.001\n    spacing: 0.001")),
      "case.yaml:10: bodies.bar.spacing: ",
      "only allowed for method sph (a fem body takes element_size)"));
  EXPECT_TRUE(reports(
      error_of(edited(kMinimal, "element_size: 0.001", "element_size: 0.001\n    lattice: nodes")),
      "case.yaml:10: bodies.bar.lattice: ", "only allowed for method sph"));
  EXPECT_TRUE(reports(
      error_of(edited(kMinimal, "method: fem", "method: dem")),
      "case.yaml:7: bodies.bar.method: ", "unknown method 'dem' (expected one of: fem, sph)"));
}

TEST(CaseReaderSph, RejectsBadSphSectionValues) {
  const auto sph_error = [](const std::string& section) {
    return error_of(kSph + "sph: " + section + "\n");
  };
  EXPECT_EQ(sph_error("{artificial_viscosity: {alpha: -1}}"),
            "case.yaml:11: sph.artificial_viscosity.alpha: must be >= 0, got -1");
  EXPECT_TRUE(reports(sph_error("{artificial_viscosity: {beta: -0.5}}"),
                      "case.yaml:11: sph.artificial_viscosity.beta: ", "must be >= 0"));
  EXPECT_TRUE(reports(sph_error("{artificial_stress: {epsilon: -0.3}}"),
                      "case.yaml:11: sph.artificial_stress.epsilon: ", "must be >= 0"));
  EXPECT_TRUE(
      reports(sph_error("{artificial_stress: {n: 0}}"),
              "case.yaml:11: sph.artificial_stress.n: ", "must be a positive integer, got 0"));
  EXPECT_TRUE(reports(sph_error("{artificial_stress: {n: 2.5}}"),
                      "case.yaml:11: sph.artificial_stress.n: ", "must be a positive integer"));
  EXPECT_TRUE(reports(sph_error("{gradient_correction: 3}"),
                      "case.yaml:11: sph.gradient_correction: ", "must be true or false, got 3"));
  EXPECT_TRUE(reports(sph_error("{xsph: {epsilon: -1}}"),
                      "case.yaml:11: sph.xsph.epsilon: ", "must be >= 0"));
  EXPECT_TRUE(
      reports(sph_error("{cfl: 0}"), "case.yaml:11: sph.cfl: ", "must be in (0, 1], got 0"));
  EXPECT_TRUE(reports(sph_error("{cfl: 1.5}"), "case.yaml:11: sph.cfl: ", "must be in (0, 1]"));
  EXPECT_TRUE(reports(sph_error("{skin: -0.1}"), "case.yaml:11: sph.skin: ", "must be >= 0"));
  EXPECT_TRUE(
      reports(sph_error("{variable_smoothing_length: 2}"),
              "case.yaml:11: sph.variable_smoothing_length: ", "must be true or false, got 2"));
}

TEST(CaseReaderSph, RejectsMalformedSphTerms) {
  const auto sph_error = [](const std::string& section) {
    return error_of(kSph + "sph: " + section + "\n");
  };
  EXPECT_EQ(sph_error("{artificial_viscosity: maybe}"),
            "case.yaml:11: sph.artificial_viscosity: must be false, true or a map of alpha, "
            "beta, balsara, got maybe");
  EXPECT_TRUE(reports(sph_error("{xsph: [0.5]}"), "case.yaml:11: sph.xsph: ",
                      "must be false, true or a map of epsilon, got a list of 1"));
  EXPECT_TRUE(reports(sph_error("{artificial_stress: ~}"),
                      "case.yaml:11: sph.artificial_stress: ", "got null"));
  EXPECT_TRUE(reports(sph_error("{xsph: {eps: 0.5}}"),
                      "case.yaml:11: sph.xsph.eps: ", "unknown key (expected one of: epsilon)"));
  EXPECT_TRUE(reports(sph_error("{viscosity: false}"), "case.yaml:11: sph.viscosity: ",
                      "unknown key (expected one of: artificial_viscosity,"));
  EXPECT_TRUE(reports(sph_error("on"), "case.yaml:11: sph: ", "must be a map"));
}

// kSph with its box replaced by a cylinder (same line numbers).
const std::string kSphCylinder =
    R"(name: bar
time: {end: 1.0e-5, output_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}
bodies:
  bar:
    method: sph
    geometry: {cylinder: {base: [0, 0, 0], axis: [0, 0, 0.1], radius: 0.003}}
    spacing: 0.001
    material: steel
)";

TEST(CaseReaderSph, ReadsTheLatticeKey) {
  const auto lattice = [](const std::string& value) {
    return read_case_text(edited(kSph, "spacing: 0.001", "spacing: 0.001\n    lattice: " + value),
                          "case.yaml")
        .bodies[0]
        .lattice;
  };
  EXPECT_EQ(lattice("nodes"), BodySpec::Lattice::Nodes);
  EXPECT_EQ(lattice("centred"), BodySpec::Lattice::Centred);
  EXPECT_EQ(read_case_text(kSph, "case.yaml", {"bodies.bar.lattice=nodes"}).bodies[0].lattice,
            BodySpec::Lattice::Nodes);
  // centred is allowed for every geometry.
  EXPECT_EQ(
      read_case_text(edited(kSphCylinder, "spacing: 0.001", "spacing: 0.001\n    lattice: centred"),
                     "case.yaml")
          .bodies[0]
          .lattice,
      BodySpec::Lattice::Centred);
}

TEST(CaseReaderSph, RejectsBadLattices) {
  EXPECT_EQ(error_of(edited(kSph, "spacing: 0.001", "spacing: 0.001\n    lattice: corners")),
            "case.yaml:10: bodies.bar.lattice: unknown lattice 'corners' (expected one of: "
            "centred, nodes)");
  EXPECT_EQ(error_of(edited(kSphCylinder, "spacing: 0.001", "spacing: 0.001\n    lattice: nodes")),
            "case.yaml:10: bodies.bar.lattice: nodes is only allowed for a box geometry (use "
            "centred for a cylinder)");
  EXPECT_TRUE(reports(error_of(kSphCylinder, {"bodies.bar.lattice=nodes"}),
                      "--set bodies.bar.lattice: bodies.bar.lattice: ",
                      "nodes is only allowed for a box geometry"));
  EXPECT_TRUE(reports(
      error_of(edited(kMinimal, "element_size: 0.001", "element_size: 0.001\n    lattice: nodes")),
      "case.yaml:10: bodies.bar.lattice: ",
      "only allowed for method sph (a fem body takes element_size)"));
}

// Fixed and velocity conditions and pressure loads act on an SPH box's particle faces.
TEST(CaseReaderSph, ReadsBoundaryConditionsAndLoadsOnSphBoxes) {
  for (const std::string lattice : {"centred", "nodes"}) {
    SCOPED_TRACE(lattice);
    const Case c =
        read_case_text(edited(kSph, "spacing: 0.001", "spacing: 0.001\n    lattice: " + lattice) +
                           "boundary_conditions:\n"
                           "  - {type: fixed, body: bar, face: zmin}\n"
                           "  - {type: velocity, body: bar, face: xmax, velocity: [~, 0, ~]}\n"
                           "loads:\n"
                           "  - {type: pressure, body: bar, face: zmax, pressure: 40.0e9,\n"
                           "     function: [[0, 0], [1e-7, 1]]}\n",
                       "case.yaml");
    ASSERT_EQ(c.boundary_conditions.size(), 2u);
    EXPECT_EQ(c.boundary_conditions[0].type, BoundaryType::Fixed);
    EXPECT_EQ(c.boundary_conditions[0].body, "bar");
    EXPECT_EQ(c.boundary_conditions[0].face, "zmin");
    EXPECT_EQ(c.boundary_conditions[1].type, BoundaryType::Velocity);
    EXPECT_EQ(c.boundary_conditions[1].face, "xmax");
    EXPECT_FALSE(c.boundary_conditions[1].velocity[0].has_value());
    EXPECT_EQ(c.boundary_conditions[1].velocity[1], 0.0);
    ASSERT_EQ(c.loads.size(), 1u);
    EXPECT_EQ(c.loads[0].body, "bar");
    EXPECT_EQ(c.loads[0].face, "zmax");
    EXPECT_NEAR(c.loads[0].pressure, 40e9, 1e-3);
  }
}

TEST(CaseReaderSph, AcceptsSymmetryOnABoxFace) {
  const Case c = read_case_text(
      kSph + "boundary_conditions:\n  - {type: symmetry, body: bar, face: xmin}\n", "case.yaml");
  ASSERT_EQ(c.boundary_conditions.size(), 1u);
  EXPECT_EQ(c.boundary_conditions[0].type, BoundaryType::Symmetry);
}

TEST(CaseReaderSph, RejectsFacesAnSphBoxDoesNotHave) {
  EXPECT_TRUE(reports(error_of(kSph + "boundary_conditions:\n  - {type: fixed, body: bar, "
                                      "face: top}\n"),
                      "case.yaml:12: boundary_conditions.0.face: ",
                      "unknown face 'top' (expected one of: xmin, xmax, ymin, ymax, zmin, zmax)"));
  EXPECT_TRUE(
      reports(error_of(kSph + "loads:\n  - {type: pressure, body: bar, face: side, pressure: 1}\n"),
              "case.yaml:12: loads.0.face: ", "unknown face 'side'"));
}

TEST(CaseReaderSph, RejectsBoundaryConditionsAndLoadsOnSphCylinders) {
  const std::string what = "'bar' is an SPH body with a cylinder: particle faces exist only for "
                           "box bodies";
  EXPECT_EQ(
      error_of(kSphCylinder + "boundary_conditions:\n  - {type: fixed, body: bar, face: base}\n"),
      "case.yaml:12: boundary_conditions.0.body: " + what);
  EXPECT_EQ(error_of(kSphCylinder +
                     "boundary_conditions:\n  - {type: symmetry, body: bar, face: base}\n"),
            "case.yaml:12: boundary_conditions.0.body: " + what);
  EXPECT_EQ(
      error_of(kSphCylinder + "loads:\n  - {type: pressure, body: bar, face: top, pressure: 1}\n"),
      "case.yaml:12: loads.0.body: " + what);
}

TEST(CaseReaderSph, AllowsProbesOnSphBodies) {
  const Case c = read_case_text(kSph + "probes:\n  - {name: tip, body: bar, point: [0, 0, 0.1]}\n",
                                "case.yaml");
  ASSERT_EQ(c.probes.size(), 1u);
  EXPECT_EQ(c.probes[0].body, "bar");
}

TEST(CaseReaderSph, OverridesSphKeys) {
  const Case c = read_case_text(kSph, "case.yaml",
                                {"bodies.bar.spacing=0.0005", "sph.xsph=false", "sph.cfl=0.25"});
  EXPECT_NEAR(c.bodies[0].spacing, 0.0005, 1e-18);
  EXPECT_FALSE(c.sph.xsph);
  EXPECT_NEAR(c.sph.cfl, 0.25, 1e-15);
  EXPECT_EQ(error_of(kSph, {"bodies.bar.h_factor=3"}),
            "--set bodies.bar.h_factor: bodies.bar.h_factor: must be in [1.0, 2.0], got 3");
}

// Rings, quarter cylinders and the section plane: the checks beyond a number's range.
TEST(CaseReader, RejectsImpossibleGeometry) {
  const std::string box = "{box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}}";
  const auto fem = [&](const std::string& geometry) {
    return error_of(edited(kMinimal, box, geometry));
  };
  EXPECT_EQ(fem("{cylinder: {base: [0, 0, 0], axis: [0, 0, 0], radius: 0.01}}"),
            "case.yaml:8: bodies.bar.geometry.cylinder.axis: empty geometry: the axis must have "
            "a non-zero length");
  EXPECT_EQ(fem("{cylinder: {base: [0, 0, 0], axis: [0.1, 0, 0], radius: 0.01, sector: quarter}}"),
            "case.yaml:8: bodies.bar.geometry.cylinder.axis: a quarter cylinder needs an axis "
            "along +z, got [0.1, 0, 0]");
  EXPECT_TRUE(reports(fem("{ring: {base: [0, 0, 0], half_width: 0.01, radius: 0.014, "
                          "thickness: 0.005}}"),
                      "case.yaml:8: bodies.bar.geometry.ring.radius: ",
                      "must exceed the hole's corner distance √2 · half_width = 0.014142 m"));
  const std::string sph_ring = "{ring: {base: [0, 0, 0], half_width: 0.01, radius: 0.05, "
                               "thickness: 0.005}}";
  EXPECT_EQ(error_of(edited(kSph, box, sph_ring)),
            "case.yaml:8: bodies.bar.geometry.ring: a ring is only meshed in hexahedra (method "
            "fem)");
  EXPECT_EQ(error_of(edited(kSphCylinder, "radius: 0.003}", "radius: 0.003, sector: quarter}")),
            "case.yaml:8: bodies.bar.geometry.cylinder.sector: quarter is only meshed in "
            "hexahedra (method fem); an sph body takes a box");
  EXPECT_EQ(error_of(kMinimal + "output: {section: {point: [0, 0, 0], normal: [0, 0, 0]}}\n"),
            "case.yaml:11: output.section.normal: must be a non-zero vector");
}

// ---- geometry files -------------------------------------------------------------------------

class CaseFiles : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("sphfem_case_reader_test_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_ / "shapes");
    std::ofstream(dir_ / "shapes" / "ball.geo") << "SetFactory(\"OpenCASCADE\");\n"
                                                   "Sphere(1) = {0, 0, 0, 0.01};\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // kSph with its geometry replaced by `geometry`, written as dir/case.yaml.
  std::filesystem::path case_file(const std::string& geometry) const {
    const std::filesystem::path file = dir_ / "case.yaml";
    std::ofstream(file) << edited(kSph, "{box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}}",
                                  geometry);
    return file;
  }

  std::filesystem::path dir_;
};

TEST_F(CaseFiles, ResolvesGeometryFileRelativeToTheCaseFile) {
  const Case c = read_case(case_file("{file: shapes/ball.geo}"));
  EXPECT_EQ(c.bodies[0].geometry.kind, GeometrySpec::Kind::File);
  EXPECT_TRUE(c.bodies[0].geometry.file.is_absolute());
  EXPECT_TRUE(std::filesystem::equivalent(c.bodies[0].geometry.file, dir_ / "shapes" / "ball.geo"));
  // Also from text, relative to the folder of the name given, and through ../
  const Case t = read_case_text(edited(kSph, "{box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}}",
                                       "{file: ../shapes/ball.geo}"),
                                dir_ / "cases" / "case.yaml");
  EXPECT_EQ(t.bodies[0].geometry.file, (dir_ / "shapes" / "ball.geo").lexically_normal());
  // An absolute path is kept.
  const std::string absolute = (dir_ / "shapes" / "ball.geo").string();
  EXPECT_EQ(read_case(case_file("{file: '" + absolute + "'}")).bodies[0].geometry.file,
            std::filesystem::path(absolute));
}

TEST_F(CaseFiles, RejectsMissingGeometryFile) {
  const std::filesystem::path file = case_file("{file: shapes/cube.geo}");
  const std::string message = error_message([&] { read_case(file); });
  EXPECT_TRUE(reports(message, file.string() + ":8: bodies.bar.geometry.file: ",
                      "geometry file 'shapes/cube.geo' not found (looked for " +
                          (dir_ / "shapes" / "cube.geo").string() + ")"));
  EXPECT_TRUE(reports(error_message([&] { read_case(case_file("{file: shapes}")); }),
                      (dir_ / "case.yaml").string() + ":8: bodies.bar.geometry.file: ",
                      "unsupported geometry file type ''"));
}

TEST_F(CaseFiles, RejectsBadGeometryFileEntries) {
  const std::string where = (dir_ / "case.yaml").string() + ":8: bodies.bar.geometry";
  EXPECT_TRUE(reports(error_message([&] { read_case(case_file("{file: shapes/ball.stl}")); }),
                      where + ".file: ",
                      "unsupported geometry file type '.stl' (expected one of: .geo, .step, "
                      ".stp, .brep)"));
  EXPECT_TRUE(reports(error_message([&] { read_case(case_file("{file: ''}")); }),
                      where + ".file: ", "must name a geometry file"));
  EXPECT_TRUE(reports(error_message([&] {
                        read_case(case_file("{file: shapes/ball.geo, box: {min: [0, 0, 0], "
                                            "max: [1, 1, 1]}}"));
                      }),
                      where + ": ", "must have exactly one of: box, cylinder, ring, file"));
}

TEST_F(CaseFiles, RejectsGeometryFileForFemBody) {
  const std::filesystem::path file = dir_ / "fem.yaml";
  std::ofstream(file) << edited(kMinimal, "{box: {min: [0, 0, 0], max: [0.005, 0.005, 0.1]}}",
                                "{file: shapes/ball.geo}");
  EXPECT_TRUE(reports(error_message([&] { read_case(file); }),
                      file.string() + ":8: bodies.bar.geometry.file: ",
                      "a geometry file is only supported for sph bodies (a fem body needs a box "
                      "or a cylinder)"));
}

TEST_F(CaseFiles, RejectsNodeLatticeAndFacesOfGeometryFiles) {
  const std::filesystem::path file = case_file("{file: shapes/ball.geo}");
  const std::string text = [&] {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  std::ofstream(file) << edited(text, "spacing: 0.001", "spacing: 0.001\n    lattice: nodes");
  EXPECT_EQ(error_message([&] { read_case(file); }),
            file.string() + ":10: bodies.bar.lattice: nodes is only allowed for a box geometry "
                            "(use centred for a geometry file)");
  std::ofstream(file) << text
                      << "loads:\n  - {type: pressure, body: bar, face: top, pressure: 1}\n";
  EXPECT_EQ(error_message([&] { read_case(file); }),
            file.string() + ":12: loads.0.body: 'bar' is an SPH body with a geometry file: "
                            "particle faces exist only for box bodies");
}

// ---- couplings: attach, contact, h_factor of FE bodies ------------------------------------

// Two FE and two SPH bodies, no couplings yet; the tests append attach and contact lists.
// Lines: 6 bar_fe, 7 bar_sph, 8 anvil, 9 ball, the appended lists from 10.
const std::string kBodies = R"(name: coupled
time: {end: 1.0e-5, output_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}
bodies:
  bar_fe: {method: fem, geometry: {box: {min: [0, 0, 5e-3], max: [4e-3, 4e-3, 8e-3]}}, element_size: 1e-3, material: steel}
  bar_sph: {method: sph, geometry: {box: {min: [0, 0, 0], max: [4e-3, 4e-3, 5e-3]}}, spacing: 1e-3, material: steel}
  anvil: {method: fem, geometry: {box: {min: [0, 0, 0.02], max: [0.01, 0.01, 0.03]}}, element_size: 2e-3, material: steel}
  ball: {method: sph, geometry: {box: {min: [0, 0, -0.02], max: [0.01, 0.01, -0.01]}}, spacing: 1e-3, material: steel}
)";

TEST(CaseReaderCoupling, ReadsAttachAndContact) {
  const Case c = read_case_text(kBodies + R"(attach:
  - {bodies: [bar_sph, bar_fe]}
contact:
  - {bodies: [anvil, bar_fe], model: kernel, penalty: 1.0e11, exponent: 3}
  - bodies: [ball, anvil]
    model: kernel
    penalty: 2.0e11
  - {bodies: [ball, bar_fe], friction: 0.3}
  - {bodies: [bar_sph, anvil], model: surface, penalty: 5.0e10}
)",
                                "case.yaml");
  ASSERT_EQ(c.attachments.size(), 1u);
  EXPECT_EQ(c.attachments[0].fem_body, "bar_fe"); // either order in the file
  EXPECT_EQ(c.attachments[0].sph_body, "bar_sph");
  ASSERT_EQ(c.contacts.size(), 4u);
  EXPECT_EQ(c.contacts[0].bodies, (std::array<std::string, 2>{"anvil", "bar_fe"}));
  EXPECT_EQ(c.contacts[0].model, ContactModel::Kernel);
  EXPECT_NEAR(c.contacts[0].penalty, 1.0e11, 1.0);
  EXPECT_NEAR(c.contacts[0].exponent, 3, 1e-15);
  EXPECT_EQ(c.contacts[1].bodies, (std::array<std::string, 2>{"ball", "anvil"}));
  EXPECT_NEAR(c.contacts[1].penalty, 2.0e11, 1.0);
  EXPECT_NEAR(c.contacts[1].exponent, 2, 1e-15); // the default
  // The surface contact is the default; its penalty defaults to the softer body's P-wave modulus
  // K + 4G/3 = E (1 − ν)/((1 + ν)(1 − 2ν)), 278.65 GPa for this steel.
  EXPECT_EQ(c.contacts[2].model, ContactModel::Surface);
  EXPECT_NEAR(c.contacts[2].penalty, 207e9 * 0.7 / (1.3 * 0.4), 1e-6 * 207e9);
  EXPECT_NEAR(c.contacts[2].friction, 0.3, 1e-15);
  EXPECT_EQ(c.contacts[3].model, ContactModel::Surface);
  EXPECT_NEAR(c.contacts[3].penalty, 5.0e10, 1.0);
  EXPECT_EQ(c.contacts[3].friction, 0.0);

  const Case none = read_case_text(kBodies + "attach: []\ncontact: []\n", "case.yaml");
  EXPECT_TRUE(none.attachments.empty());
  EXPECT_TRUE(none.contacts.empty());
}

// An FE body's h_factor sets its background particles' h (h_factor · element_size): any value
// > 0, default 1.2 (the SPH range [1, 2] is about neighbour counts, which do not apply).
TEST(CaseReaderCoupling, ReadsHFactorOfFemBodies) {
  const Case c = read_case_text(
      edited(kBodies, "element_size: 2e-3,", "element_size: 2e-3, h_factor: 2.5,"), "case.yaml");
  EXPECT_NEAR(c.bodies[0].h_factor, 1.2, 1e-15);
  EXPECT_NEAR(c.bodies[2].h_factor, 2.5, 1e-15);
  for (const std::string bad : {"0", "-1.2"})
    EXPECT_EQ(error_of(edited(kMinimal, "element_size: 0.001",
                              "element_size: 0.001\n    h_factor: " + bad)),
              "case.yaml:10: bodies.bar.h_factor: must be > 0, got " + bad);
  EXPECT_TRUE(reports(
      error_of(edited(kMinimal, "element_size: 0.001", "element_size: 0.001\n    h_factor: big")),
      "case.yaml:10: bodies.bar.h_factor: ", "must be a number, got big"));
}

// The error that reading kBodies with `lists` appended gives.
std::string coupling_error(const std::string& lists) {
  return error_of(kBodies + lists);
}

TEST(CaseReaderCoupling, RejectsMalformedPairs) {
  for (const std::string list : {"attach", "contact"}) {
    SCOPED_TRACE(list);
    const std::string extra = list == "contact" ? ", penalty: 1e11" : "";
    const auto item = [&](const std::string& bodies) {
      return coupling_error(list + ":\n  - {" + bodies + extra + "}\n");
    };
    EXPECT_EQ(coupling_error(list + ": {bodies: [bar_fe, bar_sph]}\n"),
              "case.yaml:10: " + list + ": must be a list, got a map");
    EXPECT_TRUE(reports(item("colour: red, bodies: [bar_fe, bar_sph]"),
                        "case.yaml:11: " + list + ".0.colour: ", "unknown key (expected one of: "));
    EXPECT_TRUE(
        reports(coupling_error(list + ":\n  - {" + extra.substr(extra.empty() ? 0 : 2) + "}\n"),
                "case.yaml:11: " + list + ".0.bodies: ", "missing key (the two bodies [a, b])"));
    EXPECT_EQ(item("bodies: [bar_fe]"), "case.yaml:11: " + list +
                                            ".0.bodies: must be a list of 2 body names [a, b], "
                                            "got a list of 1");
    EXPECT_TRUE(reports(item("bodies: bar_fe"), "case.yaml:11: " + list + ".0.bodies: ",
                        "must be a list of 2 body names [a, b], got bar_fe"));
    EXPECT_TRUE(reports(item("bodies: [bar_fe, bar_sph, ball]"),
                        "case.yaml:11: " + list + ".0.bodies: ", "got a list of 3"));
    EXPECT_EQ(item("bodies: [bar_fe, nobody]"),
              "case.yaml:11: " + list +
                  ".0.bodies.1: unknown body 'nobody' (expected one of: bar_fe, bar_sph, anvil, "
                  "ball)");
    EXPECT_TRUE(reports(item("bodies: [[bar_fe], bar_sph]"),
                        "case.yaml:11: " + list + ".0.bodies.0: ", "must be a string"));
    EXPECT_EQ(item("bodies: [bar_sph, bar_sph]"),
              "case.yaml:11: " + list +
                  ".0.bodies: must name two different bodies, got 'bar_sph' twice");
  }
}

TEST(CaseReaderCoupling, RejectsRepeatedPairs) {
  EXPECT_EQ(coupling_error("attach:\n  - {bodies: [bar_fe, bar_sph]}\n"
                           "  - {bodies: [bar_sph, bar_fe]}\n"),
            "case.yaml:12: attach.1.bodies: the pair 'bar_sph', 'bar_fe' is already given at "
            "case.yaml:11 (attach.0)");
  EXPECT_EQ(coupling_error("contact:\n  - {bodies: [anvil, ball], penalty: 1e11}\n"
                           "  - {bodies: [bar_fe, ball], penalty: 1e11}\n"
                           "  - {bodies: [ball, anvil], model: kernel, penalty: 2e11}\n"),
            "case.yaml:13: contact.2.bodies: the pair 'ball', 'anvil' is already given at "
            "case.yaml:11 (contact.0)");
}

TEST(CaseReaderCoupling, AttachesOneFemBodyToOneSphBody) {
  EXPECT_EQ(coupling_error("attach:\n  - {bodies: [bar_fe, anvil]}\n"),
            "case.yaml:11: attach.0.bodies: must name one fem body and one sph body, got 'bar_fe' "
            "and 'anvil', both fem");
  EXPECT_TRUE(reports(coupling_error("attach:\n  - {bodies: [ball, bar_sph]}\n"),
                      "case.yaml:11: attach.0.bodies: ", "got 'ball' and 'bar_sph', both sph"));
  // An SPH body joins at most one FE body; an FE body may hold several SPH bodies.
  EXPECT_EQ(coupling_error("attach:\n  - {bodies: [bar_fe, bar_sph]}\n"
                           "  - {bodies: [bar_sph, anvil]}\n"),
            "case.yaml:12: attach.1.bodies: sph body 'bar_sph' is already attached to 'bar_fe' "
            "at case.yaml:11 (an sph body attaches to at most one fem body)");
  const Case two = read_case_text(
      kBodies + "attach:\n  - {bodies: [bar_fe, bar_sph]}\n  - {bodies: [ball, bar_fe]}\n",
      "case.yaml");
  ASSERT_EQ(two.attachments.size(), 2u);
  EXPECT_EQ(two.attachments[1].fem_body, "bar_fe");
  EXPECT_EQ(two.attachments[1].sph_body, "ball");
}

TEST(CaseReaderCoupling, RejectsBadContactParameters) {
  const auto contact = [](const std::string& parameters) {
    return coupling_error("contact:\n  - {bodies: [bar_fe, anvil], model: kernel" + parameters +
                          "}\n");
  };
  EXPECT_TRUE(reports(contact(""),
                      "case.yaml:11: contact.0.penalty: ", "missing key (penalty pressure K, Pa)"));
  EXPECT_EQ(contact(", penalty: 0"), "case.yaml:11: contact.0.penalty: must be > 0 Pa, got 0");
  EXPECT_TRUE(
      reports(contact(", penalty: -1e11"), "case.yaml:11: contact.0.penalty: ", "must be > 0 Pa"));
  EXPECT_TRUE(reports(contact(", penalty: stiff"),
                      "case.yaml:11: contact.0.penalty: ", "must be a number, got stiff"));
  EXPECT_EQ(contact(", penalty: 1e11, exponent: 0"),
            "case.yaml:11: contact.0.exponent: must be > 0, got 0");
  EXPECT_TRUE(reports(contact(", penalty: 1e11, exponent: -2"),
                      "case.yaml:11: contact.0.exponent: ", "must be > 0"));
  const Case c = read_case_text(
      kBodies + "contact:\n  - {bodies: [bar_fe, anvil], model: kernel, penalty: 1e11, "
                "exponent: 1.5}\n",
      "case.yaml");
  EXPECT_NEAR(c.contacts[0].exponent, 1.5, 1e-15);
  // Each model takes only its own keys.
  const auto surface = [](const std::string& parameters) {
    return coupling_error("contact:\n  - {bodies: [bar_fe, anvil]" + parameters + "}\n");
  };
  EXPECT_EQ(surface(", exponent: 2"),
            "case.yaml:11: contact.0.exponent: only for model: kernel (the surface contact's force "
            "is linear in the penetration)");
  EXPECT_EQ(contact(", penalty: 1e11, friction: 0.2"),
            "case.yaml:11: contact.0.friction: only for model: surface (the kernel contact has no "
            "tangent plane)");
  EXPECT_EQ(surface(", friction: -0.1"),
            "case.yaml:11: contact.0.friction: must be >= 0, got -0.1");
  EXPECT_EQ(surface(", penalty: 0"), "case.yaml:11: contact.0.penalty: must be > 0 Pa, got 0");
  EXPECT_TRUE(reports(surface(", model: sticky"), "case.yaml:11: contact.0.model: ",
                      "unknown contact model 'sticky' (expected one of: surface, kernel)"));
}

// Attached bodies are one body, whose entities never meet through contact (METHOD.md §4.3).
TEST(CaseReaderCoupling, RejectsContactBetweenAttachedBodies) {
  EXPECT_EQ(coupling_error("attach:\n  - {bodies: [bar_fe, bar_sph]}\n"
                           "contact:\n  - {bodies: [bar_sph, bar_fe], penalty: 1e11}\n"),
            "case.yaml:13: contact.0.bodies: 'bar_sph' and 'bar_fe' are attached (one body): they "
            "cannot also be in contact");
}

TEST(CaseReaderCoupling, OverridesCouplingKeys) {
  const std::string contact =
      "contact:\n  - {bodies: [bar_fe, anvil], model: kernel, penalty: 1e11}\n";
  const Case c = read_case_text(kBodies + contact, "case.yaml",
                                {"contact.0.penalty=5e11", "bodies.anvil.h_factor=2"});
  EXPECT_NEAR(c.contacts[0].penalty, 5e11, 1.0);
  EXPECT_NEAR(c.bodies[2].h_factor, 2, 1e-15);
  EXPECT_EQ(error_of(kBodies + contact, {"contact.0.exponent=-1"}),
            "--set contact.0.exponent: contact.0.exponent: must be > 0, got -1");
  EXPECT_TRUE(reports(error_of(kBodies, {"attach=[{bodies: [bar_fe, anvil]}]"}),
                      "--set attach: attach.0.bodies: ", "one fem body and one sph body"));
}

TEST(CaseReaderOverrides, AppliesScalarOverride) {
  const Case c = read_case_text(kMinimal, "case.yaml", {"materials.steel.density=7800"});
  EXPECT_NEAR(c.materials[0].density, 7800, 1e-9);
}

TEST(CaseReaderOverrides, AppliesListOverride) {
  const Case c = read_case_text(kMinimal, "case.yaml", {"bodies.bar.velocity=[0, 0, -5]"});
  EXPECT_NEAR((c.bodies[0].velocity - Vec3(0, 0, -5)).norm(), 0, 1e-15);
}

TEST(CaseReaderOverrides, AppliesSequenceIndexOverride) {
  const Case c =
      read_case_text(kFullCase, "case.yaml", {"probes.1.point=[0, 0, 0.05]", "time.end=1e-5"});
  EXPECT_NEAR((c.probes[1].point - Vec3(0, 0, 0.05)).norm(), 0, 1e-15);
  EXPECT_NEAR((c.probes[0].point - Vec3(0.0025, 0.0025, 0.05)).norm(), 0, 1e-15);
  EXPECT_NEAR(c.time.end, 1e-5, 1e-20);
}

TEST(CaseReaderOverrides, LocatesOverriddenValues) {
  EXPECT_EQ(error_of(kMinimal, {"materials.steel.density=-1"}),
            "--set materials.steel.density: materials.steel.density: must be > 0 kg/m³, got -1");
  EXPECT_TRUE(reports(error_of(kMinimal, {"time={end: 1}"}),
                      "--set time: time.output_interval: ", "missing key"));
  // A problem elsewhere is still located in the file.
  EXPECT_TRUE(reports(error_of(edited(kMinimal, "density: 7830", "density: 0"), {"time.cfl=0.5"}),
                      "case.yaml:4: materials.steel.density: ", "must be > 0"));
}

TEST(CaseReaderOverrides, RejectsOverrideCreatingUnknownKey) {
  EXPECT_TRUE(reports(error_of(kMinimal, {"time.colour=red"}),
                      "--set time.colour: time.colour: ", "unknown key"));
  EXPECT_TRUE(reports(error_of(kMinimal, {"solver.threads=2"}),
                      "--set solver.threads: solver: ", "unknown key"));
  EXPECT_TRUE(reports(error_of(kMinimal, {"bodies.rod.method=fem"}),
                      "--set bodies.rod.method: bodies.rod.geometry: ", "missing key"));
}

TEST(CaseReaderOverrides, RejectsMalformedOverride) {
  EXPECT_EQ(error_of(kMinimal, {"time.end"}), "--set time.end: expected key.path=value");
  EXPECT_TRUE(reports(error_of(kMinimal, {"=1"}), "--set =1: ", "empty key"));
  EXPECT_TRUE(reports(error_of(kMinimal, {"time..end=1"}), "--set time..end=1: ", "empty key"));
  EXPECT_TRUE(reports(error_of(kFullCase, {"probes.2.point=[0, 0, 0]"}),
                      "--set probes.2.point=[0, 0, 0]: ", "index 2 out of range (probes has 2"));
  EXPECT_TRUE(reports(error_of(kFullCase, {"probes.first.point=[0, 0, 0]"}),
                      "--set probes.first.point=[0, 0, 0]: ", "must be an index"));
  EXPECT_TRUE(reports(error_of(kMinimal, {"name.first=x"}),
                      "--set name.first=x: ", "name is a single value"));
  EXPECT_TRUE(reports(error_of(kMinimal, {"time.end=[1"}),
                      "--set time.end=[1: ", "YAML syntax error in the value"));
}

TEST(CaseReaderOverrides, RejectsOverrideOfValueSharedByAlias) {
  const std::string shared =
      edited(kMinimal, "material: steel", "material: steel\n    velocity: &v [0, 0, 1]") +
      "probes:\n  - {name: p, body: bar, point: *v}\n";
  EXPECT_NEAR(read_case_text(shared, "case.yaml").probes[0].point.z(), 1.0, 1e-15);
  EXPECT_TRUE(reports(error_of(shared, {"probes.0.point=[0, 0, 2]"}),
                      "--set probes.0.point=[0, 0, 2]: ",
                      "probes.0.point is shared with other keys through a YAML alias"));
  EXPECT_TRUE(reports(error_of(shared, {"bodies.bar.velocity.2=2"}),
                      "--set bodies.bar.velocity.2=2: ", "bodies.bar.velocity is shared"));
}

// ---- Material libraries (cases/materials) -------------------------------------------------

const std::string kLibraries = std::string(SPHFEM_SOURCE_DIR) + "/cases/materials/";

TEST(CaseReader, MaterialFromLibraryWithChanges) {
  const Case c = read_case_text(
      edited(kMinimal,
             "steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}",
             "steel: {library: " + kLibraries + "weldox460e.yaml, entry: weldox460e_paper,\n" +
                 "          johnson_cook: {C: 0.02}, erosion: true}"),
      "case.yaml");
  const MaterialSpec& m = c.material("steel");
  EXPECT_EQ(m.model, "johnson_cook");
  EXPECT_EQ(m.density, 7850);
  ASSERT_TRUE(m.johnson_cook && m.damage && m.heating && m.eos);
  EXPECT_EQ(m.johnson_cook->C, 0.02);  // changed
  EXPECT_EQ(m.johnson_cook->A, 490e6); // kept
  EXPECT_EQ(m.johnson_cook->rate_form, RateForm::Log);
  EXPECT_EQ(m.damage->D4, -0.0123);
  EXPECT_TRUE(m.erosion);
  // The entry defaults to the case's own name for the material; --set reaches library keys.
  const Case d = read_case_text(
      edited(kMinimal,
             "steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}",
             "arne: {library: " + kLibraries + "arne.yaml}"),
      "case.yaml", {"bodies.bar.material=arne", "materials.arne.density=7800"});
  EXPECT_EQ(d.material("arne").density, 7800);
  EXPECT_EQ(d.material("arne").youngs_modulus, 200e9);
}

TEST(CaseReader, MaterialLibraryErrorsNameTheFileAndEntry) {
  const std::string line =
      "steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}";
  EXPECT_TRUE(reports(
      error_of(edited(kMinimal, line, "steel: {library: " + kLibraries + "weldox460e.yaml}")),
      "case.yaml:4: materials.steel.library: ",
      "has no material 'steel' (it has: weldox460e, weldox460e_paper)"));
  EXPECT_TRUE(
      reports(error_of(edited(kMinimal, line, "steel: {library: no_such_library.yaml}")),
              "case.yaml:4: materials.steel.library: ", "no_such_library.yaml: no such file"));
  EXPECT_EQ(error_of(edited(kMinimal, line, "steel: {library: [weldox460e.yaml]}")),
            "case.yaml:4: materials.steel.library: must be a file name (a material library, "
            "cases/materials/)");
  EXPECT_EQ(
      error_of(edited(kMinimal, line,
                      "steel: {library: " + kLibraries + "weldox460e.yaml, entry: [weldox460e]}")),
      "case.yaml:4: materials.steel.entry: must be the name of a material in the library");
  // A changed key keeps its own line (the library's entry is merged under it).
  EXPECT_EQ(error_of(edited(kMinimal, line,
                            "steel:\n    library: " + kLibraries +
                                "weldox460e.yaml\n    entry: weldox460e\n    density: -1")),
            "case.yaml:7: materials.steel.density: must be > 0 kg/m³, got -1");
}

// A library that refers back to a file being read would be read forever (a stack overflow).
TEST_F(CaseFiles, RejectsMaterialLibrariesInACycle) {
  std::ofstream(dir_ / "a.yaml") << "materials:\n  steel: {library: b.yaml}\n";
  std::ofstream(dir_ / "b.yaml") << "materials:\n  steel: {library: a.yaml}\n";
  const std::string line =
      "steel: {model: elastic, density: 7830, youngs_modulus: 207e9, poisson_ratio: 0.3}";
  const std::filesystem::path file = dir_ / "case.yaml";
  std::ofstream(file) << edited(kMinimal, line, "steel: {library: a.yaml}");
  const std::filesystem::path a = std::filesystem::canonical(dir_ / "a.yaml");
  const std::filesystem::path b = std::filesystem::canonical(dir_ / "b.yaml");
  EXPECT_EQ(error_message([&] { read_case(file); }),
            (dir_ / "b.yaml").string() + ":2: materials.steel.library: " +
                (dir_ / "a.yaml").string() + ": the libraries refer to each other in a cycle (" +
                a.string() + " -> " + b.string() + " -> " + a.string() + ")");
  std::ofstream(file) << edited(kMinimal, line, "steel: {library: case.yaml}");
  EXPECT_TRUE(reports(error_message([&] { read_case(file); }),
                      file.string() + ":4: materials.steel.library: ",
                      "the libraries refer to each other in a cycle"));
}

} // namespace
} // namespace sphfem
