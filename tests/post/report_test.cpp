// Tests of `sphfem post report` (post/report.hpp): base64 against RFC 4648's vectors; the
// reference file's reader and its errors; a report for a run without reference values and
// for one whose case folder has them (values read back from the page), written by `sphfem run`
// itself at the end of the run; and the errors of a run folder with a bad summary.json or
// history.csv.
#include "post/report.hpp"
#include "tests/support/command.hpp"

#include "solver/core/error.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using sphfem::test::slurp;
using namespace sphfem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sphfem_report_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The FE bar of cases/bar_pressed_fe, 2 µs, copied into `dir` so its folder can hold a
// reference.csv; `sphfem run` on it; returns the run folder.
fs::path run_bar(const fs::path& dir) {
  fs::copy_file(fs::path(SPHFEM_SOURCE_DIR) / "cases/bar_pressed_fe/case.yaml", dir / "case.yaml");
  const fs::path out = dir / "out";
  const std::string cmd = std::string(SPHFEM_BINARY) + " run " + (dir / "case.yaml").string() +
                          " -o " + out.string() + " -q --set time.end=2e-6 > " +
                          (dir / "log.txt").string() + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "log.txt");
  return out;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

} // namespace

TEST(Report, Base64MatchesRfc4648) {
  EXPECT_EQ(post::base64(""), "");
  EXPECT_EQ(post::base64("f"), "Zg==");
  EXPECT_EQ(post::base64("fo"), "Zm8=");
  EXPECT_EQ(post::base64("foo"), "Zm9v");
  EXPECT_EQ(post::base64("foob"), "Zm9vYg==");
  EXPECT_EQ(post::base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(post::base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(post::base64(std::string("\xff\x00\x10", 3)), "/wAQ");
}

TEST(Report, ReferenceFileErrorsNameTheLine) {
  const fs::path dir = scratch("reference_errors");
  std::ofstream(dir / "bad_header.csv") << "what,value\n";
  std::ofstream(dir / "bad_value.csv") << "# comment\nquantity,value,unit,source\nsteps,12x,,\n";
  auto message = [](const fs::path& file) -> std::string {
    try {
      post::read_reference_csv(file);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(message(dir / "bad_header.csv").find("bad_header.csv:1: expected the header"),
            std::string::npos)
      << message(dir / "bad_header.csv");
  EXPECT_NE(message(dir / "bad_value.csv").find("bad_value.csv:3: value '12x' is not a number"),
            std::string::npos)
      << message(dir / "bad_value.csv");
  std::ofstream(dir / "bad_when.csv") << "quantity,value,unit,source,when\nsteps,12,,,preset\n";
  EXPECT_NE(
      message(dir / "bad_when.csv").find("bad_when.csv:2: when 'preset': expected path=value"),
      std::string::npos)
      << message(dir / "bad_when.csv");
  std::ofstream(dir / "empty.csv") << "# only a comment\n\n";
  EXPECT_NE(message(dir / "empty.csv")
                .find("empty.csv: empty (expected the header quantity,value,unit,source)"),
            std::string::npos)
      << message(dir / "empty.csv");
  EXPECT_NE(message(dir / "absent.csv").find("absent.csv: cannot open the reference file"),
            std::string::npos)
      << message(dir / "absent.csv");
  const auto rows = [&] {
    std::ofstream(dir / "good.csv") << "quantity,value,unit,source\n"
                                       "bodies.bar.mass,0.019575,kg,\"rho V, exact\"\n";
    return post::read_reference_csv(dir / "good.csv");
  }();
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].quantity, "bodies.bar.mass");
  EXPECT_EQ(rows[0].reference, 0.019575);
  EXPECT_EQ(rows[0].source, "rho V, exact");
}

TEST(Report, RunWritesAReportWithoutReference) {
  const fs::path out = run_bar(scratch("plain"));
  const fs::path html = out / "report" / "report.html";
  ASSERT_TRUE(fs::is_regular_file(html)) << "sphfem run writes the report";
  const std::string page = slurp(html);
  EXPECT_NE(page.find("<h1>sphfem report: bar_pressed_fe</h1>"), std::string::npos);
  // Energy, velocity vz and the section, each embedded; no external file referenced.
  EXPECT_GE(count(page, "src=\"data:image/png;base64,iVBORw0KGgo"), 3);
  EXPECT_EQ(count(page, "src=\"report/"), 0);
  EXPECT_NE(page.find("No reference values"), std::string::npos);
  EXPECT_NE(page.find("No fragments"), std::string::npos); // no particles in this run
  for (const char* png : {"energy.png", "energy_bodies.png", "velocity_vz.png", "section.png"})
    EXPECT_GT(fs::file_size(out / "report" / png), 1000u) << png;
  EXPECT_NE(page.find("<th>internal energy (J)</th>"), std::string::npos);
}

TEST(Report, ComparesWithTheCaseReference) {
  const fs::path dir = scratch("reference");
  // ρ V of the 5 × 5 × 100 mm bar, the element count, and a quantity the run does not have.
  std::ofstream(dir / "reference.csv") << "quantity,value,unit,source\n"
                                          "bodies.bar.mass,0.019575,kg,7830 × 5 × 5 × 100 mm³\n"
                                          "counts.elements,2500,,5 × 5 × 100 hexahedra\n"
                                          "counts.elements,2000,,a wrong value\n"
                                          "results.plug.mass,0.1,kg,no plug in a bar\n"
                                          "history.time.max,2e-6,s,the end time\n";
  const fs::path out = run_bar(dir);
  const auto report = post::write_report({out, {}, out / "again"});
  ASSERT_EQ(report.references.size(), 5u);
  EXPECT_TRUE(report.references[0].found);
  EXPECT_NEAR(report.references[0].relative_error(), 0.0, 1e-12);
  EXPECT_EQ(report.references[1].relative_error(), 0.0);
  EXPECT_DOUBLE_EQ(report.references[2].relative_error(), 0.25);
  EXPECT_FALSE(report.references[3].found);
  EXPECT_NEAR(report.references[4].relative_error(), 0.0, 1e-9);
  const std::string page = slurp(report.html);
  EXPECT_NE(page.find("+0.00%"), std::string::npos);
  EXPECT_NE(page.find("class=\"bad\">+25.00%"), std::string::npos);
  EXPECT_NE(page.find("not in this run"), std::string::npos);
  // The comparison for scripts: one row per reference value, empty where the run lacks it.
  const std::string csv = slurp(out / "again" / "reference.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "quantity,reference,value,unit,relative_error,source");
  EXPECT_NE(csv.find("counts.elements,2000,2500,,0.25,\"a wrong value\""), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("results.plug.mass,0.1,,kg,,\"no plug in a bar\""), std::string::npos) << csv;
}

TEST(Report, MissingRunIsAClearError) {
  const fs::path dir = scratch("missing");
  try {
    post::write_report({dir, {}, {}});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a finished run (no summary.json"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "report"));
}

// A run folder whose summary.json or history.csv is wrong in one way: one Error naming the file
// and the key or column (not the JSON library's own text), and no report folder. The same folder
// with good files gives a report, so each fault alone is the cause.
TEST(Report, BadRunFilesAreOneLineErrors) {
  const fs::path dir = scratch("bad_files");
  const std::string good_summary =
      R"({"case": "bar", "counts": {"elements": 1}, "energy": {"balance_error": 0},
          "bodies": {"bar": {"mass": 1, "com_velocity": [0, 0, -1]}}})";
  const std::string good_history =
      "time,body.bar.vx,body.bar.vy,body.bar.vz\n0,0,0,-1\n1e-6,0,0,-1\n";
  const auto folder = [&](const std::string& name, const std::string& summary,
                          const std::string& history) {
    const fs::path run = dir / name;
    fs::create_directories(run);
    std::ofstream(run / "summary.json") << summary;
    if (!history.empty())
      std::ofstream(run / "history.csv") << history;
    return run;
  };
  const auto message = [](const fs::path& run, const fs::path& reference = {}) -> std::string {
    try {
      post::write_report({run, reference, {}});
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  // A reference quantity with an index beyond any array is not in this run (it was an uncaught
  // out_of_range).
  std::ofstream(dir / "reference.csv")
      << "quantity,value,unit,source\nbodies.bar.com_velocity.2,-1,m/s,\n"
         "bodies.bar.com_velocity.99999999999999999999999,0,m/s,\n";
  const fs::path good = folder("good", good_summary, good_history);
  const post::Report report = post::write_report({good, dir / "reference.csv", {}});
  EXPECT_TRUE(fs::is_regular_file(report.html));
  ASSERT_EQ(report.references.size(), 2u);
  EXPECT_TRUE(report.references[0].found);
  EXPECT_FALSE(report.references[1].found);

  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good_summary;
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
  };
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {folder("not_json", "{\"case\": ", good_history), "summary.json: not valid JSON: "},
      {folder("list", "[1, 2]", good_history),
       "summary.json: (top level): expected an object (the run's summary), got array"},
      {folder("no_counts", with(R"("counts": {"elements": 1}, )", ""), good_history),
       "summary.json: counts: expected an object, got nothing (missing key)"},
      {folder("text_count", with(R"({"elements": 1})", R"({"elements": "one"})"), good_history),
       "summary.json: counts.elements: expected a number, got string"},
      {folder("energy_list", with(R"({"balance_error": 0})", "[0]"), good_history),
       "summary.json: energy: expected an object, got array"},
      {folder("case_number", with(R"("case": "bar")", R"("case": 3)"), good_history),
       "summary.json: case: expected a string, got number"},
      {folder("short_velocity", with("[0, 0, -1]", "[0, -1]"), good_history),
       "summary.json: bodies.bar.com_velocity: expected 3 numbers [vx, vy, vz], got array"},
      {folder("no_velocity", with(R"(, "com_velocity": [0, 0, -1])", ""), good_history),
       "summary.json: bodies.bar.com_velocity: expected 3 numbers [vx, vy, vz], got nothing "
       "(missing key)"},
      {folder("text_mass", with(R"("mass": 1)", R"("mass": "1 kg")"), good_history),
       "summary.json: bodies.bar.mass: expected a number, got string"},
      {folder("bad_plane",
              with(R"("case": "bar")", R"("case": "bar", "section_plane": {"point": [0, 0, 0],
                   "normal": [0, 1, 0], "u_range": [1]})"),
              good_history),
       "summary.json: section_plane.u_range: expected 2 numbers [u0, u1], got array"},
      {folder("no_history", good_summary, ""), "history.csv: cannot open"},
      {folder("untimed", good_summary, "t,body.bar.vx,body.bar.vy,body.bar.vz\n0,0,0,0\n"),
       "history.csv:1: no time column"},
      {folder("no_vy", good_summary, "time,body.bar.vx,body.bar.vz\n0,0,0\n"),
       "history.csv:1: no column body.bar.vy ("},
  };
  for (const auto& [run, expected] : cases) {
    const std::string what = message(run);
    EXPECT_NE(what.find(expected), std::string::npos) << run << "\n" << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_FALSE(fs::exists(run / "report")) << run;
  }
}
