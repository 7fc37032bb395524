// Tests of the scenes registry (solver/scenes/scene.hpp) and of how the case reader hands a
// `scene:` to it: names unique, a scene's keys apart from those every case has, an unknown scene
// answered with the list of known ones, and a scene's messages located as the reader's are.
#include "solver/scenes/scene.hpp"

#include "solver/core/error.hpp"
#include "solver/io/case_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

namespace sphfem {
namespace {

const std::string kPlate = R"(name: plate
scene: plate_impact
time: {end: 1.0e-5, output_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.33}
plate: {thickness: 0.012, clamped_diameter: 0.5, material: steel}
core: {half_width: 0.024}
projectile: {diameter: 0.02, length: 0.08, material: steel, velocity: 300}
)";

std::string error_of(const std::vector<std::string>& overrides) {
  try {
    read_case_text(kPlate, "plate.yaml", overrides);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Scenes, NamesAreUniqueAndKeysApartFromEveryCases) {
  const std::set<std::string_view> common{"name",   "scene", "time", "materials",
                                          "probes", "fem",   "sph",  "output"};
  std::set<std::string_view> names;
  ASSERT_FALSE(scene_types().empty());
  for (const SceneType& type : scene_types()) {
    EXPECT_TRUE(names.insert(type.name).second) << type.name << " registered twice";
    EXPECT_NE(type.read, nullptr) << type.name;
    for (const std::string_view key : type.keys)
      EXPECT_FALSE(common.contains(key)) << type.name << " claims the common key " << key;
  }
}

TEST(Scenes, UnknownSceneListsTheKnownOnes) {
  std::string expected;
  for (const SceneType& type : scene_types())
    expected += (expected.empty() ? "" : ", ") + std::string(type.name);
  EXPECT_EQ(error_of({"scene=plates"}),
            "--set scene: scene: unknown scene 'plates' (expected one of: " + expected + ")");
}

TEST(Scenes, KeysOutsideTheSceneAreRefusedWithTheSceneList) {
  const std::string error = error_of({"attach=[]"});
  EXPECT_NE(error.find("--set attach: attach: unknown key (expected one of: name, scene, time, "
                       "materials, probes, fem, sph, output, preset, symmetry, plate, core, "
                       "projectile)"),
            std::string::npos)
      << error;
}

TEST(Scenes, SceneValuesAreLocatedLikeTheReaders) {
  // A value from the file: its line; from an override: the --set key.
  EXPECT_EQ(error_of({"plate.thickness=-1"}),
            "--set plate.thickness: plate.thickness: must be > 0 m, got -1");
  EXPECT_EQ(error_of({"projectile.contact.exponent=3"}),
            "--set projectile.contact.exponent: projectile.contact.exponent: only for model: "
            "kernel (the surface contact's force is linear in the penetration)");
  EXPECT_NE(error_of({"core.colour=red"}).find("core.colour: unknown key"), std::string::npos);
  const Case c = read_case_text(kPlate, "plate.yaml");
  ASSERT_TRUE(c.scene.has_value());
  EXPECT_EQ(c.scene->name, "plate_impact");
  EXPECT_EQ(c.bodies.size(), 3u);
}

} // namespace
} // namespace sphfem
