// Tests of the validation suite's scripts (scripts/validate.sh, scripts/validation-page.py):
// bad arguments are one-line errors with exit 2 and --help prints the usage; the page, fed the
// files the runs would leave, compares each quantity with its reference as computed here — the
// Børvik limit against 184.5 m/s, the plug of a quarter model taken 4 times against a 20 × 12 mm
// cylinder of 7850 kg/m³ — and marks the Børvik rows as calibrated on their reference.
#include "../support/command.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

namespace sphfem {
namespace {

namespace fs = std::filesystem;

using test::run_shell;

const std::string kScripts = std::string(SPHFEM_SOURCE_DIR) + "/scripts/";

TEST(ValidateScript, BadArgumentsAndHelp) {
  const test::Scratch s("validate_args");
  const auto bad = run_shell(kScripts + "validate.sh --preset huge -o " + s.dir.string(), s.dir);
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("validate: --preset: expected coarse, standard or fine, got 'huge'"),
            std::string::npos)
      << bad.err;
  EXPECT_EQ(run_shell(kScripts + "validate.sh -j two", s.dir).code, 2);
  EXPECT_EQ(run_shell(kScripts + "validate.sh --frobnicate", s.dir).code, 2);
  const auto help = run_shell(kScripts + "validate.sh --help", s.dir);
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("scripts/validate.sh [--preset coarse|standard|fine]"), std::string::npos)
      << help.out;
}

TEST(ValidationPage, ComparesEachQuantityWithItsReference) {
  const test::Scratch s("validation_page");
  const fs::path out = s.dir / "validation";
  for (const char* bar : {"bar_impact", "bar_pressed"}) {
    fs::create_directories(out / bar / "report");
    std::ofstream(out / bar / "report" / "reference.csv")
        << "quantity,reference,value,unit,relative_error,source\n"
           "bodies.bar_a.com_velocity.2,-200,-190,m/s,-0.05,\"1D theory, exchanged\"\n";
  }
  const fs::path run = out / "borvik_12mm" / "run_303.5";
  fs::create_directories(run);
  std::ofstream(run / "summary.json") << R"({"scene": {"symmetry": "quarter"}})";
  std::ofstream(out / "borvik_12mm" / "sweep.json") << R"({"fit": {"vbl_m_per_s": 190.0},
             "reference": {"comparisons": [{"label": "paper"}],
                           "points": [
               {"v0_m_per_s": 181.5, "vr_m_per_s": 0, "error_run_m_per_s": 69.4,
                "error_comparison_m_per_s": [0]},
               {"v0_m_per_s": 200, "vr_m_per_s": 71, "error_run_m_per_s": 6,
                "error_comparison_m_per_s": [-3]},
               {"v0_m_per_s": 300, "vr_m_per_s": 200, "error_run_m_per_s": 8,
                "error_comparison_m_per_s": [4]}]},
             "runs": [{"v0_m_per_s": 303.5, "plug_mass_kg": 0.0056, "run_folder": ")"
                                                    << run.string() << R"("}]})";
  const auto r = run_shell("python3 " + kScripts + "validation-page.py " + out.string(), s.dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = test::slurp(out / "validation.csv");
  // The bar rows carried over; the limit 190 against 184.5: +5.5 m/s, +2.98%.
  EXPECT_NE(csv.find("bar_impact,bodies.bar_a.com_velocity.2,-190.0,-200.0,10.0,-0.05,m/s"),
            std::string::npos)
      << csv;
  std::istringstream lines(csv);
  bool limit = false, plug = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("borvik_12mm,ballistic limit", 0) == 0) {
      limit = true;
      EXPECT_NE(line.find(",190.0,184.5,5.5,"), std::string::npos) << line;
      EXPECT_NE(line.find("fitted to this ballistic curve"), std::string::npos) << line;
    }
    if (line.rfind("borvik_12mm,plug mass", 0) == 0) {
      plug = true;
      const double cylinder = 7850 * std::numbers::pi * 0.01 * 0.01 * 0.012; // 29.6 g
      std::ostringstream expected;
      expected << ",0.0224,";
      EXPECT_NE(line.find(expected.str()), std::string::npos) << line;
      const double relative = 4 * 0.0056 / cylinder - 1;
      EXPECT_NE(line.find(std::to_string(relative).substr(0, 7)), std::string::npos)
          << line << " (" << relative << ")";
    }
  }
  EXPECT_TRUE(limit && plug) << csv;
  // The rms over the tests that perforated in the experiment (vr > 0): √((6² + 8²)/2) = 7.0711
  // m/s, the comparison's √((3² + 4²)/2) = 3.5355 m/s; the non-perforating test is left out.
  EXPECT_NE(csv.find("rms error of vpr over the 2 perforating tests,,,7.0710678"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("rms error of vpr over the 2 perforating tests, paper\",,,3.5355339"),
            std::string::npos)
      << csv;
  EXPECT_NE(test::slurp(out / "validation.html").find("calibrated on it"), std::string::npos);
}

} // namespace
} // namespace sphfem
