// End to end with the perforation materials: a blunt Arne steel block (hexahedra, elastic)
// strikes a 4 mm Weldox 460 E plate (particles, Johnson–Cook with damage, heating and the
// Mie–Grüneisen EOS, both from cases/materials/) at 800 m/s. The run must kill particles and
// still conserve mass and momentum, keep the energy balance, and write the material history
// to the frames and the kill counts to summary.json.
#include "tests/support/command.hpp"
#include "tests/support/punch_case.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using sphfem::test::slurp;

TEST(PerforationSmoke, KillsParticlesAndConservesWhatItMust) {
  const fs::path dir = fs::temp_directory_path() / "sphfem_e2e_punch";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "case.yaml") << sphfem::test::punch_case(0.012, 0.005, 0.012);
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
