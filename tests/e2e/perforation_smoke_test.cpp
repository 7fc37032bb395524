// End to end with the perforation materials: a blunt Arne steel block (hexahedra, elastic)
// strikes a 4 mm Weldox 460 E plate (particles, Johnson–Cook with damage, heating and the
// Mie–Grüneisen EOS, both from cases/materials/) at 800 m/s. The run must kill particles and
// still conserve mass and momentum, keep the energy balance, and write the material history
// to the frames and the kill counts to summary.json.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string materials = std::string(SPHFEM_SOURCE_DIR) + "/cases/materials/";

std::string punch_case() {
  return R"(name: punch
time: {end: 1.5e-5, cfl: 0.5, output_interval: 5.0e-6, history_interval: 1.0e-7}
materials:
  weldox460e: {library: )" +
         materials + R"(weldox460e.yaml}
  arne: {library: )" +
         materials + R"(arne.yaml}
bodies:
  plate:
    method: sph
    geometry: {box: {min: [-0.012, -0.012, -0.004], max: [0.012, 0.012, 0.0]}}
    spacing: 0.001
    material: weldox460e
  projectile:
    method: fem
    geometry: {box: {min: [-0.005, -0.005, 0.003], max: [0.005, 0.005, 0.015]}}
    element_size: 0.001
    material: arne
    velocity: [0, 0, -800]
contact:
  - {bodies: [plate, projectile], penalty: 1.0e11, exponent: 2}
)";
}

} // namespace

TEST(PerforationSmoke, KillsParticlesAndConservesWhatItMust) {
  const fs::path dir = fs::temp_directory_path() / "sphfem_e2e_punch";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "case.yaml") << punch_case();
  const std::string cmd = std::string(SPHFEM_BINARY) + " run " + (dir / "case.yaml").string() +
                          " -o " + (dir / "out").string() + " -q > " + (dir / "log.txt").string() +
                          " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "log.txt");

  const auto summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  const auto& plate = summary["bodies"]["plate"];
  const auto& projectile = summary["bodies"]["projectile"];
  EXPECT_GT(plate["killed_particles"].get<int>(), 50); // measured 272 of 2304
  EXPECT_EQ(projectile["killed_particles"].get<int>(), 0);
  // Mass: ρ V of each body, killed particles included.
  EXPECT_NEAR(plate["mass"].get<double>(), 7850 * 0.024 * 0.024 * 0.004, 1e-12);
  EXPECT_NEAR(projectile["mass"].get<double>(), 7838 * 0.01 * 0.01 * 0.012, 1e-12);
  EXPECT_LT(summary["momentum_drift"].get<double>(), 1e-12);
  // Energy: measured 2.9% (the elastic plate: 0.03%); see docs/materials.md.
  EXPECT_LT(summary["energy"]["balance_error"].get<double>(), 0.05);
  // The plate is pushed, the projectile slowed, neither past the other's speed.
  const double plate_vz = plate["com_velocity"][2].get<double>();
  const double projectile_vz = projectile["com_velocity"][2].get<double>();
  EXPECT_LT(plate_vz, -50.0);
  EXPECT_GT(projectile_vz, -800.0);
  EXPECT_LT(projectile_vz, plate_vz);

  // The last particle frame carries the material history and the kill flag.
  const std::string frame = slurp(dir / "out" / "frames" / "sph_000003.vtu");
  for (const char* array : {"plastic_strain", "damage", "temperature", "killed"})
    EXPECT_NE(frame.find(std::string("Name=\"") + array + "\""), std::string::npos) << array;
}
