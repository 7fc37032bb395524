// `sphfem post chart` end to end, with DISPLAY unset: on a CSV of two power laws in two groups the
// command draws one series per group, on log-log axes whose decades follow from the frame alone,
// each series' points where the data put them and in its own colour; bad input fails with one
// line naming the file, line or column, and writes nothing.
#include "png_pixels.hpp"
#include "tests/support/command.hpp"

#include "post/line_chart.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using sphfem::post::LineChart;
using sphfem::test::run_sphfem;
using sphfem::test::Scratch;

namespace {

// error = 10 / cost (group "a") and 100 / cost (group "b") at cost 1, 10, 100, 1000 s: the
// axes span x 10^0 … 10^3, y 10^−2 … 10^2.
fs::path write_table(const fs::path& dir) {
  const fs::path csv = dir / "cost.csv";
  std::ofstream out(csv);
  out << "# error against cost\nmodel,wall_s,error_pct\n";
  for (double cost : {1.0, 10.0, 100.0, 1000.0})
    out << "a," << cost << "," << 10 / cost << "\n";
  for (double cost : {1.0, 10.0, 100.0, 1000.0})
    out << "b," << cost << "," << 100 / cost << "\n";
  return csv;
}

} // namespace

TEST(PostChart, DrawsOneSeriesPerGroupOnLogLogAxes) {
  const Scratch scratch("post_chart");
  const fs::path csv = write_table(scratch.dir), png = scratch.dir / "chart.png";
  const auto r = run_sphfem("post chart " + csv.string() + " -o " + png.string() +
                                " --x wall_s --y error_pct --group model --log-x --log-y "
                                "--size 600x400",
                            scratch.dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("8 points, 2 series"), std::string::npos) << r.out;
  const auto pixels = sphfem_test::read_png(png);
  ASSERT_EQ(pixels.width, 600);
  ASSERT_EQ(pixels.height, 400);
  const auto frame = LineChart::plot_area(600, 400);
  auto at = [&](double cost, double error) { // x: 3 decades from 1; y: 4 decades from 0.01
    return std::pair{frame.left + std::log10(cost) / 3 * (frame.right - frame.left),
                     frame.bottom - (std::log10(error) + 2) / 4 * (frame.bottom - frame.top)};
  };
  for (double cost : {3.0, 30.0, 300.0}) { // between the points: on the straight segments
    const auto [ax, ay] = at(cost, 10 / cost);
    const auto [bx, by] = at(cost, 100 / cost);
    EXPECT_TRUE(pixels.near(ax, ay, LineChart::palette(0), 1)) << "a at " << cost;
    EXPECT_TRUE(pixels.near(bx, by, LineChart::palette(1), 1)) << "b at " << cost;
    EXPECT_FALSE(pixels.near(ax, ay, LineChart::palette(1), 3)) << "b is not at a's place";
  }
}

TEST(PostChart, BadInputFailsWithOneLineAndWritesNothing) {
  const Scratch scratch("post_chart_errors");
  const fs::path& dir = scratch.dir;
  const fs::path good = write_table(dir);
  std::ofstream(dir / "text.csv") << "model,wall_s,error_pct\na,1,2\nb,fast,3\n";
  std::ofstream(dir / "zero.csv") << "model,wall_s,error_pct\na,1,2\na,2,0\n";
  const std::string png = " -o " + (dir / "p.png").string();
  const std::string xy = " --x wall_s --y error_pct";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {good.string() + " --x wall_s --y err",
       "cost.csv: no column err (columns: model, wall_s, error_pct)"},
      {good.string() + xy + " --group kind", "no column kind"},
      {(dir / "text.csv").string() + xy, "text.csv:3: column wall_s: not a number: fast"},
      {(dir / "zero.csv").string() + xy + " --log-y",
       "zero.csv:3: column error_pct: 0 on a logarithmic axis (expected > 0)"},
      {(dir / "absent.csv").string() + xy, "absent.csv: cannot open"},
      {good.string() + xy + " --size 10x10", "chart size 10x10"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = run_sphfem("post chart " + args + png, dir);
    EXPECT_NE(r.code, 0) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "p.png")) << args;
  }
}
