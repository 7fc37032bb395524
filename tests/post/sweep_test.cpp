// Tests of `sphfem sweep` (app/sweep_command.hpp, post/sweep.hpp, post/recht_ipson.hpp): the
// Recht–Ipson fit on exact, noisy and experimental data; the bisection of the ballistic limit;
// run results read back, unknown ones included; the reference reader; and the command on two
// short runs of the punch scene.
#include "post/recht_ipson.hpp"
#include "post/sweep.hpp"
#include "tests/support/command.hpp"
#include "tests/support/punch_case.hpp"

#include "solver/core/error.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <functional>

namespace fs = std::filesystem;
using namespace sphfem;
using post::BallisticPoint;

namespace {

// Børvik et al.'s experiments on 12 mm Weldox 460 E plates, as printed in Table 3 of Zhang,
// Qiang & Gao, Eng. Struct. 33 (2011) 255–264 (../shared/data/borvik_12mm_table3.csv, columns
// v0 and exp_vpr): impact and residual projectile velocity, m/s.
const std::vector<BallisticPoint> experiment{
    {181.5, 0, false},    {189.6, 42, true},    {200.4, 71, true},   {224.7, 113.7, true},
    {244.2, 132.6, true}, {285.4, 181.1, true}, {303.5, 199.7, true}};

// The published fit to them: vbl = 184.5 m/s, p = 2.24, a = 0.783.
post::RechtIpson published() {
  post::RechtIpson r;
  r.a = 0.783;
  r.p = 2.24;
  r.vbl = 184.5;
  return r;
}

std::vector<BallisticPoint> synthetic(const std::function<double(std::size_t)>& noise) {
  std::vector<BallisticPoint> points;
  for (std::size_t k = 0; k < experiment.size(); ++k) {
    const double v0 = experiment[k].v0;
    points.push_back({v0, published()(v0) + (experiment[k].perforated ? noise(k) : 0.0),
                      experiment[k].perforated});
  }
  return points;
}

} // namespace

TEST(RechtIpson, CurveIsZeroBelowTheLimit) {
  // Exactly zero at and below vbl: no tolerance.
  EXPECT_NEAR(published()(184.5), 0.0, 0.0);
  EXPECT_NEAR(published()(100.0), 0.0, 0.0);
  // 0.783 (303.5^2.24 − 184.5^2.24)^(1/2.24) = 199.008 m/s (computed apart, to 4 digits).
  EXPECT_NEAR(published()(303.5), 199.008, 1e-3);
}

TEST(RechtIpson, RecoversExactParameters) {
  const auto fit = post::fit_recht_ipson(synthetic([](std::size_t) { return 0.0; }));
  ASSERT_TRUE(fit);
  EXPECT_EQ(fit->points, 6);
  // Exact data: only the solver's convergence limits the recovery.
  EXPECT_NEAR(fit->a, 0.783, 1e-3 * 0.783);
  EXPECT_NEAR(fit->p, 2.24, 1e-3 * 2.24);
  EXPECT_NEAR(fit->vbl, 184.5, 1e-3 * 184.5);
  EXPECT_LT(fit->rms, 1e-6);
  EXPECT_NEAR(fit->vbl_min, 181.5, 1e-12);
  EXPECT_NEAR(fit->vbl_max, 189.6, 1e-12);
}

TEST(RechtIpson, NoisyDataKeepTheLimit) {
  // ±2 m/s, alternating in sign, deterministic.
  const auto fit =
      post::fit_recht_ipson(synthetic([](std::size_t k) { return k % 2 ? 2.0 : -2.0; }));
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->vbl, 184.5, 3.0);
  EXPECT_LE(fit->rms, 2.0 + 1e-9); // the true curve's rms is 2 m/s: the fit can only do better
  EXPECT_GT(fit->a, 0);
  EXPECT_LE(fit->a, 1.5);
  EXPECT_GE(fit->p, 1);
  EXPECT_LE(fit->p, 4);
}

