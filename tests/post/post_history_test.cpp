// `sphfem post history` end to end, with DISPLAY unset: on synthetic histories of known straight
// lines the PNG has the asked size, is not blank and shows each run's curve (and the dashed
// reference) where the data put it; the CSV holds exactly the plotted data in the chart's
// units; bad input (options, a run's history.csv, the reference CSV) fails with one line naming
// the problem and writes nothing.
#include "png_pixels.hpp"
#include "tests/support/command.hpp"

#include "post/history_plot.hpp"
#include "post/line_chart.hpp"
#include "post/post.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
using sphfem::post::LineChart;
using sphfem::test::Result;
using sphfem::test::run_sphfem;
using sphfem::test::Scratch;
using sphfem::test::slurp;

namespace {

// A run folder whose history has straight lines over t = 0 … 10 µs: tip.vz = −slope·t[µs]
// m/s, tip.szz = −t[µs] GPa, body.bar.vz = −5·t[µs] m/s.
fs::path write_run(const fs::path& dir, const std::string& name, double slope) {
  const fs::path run = dir / name;
  fs::create_directories(run);
  std::ofstream out(run / "history.csv");
  out << "time,dt,tip.vz,tip.szz,body.bar.vz,energy.kinetic\n";
  for (int i = 0; i <= 100; ++i) {
    const double t_us = 0.1 * i;
    out << t_us * 1e-6 << ",1e-7," << -slope * t_us << "," << -1e9 * t_us << "," << -5 * t_us << ","
        << 1000 - t_us << "\n";
  }
  return run;
}

// Data x in [0, 10] µs and y in [−100, 0] give exactly those axes (steps 2 and 20).
void expected_pixel(int w, int h, double t_us, double v, double& px, double& py) {
  const auto r = LineChart::plot_area(w, h);
  px = r.left + t_us / 10 * (r.right - r.left);
  py = r.top + -v / 100 * (r.bottom - r.top);
}

struct CsvRow {
  std::string series;
  double time, value;
};

// Cells of a CSV line; a quoted cell may hold commas and doubled quotes.
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"')
      cells.back() += line[++i];
    else if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      cells.emplace_back();
    else
      cells.back() += c;
  }
  return cells;
}

std::vector<CsvRow> read_plot_csv(const fs::path& file, std::string& header) {
  std::ifstream in(file);
  std::getline(in, header);
  std::vector<CsvRow> rows;
  for (std::string line; std::getline(in, line);) {
    const auto cells = split_csv(line);
    EXPECT_EQ(cells.size(), 3u) << line;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    rows.push_back({cells[0], std::stod(cells[1]), cells[2].empty() ? nan : std::stod(cells[2])});
  }
  return rows;
}

} // namespace

TEST(PostHistory, ChartShowsEveryRunAndTheReferenceWhereTheDataSay) {
  const Scratch scratch("post_chart");
  const fs::path& dir = scratch.dir;
  const fs::path a = write_run(dir, "fe", 10), b = write_run(dir, "sph", 5);
  std::ofstream(dir / "ref.csv")
      << "# a made-up reference, SI units\ntime,tip.vz\n0,-80\n1e-5,-80\n";
  const fs::path plots = dir / "post";
  const auto r = run_sphfem("post history " + a.string() + " --compare " + b.string() +
                                " --reference " + (dir / "ref.csv").string() +
                                " --columns tip.vz --size 640x400 -o " + plots.string(),
                            dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("tip.vz.png"), std::string::npos);
  ASSERT_TRUE(fs::exists(plots / "tip.vz.png"));
  EXPECT_FALSE(fs::exists(plots / "tip.szz.png")); // only the chosen column

  const auto png = sphfem_test::read_png(plots / "tip.vz.png");
  ASSERT_EQ(png.width, 640);
  ASSERT_EQ(png.height, 400);
  const double ink = png.non_white_fraction(); // frame, grid, text, three curves
  EXPECT_GT(ink, 0.02);
  EXPECT_LT(ink, 0.5);
  const auto fe = LineChart::palette(0), sph = LineChart::palette(1);
  for (double t = 0.5; t < 10; t += 0.5) {
    double px, py;
    expected_pixel(640, 400, t, -10 * t, px, py);
    EXPECT_TRUE(png.near(px, py, fe)) << "fe at t = " << t << " µs";
    expected_pixel(640, 400, t, -5 * t, px, py);
    EXPECT_TRUE(png.near(px, py, sph)) << "sph at t = " << t << " µs";
    if (t >= 1) { // the curves are apart (≥ 15 px): each colour only on its own line
      EXPECT_FALSE(png.near(px, py, fe, 2)) << "fe on the sph line at t = " << t << " µs";
    }
  }
  int reference_pixels = 0; // dashed black at −80 m/s, left of the fe curve's crossing
  for (double t = 0.5; t < 7.5; t += 0.25) {
    double px, py;
    expected_pixel(640, 400, t, -80, px, py);
    reference_pixels += png.near(px, py, {0, 0, 0}, 0, 80);
  }
  EXPECT_GT(reference_pixels, 10);
}

