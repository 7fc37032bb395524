// Acceptance tests of `sphfem material` (app/material_command.hpp), run as the built binary:
// the Weldox 460 E flow stress at p = 0.2 and its failure strain in a 1e-3/s tensile test
// against the closed forms of METHOD.md §5, an unknown material name, and the chart.
#include "tests/support/command.hpp"
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using sphfem::test::Result;
using sphfem::test::run_sphfem;
using sphfem::test::slurp;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sphfem_material_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The CSV's columns by name ('#' lines are comments).
std::map<std::string, std::vector<double>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#')
      continue;
    std::istringstream cells(line);
    std::string cell;
    if (names.empty()) {
      while (std::getline(cells, cell, ','))
        names.push_back(cell);
      continue;
    }
    for (std::size_t i = 0; std::getline(cells, cell, ','); ++i)
      columns[names.at(i)].push_back(std::stod(cell));
  }
  return columns;
}

// y at x by linear interpolation in a table with increasing x.
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  for (std::size_t i = 1; i < x.size(); ++i)
    if (x[i] >= at && x[i] > x[i - 1])
      return y[i - 1] + (at - x[i - 1]) / (x[i] - x[i - 1]) * (y[i] - y[i - 1]);
  ADD_FAILURE() << at << " beyond the table";
  return NAN;
}

// The first row of a CSV that has failed, or the number of rows.
std::size_t first_failed(std::map<std::string, std::vector<double>>& csv) {
  const auto& failed = csv["failed"];
  std::size_t first = 0;
  while (first < failed.size() && failed[first] == 0)
    ++first;
  return first;
}

const std::string library = std::string(SPHFEM_SOURCE_DIR) + "/cases/materials/weldox460e.yaml";
const std::string tensile = "material " + library +
                            " --material weldox460e --path uniaxial-stress --strain-rate 1e-3"
                            " --to 2.0 --no-heating";

// Constants of the `weldox460e` entry (cases/materials/weldox460e.yaml): A, B, n, C (power
// form), ṗ0; D1..D4 (D4 power form), D_C.
const double A = 490e6, B = 807e6, n = 0.73, C = 0.0114, rate0 = 5e-4;
const double D1 = 0.0705, D2 = 1.732, D3 = -0.54, D4 = -0.015, D_C = 0.3;

// (a) von Mises at p = 0.2 against (A + B 0.2ⁿ)(1 + ε̇/ṗ0)^C within 1% (the imposed rate stands
// for ṗ: they differ by ~1% there, which moves the rate term by ~1e-4). (d) the chart.
TEST(MaterialCommand, FlowStressMatchesJohnsonCook) {
  const fs::path dir = scratch("flow");
  const auto r = run_sphfem(tensile + " --no-damage -o " + (dir / "out.csv").string() + " --plot " +
                                (dir / "out.png").string(),
                            dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("peak von Mises"), std::string::npos) << r.out;
  auto csv = read_csv(dir / "out.csv");
  ASSERT_EQ(csv["von_mises_Pa"].size(), 2001u);
  const double at = interpolate(csv["plastic_strain"], csv["von_mises_Pa"], 0.2);
  const double expected = (A + B * std::pow(0.2, n)) * std::pow(1 + 1e-3 / rate0, C);
  EXPECT_NEAR(at, expected, 0.01 * expected);
  for (const double failed : csv["failed"])
    EXPECT_NEAR(failed, 0.0, 0.0);

  const std::string png = slurp(dir / "out.png");
  EXPECT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(0, 4), "\x89PNG");
  EXPECT_FALSE(fs::exists(dir / "out_damage.png")); // only with damage
}

// (b) with damage: D reaches D_C = 0.3 and the point fails at p_f(σ* = 1/3, ṗ* = 2) within 2%;
// after failure every stress is zero.
TEST(MaterialCommand, FailsAtTheFractureStrain) {
  const fs::path dir = scratch("failure");
  const auto r = run_sphfem(
      tensile + " -o " + (dir / "out.csv").string() + " --plot " + (dir / "out.png").string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("failed at strain"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "out_damage.png"));
  auto csv = read_csv(dir / "out.csv");
  const auto& failed = csv["failed"];
  const std::size_t first = first_failed(csv);
  ASSERT_LT(first, failed.size()) << "never failed";
  const double p_f = (D1 + D2 * std::exp(D3 / 3)) * std::pow(1 + 1e-3 / rate0, D4);
  EXPECT_NEAR(csv["plastic_strain"][first], p_f, 0.02 * p_f);
  EXPECT_NEAR(csv["damage"][first], D_C, 1e-9);
  for (std::size_t i = first; i < failed.size(); ++i) {
    EXPECT_NEAR(failed[i], 1.0, 0.0);
    for (const char* column : {"von_mises_Pa", "stress_xx_Pa", "stress_yy_Pa", "stress_zz_Pa",
                               "stress_xy_Pa", "stress_yz_Pa", "stress_zx_Pa", "pressure_Pa"})
      EXPECT_NEAR(csv[column][i], 0.0, 0.0) << column << " at row " << i;
  }
}

// --band-width on the Børvik case's regularised Weldox (L = 0.655 mm, β = 0.534): the point fails
// at p_f × (L / w)^β for w = 3.6 mm (2 h0 of a particle at the coarse preset), within 2%; on the
// library entry, which has no L, the option is an error naming the key, and nothing is written.
TEST(MaterialCommand, BandWidthScalesARegularisedFractureStrain) {
  const fs::path dir = scratch("band");
  const std::string borvik = std::string(SPHFEM_SOURCE_DIR) + "/cases/borvik_12mm/case.yaml";
  auto r = run_sphfem("material " + borvik +
                          " --material weldox460e --path uniaxial-stress --strain-rate 1e-3"
                          " --to 2.0 --no-heating --band-width 0.0036 -o " +
                          (dir / "out.csv").string(),
                      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  auto csv = read_csv(dir / "out.csv");
  ASSERT_LT(first_failed(csv), csv["failed"].size()) << "never failed";
  const double p_f = (D1 + D2 * std::exp(D3 / 3)) * std::pow(1 + 1e-3 / rate0, D4) *
                     std::pow(0.65536713386 / 3.6, 0.534);
  EXPECT_NEAR(csv["plastic_strain"][first_failed(csv)], p_f, 0.02 * p_f);
  EXPECT_NE(slurp(dir / "out.csv").find("--band-width 0.0036"), std::string::npos);

  r = run_sphfem(tensile + " --band-width 0.0024 -o " + (dir / "library.csv").string(), dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("'weldox460e' has no damage.regularisation_length"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "library.csv"));
}

// (c) an unknown name: non-zero exit, the name and the available ones in the message.
TEST(MaterialCommand, UnknownMaterialIsAnError) {
  const fs::path dir = scratch("unknown");
  const auto r = run_sphfem("material " + library +
                                " --material nosuch --path shear --strain-rate 1 --to 1 -o " +
                                (dir / "out.csv").string(),
                            dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("'nosuch'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("weldox460e, weldox460e_paper"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.csv"));
}

// A bad path name is rejected by the command line, before anything runs.
TEST(MaterialCommand, UnknownPathIsAnError) {
  const fs::path dir = scratch("path");
  const auto r = run_sphfem("material " + library +
                                " --material weldox460e --path biaxial --strain-rate 1 --to 1 -o " +
                                (dir / "out.csv").string(),
                            dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("biaxial"), std::string::npos) << r.err;
}

} // namespace