TEST(RechtIpson, FitsTheExperiment) {
  const auto fit = post::fit_recht_ipson(experiment);
  ASSERT_TRUE(fit);
  std::cout << "experiment: vbl " << fit->vbl << " m/s, p " << fit->p << ", a " << fit->a
            << ", rms " << fit->rms << " m/s\n";
  // Published: vbl 184.5 m/s, rms 1.8 m/s (borvik_weldox460e.md).
  EXPECT_NEAR(fit->vbl, 184.5, 1.0);
  EXPECT_LE(fit->rms, 2.5);
}

TEST(RechtIpson, NeedsThreePerforatingPoints) {
  EXPECT_FALSE(post::fit_recht_ipson({{181.5, 0, false}, {200, 70, true}, {300, 200, true}}));
}

TEST(Bisection, BracketsTheLimitInTheExpectedSteps) {
  const double limit = 187.3;
  std::vector<BallisticPoint> points;
  for (const double v0 : {181.5, 189.6, 200.4, 224.7, 244.2, 285.4, 303.5})
    points.push_back({v0, 0, v0 > limit});
  int steps = 0;
  while (const auto v = post::next_bisection(points, 1.0)) {
    points.push_back({*v, 0, *v > limit});
    ++steps;
  }
  // 8.1 m/s halved to ≤ 1 m/s: ceil(log2(8.1)) = 4 runs.
  EXPECT_EQ(steps, 4);
  double below = 0, above = 1e9;
  for (const auto& p : points)
    (p.perforated ? above : below) = p.perforated ? std::min(above, p.v0) : std::max(below, p.v0);
  EXPECT_LE(above - below, 1.0);
  EXPECT_LT(below, limit);
  EXPECT_GT(above, limit);
}

TEST(Bisection, NeedsABracket) {
  EXPECT_FALSE(post::next_bisection({{200, 70, true}, {300, 200, true}}, 1.0));
  EXPECT_FALSE(post::next_bisection({{100, 0, false}}, 1.0));
  EXPECT_FALSE(post::next_bisection({{100, 0, false}, {100.5, 5, true}}, 1.0));
  // A non-perforating point above the lowest perforating one does not bound the bracket.
  EXPECT_NEAR(*post::next_bisection({{100, 0, false}, {110, 5, true}, {120, 0, false}}, 1.0), 105.0,
              1e-12);
}

TEST(SweepRun, MissingResultsAreUnknown) {
  test::Scratch s("sweep_unknown");
  post::SweepRun none;
  none.folder = s.dir / "none";
  post::read_run_results(none);
  EXPECT_FALSE(none.known());
  EXPECT_NE(none.note.find("summary.json"), std::string::npos);

  post::SweepRun old;
  old.folder = s.dir / "old";
  fs::create_directories(old.folder);
  std::ofstream(old.folder / "summary.json") << R"({"case": "x", "steps": 3})";
  post::read_run_results(old);
  EXPECT_FALSE(old.known());
  EXPECT_NE(old.note.find("results.perforated"), std::string::npos);

  post::SweepRun done;
  done.folder = s.dir / "done";
  fs::create_directories(done.folder);
  std::ofstream(done.folder / "summary.json")
      << R"({"results": {"perforated": true, "residual_velocity": {"projectile": 71.5,
            "plug": 104.0}, "plug": {"mass": 0.029}}})";
  post::read_run_results(done);
  ASSERT_TRUE(done.known());
  EXPECT_TRUE(*done.perforated);
  EXPECT_NEAR(*done.residual_projectile, 71.5, 1e-12);
  EXPECT_NEAR(*done.residual_plug, 104.0, 1e-12);
  EXPECT_NEAR(*done.plug_mass, 0.029, 1e-12);

  const auto points = post::ballistic_points({none, old, done});
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].vr, 71.5, 1e-12);
}

TEST(SweepReference, ReadsNamedColumnsAndReportsErrors) {
  test::Scratch s("sweep_reference");
  const fs::path table = s.dir / "table.csv";
  std::ofstream(table) << "# comment\ntest,v0,exp_vpr\n1,303.5,199.7\n5,210.0,\n9,181.5,0\n";
  const auto points = post::read_ballistic_reference(table, "v0", "exp_vpr");
  ASSERT_EQ(points.size(), 2u); // the row without exp_vpr is skipped
  EXPECT_NEAR(points[0].v0, 303.5, 1e-12);
  EXPECT_NEAR(points[0].vr, 199.7, 1e-12);

  EXPECT_THROW(post::read_ballistic_reference(s.dir / "missing.csv"), Error);
  EXPECT_THROW(post::read_ballistic_reference(table), Error); // no vr column
  std::ofstream(s.dir / "bad.csv") << "v0,vr\n200,fast\n";
  try {
    post::read_ballistic_reference(s.dir / "bad.csv");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:2"), std::string::npos) << e.what();
  }
}