TEST(PostHistory, CsvHoldsThePlottedDataInChartUnits) {
  const Scratch scratch("post_csv");
  const fs::path& dir = scratch.dir;
  const fs::path a = write_run(dir, "fe", 10), b = write_run(dir, "sph", 5);
  std::ofstream(dir / "ref.csv") << "time,tip.szz\n0,0\n5e-6,\n1e-5,-1e10\n";
  const auto r =
      run_sphfem("post history " + a.string() + " --compare " + b.string() +
                     " --label FE \"SPH, fine\" --reference " + (dir / "ref.csv").string(),
                 dir);
  ASSERT_EQ(r.code, 0) << r.err;
  // Default columns and folder: every probe's vz and szz and every body's vz, under RUN/plots.
  for (const char* c : {"tip.vz", "tip.szz", "body.bar.vz"}) {
    EXPECT_TRUE(fs::exists(a / "post" / (std::string(c) + ".png"))) << c;
    EXPECT_TRUE(fs::exists(a / "post" / (std::string(c) + ".csv"))) << c;
  }
  EXPECT_FALSE(fs::exists(a / "post" / "energy.kinetic.png"));

  std::string header;
  const auto rows = read_plot_csv(a / "post" / "tip.szz.csv", header);
  EXPECT_EQ(header, "series,time [us],tip.szz [GPa]");
  std::map<std::string, int> count;
  const auto history = sphfem::post::read_history_csv(a / "history.csv");
  for (const auto& row : rows) {
    const int i = count[row.series]++;
    if (row.series == "FE" || row.series == "SPH, fine") { // a label with a comma is quoted
      // %.10g: ten significant digits.
      EXPECT_NEAR(row.time, history["time"][i] * 1e6, 1e-9 * (1 + row.time));
      EXPECT_NEAR(row.value, history["tip.szz"][i] * 1e-9, 1e-9 * (1 + std::abs(row.value)));
    }
  }
  EXPECT_EQ(count["FE"], 101);
  EXPECT_EQ(count["SPH, fine"], 101);
  EXPECT_EQ(count["ref"], 3); // the empty cell is a gap, written as an empty value
  EXPECT_NE(slurp(a / "post" / "tip.szz.csv").find("ref,5,\n"), std::string::npos);
}

TEST(PostHistory, TimeUnitAndLabelsReachTheCsv) {
  const Scratch scratch("post_units");
  const fs::path& dir = scratch.dir;
  const fs::path a = write_run(dir, "fe", 10);
  const auto r = run_sphfem("post history " + a.string() +
                                " --columns body.bar.vz --time-unit ms -o " + (dir / "p").string(),
                            dir);
  ASSERT_EQ(r.code, 0) << r.err;
  std::string header;
  const auto rows = read_plot_csv(dir / "p" / "body.bar.vz.csv", header);
  EXPECT_EQ(header, "series,time [ms],body.bar.vz [m/s]");
  ASSERT_EQ(rows.size(), 101u);
  EXPECT_EQ(rows.front().series, "fe"); // the run folder's name
  EXPECT_NEAR(rows.back().time, 0.01, 1e-12);
  EXPECT_NEAR(rows.back().value, -50, 1e-9);
}

