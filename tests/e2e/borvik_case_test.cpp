// The Børvik case (cases/borvik_12mm) as CI can afford it: the quarter model of the plate scene
// against the whole one on an elastic impact (mirror particles and rollers must make them the
// same), and one coarse quarter shot at 303.5 m/s through `sphfem run`, case file as shipped:
// it perforates, with an energy balance within 5%.
#include "tests/support/command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using sphfem::test::run_sphfem;
using sphfem::test::Scratch;
using sphfem::test::slurp;

namespace {

// The Børvik scene at 2 mm with both materials elastic, for 25 µs: the projectile has struck
// the plate (its face starts 1.5 mm above the plate's and meets the core's spheres, Δp/2 above
// it, after 1.6 µs) and the wave has crossed the plate but not reached the rim.
const std::string kElasticScene = R"(name: borvik_elastic
scene: plate_impact
time: {end: 2.5e-5, output_interval: 2.5e-5, history_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.33}
  tool: {model: elastic, density: 7838, youngs_modulus: 200e9, poisson_ratio: 0.33}
plate: {thickness: 0.012, clamped_diameter: 0.5, material: steel}
core: {half_width: 0.024, spacing: 0.002}
projectile:
  diameter: 0.020
  length: 0.080
  element_size: 0.002
  material: tool
  velocity: 303.5
output: {frames: false}
)";

nlohmann::json summary_of(const fs::path& run) {
  return nlohmann::json::parse(slurp(run / "summary.json"));
}

TEST(BorvikCase, QuarterAndHalfModelsMatchTheWholeOneOnAnElasticImpact) {
  const Scratch scratch("borvik_symmetry");
  const fs::path c = scratch.dir / "case.yaml";
  std::ofstream(c) << kElasticScene;
  const char* symmetries[] = {"none", "half", "quarter"};
  double vz[3][2];
  for (int k = 0; k < 3; ++k) {
    const fs::path out = scratch.dir / symmetries[k];
    const auto r = run_sphfem("solve " + c.string() + " -o " + out.string() +
                                  " -q --set symmetry=" + symmetries[k],
                              scratch.dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto s = summary_of(out);
    vz[k][0] = s["bodies"]["plate_core"]["com_velocity"][2].get<double>();
    vz[k][1] = s["bodies"]["projectile"]["com_velocity"][2].get<double>();
    EXPECT_LT(s["energy"]["balance_error"].get<double>(), 0.01);
  }
  // The impact has happened: the projectile has slowed and the core moves.
  EXPECT_GT(vz[0][1], -300.0);
  EXPECT_LT(vz[0][0], -1.0);
  // The quarter's and the half's meshes are exactly the quadrant and the half of the whole one's,
  // and the surface contact meets the projectile's own faces, which the planes cut without
  // images. Measured at 25 µs: plate core −129.593 / −129.596 m/s, projectile −68.376 / −68.367
  // m/s, whole / quarter (0.01%; with the kernel contact's mirrored background particles the
  // projectile differed by 0.9%). What is left is the order of the sums: 0.1% bounds both.
  for (int k = 1; k < 3; ++k) {
    EXPECT_NEAR(vz[k][0], vz[0][0], 0.001 * std::abs(vz[0][0])) << symmetries[k] << ": plate core";
    EXPECT_NEAR(vz[k][1], vz[0][1], 0.001 * std::abs(vz[0][1])) << symmetries[k] << ": projectile";
  }
}

TEST(BorvikCase, CoarseQuarterShotRunsToTheEndWithItsReport) {
  const Scratch scratch("borvik_coarse");
  const fs::path out = scratch.dir / "run";
  const auto r =
      run_sphfem("run " + std::string(SPHFEM_SOURCE_DIR) + "/cases/borvik_12mm/case.yaml -o " +
                     out.string() + " -q --set preset=coarse --set time.output_interval=5.0e-5",
                 scratch.dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto s = summary_of(out);
  EXPECT_NEAR(s["time"].get<double>(), 3.0e-4, 1e-9);
  EXPECT_LT(s["energy"]["balance_error"].get<double>(), 0.05);
  EXPECT_EQ(s["scene"]["projectile"]["velocity"].get<double>(), 303.5);
  ASSERT_TRUE(s.contains("results"));
  const auto& results = s["results"];
  EXPECT_EQ(results["target"], "plate_core");
  EXPECT_EQ(results["projectile"], "projectile");
  // A plug is punched out and both leave the plate (measured with the case's surface contact and
  // regularised fracture strain: projectile 210.6 m/s, plug 238.1 m/s, 4.6 g of a quarter plug
  // whose cylinder of 20 mm × 12 mm would be 7.4 g). The experiment's projectile leaves at
  // 199.7 m/s and the standard preset gives 213.2 m/s (cases/borvik_12mm/README.md): within 10%
  // of the experiment even at the coarse preset (unregularised, with the kernel contact, it was
  // 169.7, −15%).
  EXPECT_TRUE(results["perforated"].get<bool>());
  EXPECT_NEAR(results["residual_velocity"]["projectile"].get<double>(), 199.7, 0.10 * 199.7);
  EXPECT_GT(results["residual_velocity"]["plug"].get<double>(),
            results["residual_velocity"]["projectile"].get<double>());
  EXPECT_GT(results["plug"]["mass"].get<double>(), 0.5 * 7.4e-3);
  EXPECT_LT(results["plug"]["mass"].get<double>(), 2.0 * 7.4e-3);
  // A normal impact on a quarter model: the whole bodies move along the axis, by symmetry.
  EXPECT_EQ(s["scene"]["symmetry"], "quarter");
  for (const char* body : {"projectile", "plug"}) {
    EXPECT_NEAR(results["deviation_deg"][body].get<double>(), 0.0, 1e-9) << body;
    EXPECT_NEAR(results["angle_from_normal_deg"][body].get<double>(), 0.0, 1e-9) << body;
    EXPECT_GE(results["speed"][body].get<double>(),
              results["residual_velocity"][body].get<double>() - 1e-9);
  }
  // The report compares with the experiment at this velocity (reference.csv's `when`).
  const std::string html = slurp(out / "report" / "report.html");
  EXPECT_NE(html.find("experiment (test 1)"), std::string::npos);
  EXPECT_EQ(html.find("experiment (test 2)"), std::string::npos);
}

} // namespace
