// Tests of the calibration scripts (scripts/calibrate.sh, scripts/calibration.py): bad arguments
// are one-line errors with exit 2; the analysis, fed histories of a punch whose force and travel
// are known in closed form, measures them as computed here — a trapezoid force (rising over 2 mm
// to its peak, held 2 mm, falling over 2 mm) at 20 m/s does the work peak × 4 mm and its 5 µs
// average falls below a tenth of the peak at 5.85 mm — and finds the L where a straight line
// through the SPH runs' works meets the finest hexahedral run's.
#include "../support/command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <string>

namespace sphfem {
namespace {

namespace fs = std::filesystem;

using test::run_shell;

const std::string kScripts = std::string(SPHFEM_SOURCE_DIR) + "/scripts/";

// A run folder whose history is the trapezoid punch with a whole-model peak force `peak` (N):
// the quarter model's contact.punch.fz is peak / 4; the punch moves at −20 m/s throughout.
void punch_run(const fs::path& dir, double peak) {
  fs::create_directories(dir);
  std::ofstream out(dir / "history.csv");
  out << "# a comment line, as the solver writes\ntime,body.punch.vz,contact.punch.fz\n";
  for (int i = 0; i <= 4000; ++i) {
    const double t = i * 1e-7, u = 20 * t; // m
    const double f = u < 0.002 ? u / 0.002 : u < 0.004 ? 1 : u < 0.006 ? (0.006 - u) / 0.002 : 0;
    out << t << ",-20," << peak / 4 * f << "\n";
  }
}

TEST(CalibrateScript, BadArgumentsAndHelp) {
  const test::Scratch s("calibrate_args");
  const auto bad = run_shell(kScripts + "calibrate.sh --spacings 1mm -o " + s.dir.string(), s.dir);
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("calibrate: expected a comma-separated list of lengths in m, got '1mm'"),
            std::string::npos)
      << bad.err;
  EXPECT_EQ(run_shell(kScripts + "calibrate.sh --material /no/such.yaml", s.dir).code, 2);
  EXPECT_EQ(run_shell(kScripts + "calibrate.sh -j two", s.dir).code, 2);
  EXPECT_EQ(run_shell(kScripts + "calibrate.sh --frobnicate", s.dir).code, 2);
  const auto help = run_shell(kScripts + "calibrate.sh --help", s.dir);
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("scripts/calibrate.sh [--material FILE]"), std::string::npos) << help.out;
  const auto empty = run_shell("python3 " + kScripts + "calibration.py " + s.dir.string(), s.dir);
  EXPECT_NE(empty.code, 0);
  EXPECT_NE(empty.err.find("no hex_<size> run with a history.csv"), std::string::npos) << empty.err;
}

TEST(Calibration, MeasuresTheTrapezoidAndFindsTheLength) {
  const test::Scratch s("calibration");
  const fs::path out = s.dir / "calibration";
  punch_run(out / "hex_0.0005", 300e3); // the finest: the reference, W = 1200 J
  punch_run(out / "hex_0.001", 330e3);
  punch_run(out / "sph_0.001_L0.0008", 250e3); // W = 1000 J
  punch_run(out / "sph_0.001_L0.0016", 350e3); // W = 1400 J: L = 1.2 mm gives 1200 J
  punch_run(out / "sph_0.0015_L0.0012", 280e3);
  const auto r = run_shell(
      "SPHFEM=/nonexistent python3 " + kScripts + "calibration.py " + out.string(), s.dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(test::slurp(out / "calibration.json"));
  EXPECT_EQ(j["reference"]["run"], "hex_0.0005");
  EXPECT_NEAR(j["reference"]["peak_force_N"].get<double>(), 300e3, 1e-6 * 300e3);
  EXPECT_NEAR(j["reference"]["work_J"].get<double>(), 1200, 1e-3); // trapezoid rule: exact
  EXPECT_NEAR(j["reference"]["separation_travel_m"].get<double>(), 5.85e-3, 0.01e-3);
  ASSERT_EQ(j["spacings"].size(), 2u);
  EXPECT_NEAR(j["spacings"][0]["spacing_m"].get<double>(), 0.001, 1e-12);
  EXPECT_NEAR(j["spacings"][0]["length_m"].get<double>(), 0.0012, 1e-8);
  EXPECT_FALSE(j["spacings"][0]["extrapolated"].get<bool>());
  EXPECT_TRUE(j["spacings"][1]["length_m"].is_null()); // one length run at 1.5 mm
  EXPECT_NE(r.out.find("spacing 1 mm: L = 1.2 mm"), std::string::npos) << r.out;
  const std::string csv = test::slurp(out / "calibration.csv");
  EXPECT_NE(csv.find("sph_0.001_L0.0008,sph,0.001,0.0008,250000,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",1000,0.8333\n"), std::string::npos) << csv;
}

} // namespace
} // namespace sphfem