TEST(PostHistory, BadInputFailsWithOneLineAndWritesNothing) {
  const Scratch scratch("post_errors");
  const fs::path& dir = scratch.dir;
  const fs::path a = write_run(dir, "fe", 10);
  std::ofstream(dir / "bad.csv") << "time,tip.vz\n0,0\n1e-6,abc\n";
  std::ofstream(dir / "short.csv") << "time,tip.vz\n0,0\n1e-6\n";
  std::ofstream(dir / "notime.csv") << "t,tip.vz\n0,0\n";
  std::ofstream(dir / "other.csv") << "time,tip.vx\n0,0\n";
  std::ofstream(dir / "empty.csv") << "# only a comment\n\n";
  std::ofstream(dir / "blank.csv") << "time,,tip.vz\n0,0,0\n";
  std::ofstream(dir / "twice.csv") << "time,tip.vz,tip.vz\n0,0,0\n";
  // Runs whose own history.csv lacks the time, or any column a chart is drawn of by default.
  fs::create_directories(dir / "untimed");
  std::ofstream(dir / "untimed" / "history.csv") << "t,tip.vz\n0,0\n";
  fs::create_directories(dir / "energies");
  std::ofstream(dir / "energies" / "history.csv") << "time,energy.kinetic\n0,1\n";
  const std::string out = " -o " + (dir / "p").string();
  const std::string ref = " --columns tip.vz --reference " + dir.string() + "/";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"post history " + (dir / "missing").string(), "missing: no such run folder"},
      {"post history " + dir.string(), "not a run folder (no history.csv"},
      {"post history " + a.string() + " --columns tip.vz,nope",
       "unknown column nope; available: time, dt, tip.vz, tip.szz, body.bar.vz, energy.kinetic"},
      {"post history " + a.string() + ref + "bad.csv",
       "bad.csv:3: column tip.vz: not a number: abc"},
      {"post history " + a.string() + ref + "short.csv", "short.csv:3: expected 2 values, found 1"},
      {"post history " + a.string() + ref + "notime.csv", "notime.csv:1: no time column"},
      {"post history " + a.string() + ref + "other.csv",
       "other.csv:1: none of the plotted columns"},
      {"post history " + a.string() + ref + "absent.csv", "absent.csv: cannot open"},
      {"post history " + a.string() + ref + "empty.csv",
       "empty.csv: empty file, expected a header line"},
      {"post history " + a.string() + ref + "blank.csv", "blank.csv:1: empty column name"},
      {"post history " + a.string() + ref + "twice.csv",
       "twice.csv:1: column tip.vz appears twice"},
      {"post history " + (dir / "untimed").string() + " --columns tip.vz",
       "untimed/history.csv: no time column"},
      {"post history " + (dir / "energies").string(),
       "energies/history.csv: no probe or body velocity columns; choose some with --columns "
       "from: time, energy.kinetic"},
      {"post history " + a.string() + " --label x y", "2 --label values for 1 runs"},
      {"post history " + a.string() + " --time-unit h", "--time-unit h: expected s, ms, us or ns"},
      {"post history " + a.string() + " --size 640", "--size 640: expected WIDTHxHEIGHT"},
      {"post history " + a.string() + " --size 20x20", "chart size 20x20"},
      {"post history " + a.string() + " --compare " + (dir / "missing").string(), "no such run"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = run_sphfem(args + out, dir);
    EXPECT_NE(r.code, 0) << args;
    EXPECT_NE(r.err.find("sphfem: error: "), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "p")) << args;
  }
}

TEST(PostHistory, ProbesAndBodiesChooseTheirColumns) {
  Scratch s("post_select");
  const fs::path run = write_run(s.dir, "run", 10);
  const auto history = sphfem::post::read_history_csv(run / "history.csv");
  using V = std::vector<std::string>;
  EXPECT_EQ(sphfem::post::selected_history_columns(history, {"tip"}, {}), (V{"tip.vz", "tip.szz"}));
  EXPECT_EQ(sphfem::post::selected_history_columns(history, {}, {"bar"}), (V{"body.bar.vz"}));
  const Result r = run_sphfem(
      "post history " + run.string() + " --bodies bar -o " + (s.dir / "plots").string(), s.dir);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s.dir / "plots" / "body.bar.vz.png"));
  EXPECT_FALSE(fs::exists(s.dir / "plots" / "tip.vz.png"));
  const Result bad = run_sphfem("post history " + run.string() + " --probes nose", s.dir);
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.err.find("--probes: no probe nose in the history; probes: tip"), std::string::npos)
      << bad.err;
}

TEST(PostHistory, HelpDescribesTheCommand) {
  const Scratch scratch("post_help");
  const fs::path& dir = scratch.dir;
  const auto r = run_sphfem("post history --help", dir);
  EXPECT_EQ(r.code, 0);
  for (const char* word : {"--columns", "--compare", "--label", "--reference", "--time-unit",
                           "--size", "DIR/<column>.png", "GPa"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word;
}