TEST(SweepCommand, TwoShortRuns) {
  test::Scratch s("sweep_command");
  std::ofstream(s.dir / "case.yaml") << test::punch_case(0.009, 0.004, 0.008);
  std::ofstream(s.dir / "reference.csv") << "v0,vr,label\n300,0,slow\n800,500,fast\n";
  const fs::path out = s.dir / "sweep";
  const auto r = test::run_sphfem(
      "sweep " + (s.dir / "case.yaml").string() + " -o " + out.string() +
          " --key bodies.projectile.velocity --format '[0,0,-{}]' --values 300,800 -j 1" +
          " --set time.output_interval=5e-6 --reference " + (s.dir / "reference.csv").string(),
      s.dir);
  ASSERT_EQ(r.code, 0) << r.err;
  // One progress line per run.
  EXPECT_NE(r.err.find("bodies.projectile.velocity = [0,0,-300]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bodies.projectile.velocity = [0,0,-800]"), std::string::npos) << r.err;

  const std::string csv = test::slurp(out / "sweep.csv");
  std::istringstream lines(csv);
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(lines, line))
    rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u) << csv;
  EXPECT_EQ(rows[0], "v0_m_per_s,perforated,residual_projectile_m_per_s,residual_plug_m_per_s,"
                     "plug_mass_kg,wall_s,run_folder");
  EXPECT_EQ(rows[1].rfind("300,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("800,", 0), 0u) << rows[2];
  EXPECT_TRUE(fs::exists(out / "run_bodies.projectile.velocity_300" / "summary.json"));
  EXPECT_TRUE(fs::exists(out / "run_bodies.projectile.velocity_800" / "summary.json"));
  EXPECT_GT(fs::file_size(out / "ballistic_curve.png"), 1000u);
  const std::string html = test::slurp(out / "sweep.html");
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);

  const auto j = nlohmann::json::parse(test::slurp(out / "sweep.json"));
  ASSERT_EQ(j["runs"].size(), 2u);
  EXPECT_TRUE(j["fit"].is_null()); // two runs cannot fix three parameters
  ASSERT_EQ(j["reference"]["points"].size(), 2u);
  for (const auto& run : j["runs"]) {
    // Results written by `run` are read; without them the run is unknown, with a note.
    if (run["perforated"] == "unknown")
      EXPECT_TRUE(run.contains("note"));
    else
      EXPECT_TRUE(run["perforated"].is_boolean());
    EXPECT_GT(run["wall_s"].get<double>(), 0);
  }
  // Errors against the reference exist for the runs whose outcome is known.
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_EQ(j["reference"]["points"][k]["error_run_m_per_s"].is_null(),
              j["runs"][k]["perforated"] == "unknown");
}

TEST(SweepCommand, BadInputIsOneLineError) {
  test::Scratch s("sweep_bad");
  std::ofstream(s.dir / "case.yaml") << test::punch_case(0.009, 0.004, 0.008);
  const std::string base =
      "sweep " + (s.dir / "case.yaml").string() + " -o " + (s.dir / "out").string() + " ";
  for (const std::string& args :
       {base + "--key bodies.projectile.speed --values 300", base + "--values 300,fast",
        base + "--values ''", base + "--key bodies.projectile.velocity --values 300",
        base + "--param bodies.projectile.speed=1:3:1", base + "--param time.end=3:1:1",
        base + "--param time.end=1:3", base + "--param time.end=1:3:1 --values 1",
        base + "--key time.end --values 1e-6 --reference " + (s.dir / "none.csv").string()}) {
    const auto r = test::run_sphfem(args, s.dir);
    EXPECT_NE(r.code, 0) << args;
    EXPECT_EQ(r.err.rfind("sphfem: error: ", 0), 0u) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(s.dir / "out"));
}
