// End-to-end tests of the `sphfem` command: the bar case runs and writes every file DESIGN.md
// fixes (frames re-read with VTK's own reader); bad input fails with one clear line and
// writes nothing; solve re-uses a fresh model.h5 and re-meshes a stale one.
#include "post/post.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

struct Result {
  int code;
  std::string out, err;
};

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sphfem_e2e_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Result run_sphfem(const std::string& args, const fs::path& dir) {
  const std::string cmd = std::string(SPHFEM_BINARY) + " " + args + " >" +
                          (dir / "stdout.txt").string() + " 2>" + (dir / "stderr.txt").string();
  const int status = std::system(cmd.c_str());
  return {WEXITSTATUS(status), slurp(dir / "stdout.txt"), slurp(dir / "stderr.txt")};
}

const std::string bar_case = std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_pressed_fe/case.yaml";
const std::string sph_bar_case =
    std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_pressed_sph/case.yaml";

// The wave front at a probe: the first time |vz| reaches 5% of its peak (interpolated), and
// that peak.
struct Front {
  double arrival = 0, peak = 0;
};
Front front(const sphfem::post::History& history, const std::string& probe) {
  const auto& t = history["time"];
  const auto& vz = history[probe + ".vz"];
  Front f;
  f.peak = -*std::min_element(vz.begin(), vz.end());
  for (std::size_t i = 1; i < vz.size() && f.arrival == 0; ++i)
    if (-vz[i] >= 0.05 * f.peak)
      f.arrival = t[i - 1] + (0.05 * f.peak + vz[i - 1]) / (vz[i - 1] - vz[i]) * (t[i] - t[i - 1]);
  return f;
}

} // namespace

TEST(Run, BarCaseWritesEveryOutput) {
  const fs::path dir = scratch("bar");
  const fs::path out = dir / "OUT";
  const auto r = run_sphfem("run " + bar_case + " -o " + out.string() + " -q", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"model.h5", "model.vtu", "results.pvd", "history.csv", "history.h5",
                        "summary.json", "run.log"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_NE(r.out.find("results.pvd"), std::string::npos); // tells where the ParaView file is

  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  for (const char* key : {"case", "steps", "time", "wall_s", "entity_steps_per_s", "threads",
                          "counts", "energy", "momentum_drift", "bodies", "peak_resident_MB"})
    EXPECT_TRUE(summary.contains(key)) << key;
  // The process held at least the 2 500 elements' state (≈ 0.6 kB each), and less than the
  // machine has.
  EXPECT_GT(summary["peak_resident_MB"].get<double>(), 1.5);
  EXPECT_LT(summary["peak_resident_MB"].get<double>(), 24 * 1024.0);
  EXPECT_EQ(summary["counts"]["elements"].get<int>(), 2500);
  EXPECT_NEAR(summary["time"].get<double>(), 1.4e-5, 1e-15);
  EXPECT_LT(summary["energy"]["balance_error"].get<double>(), 0.01);
  EXPECT_TRUE(summary["bodies"]["bar"].contains("com_velocity"));

  const auto history = sphfem::post::read_history_csv(out / "history.csv");
  for (const char* column :
       {"time", "dt", "quarter.vz", "mid.szz", "body.bar.vz", "energy.kinetic", "energy.internal",
        "energy.hourglass", "energy.external_work", "energy.total"})
    EXPECT_TRUE(history.values.count(column)) << column;
  EXPECT_NEAR(history["time"].back(), 1.4e-5, 1e-15);

  // Wave theory (acceptance of the bar case): the front reaches the mid probe, 50 mm from the
  // loaded end, at 50 mm / c_p after the load does, c_p = √((K + 4G/3)/ρ). Front = first time
  // |vz| reaches 5% of its peak there; the load reaches 5% of its plateau at 0.05 × 0.25 µs.
  const double E = 207e9, nu = 0.3, rho = 7830;
  const double c_p = std::sqrt((E / (3 * (1 - 2 * nu)) + 4 * E / (2 * (1 + nu)) / 3) / rho);
  const double predicted = 0.05 * 0.25e-6 + 0.05 / c_p;
  EXPECT_NEAR(front(history, "mid").arrival, predicted, 0.03 * predicted);

  // Every frame listed in the collection is complete and readable by VTK with its arrays.
  const auto frames = sphfem::post::read_pvd(out / "results.pvd");
  ASSERT_GE(frames.size(), 2u);
  EXPECT_NEAR(frames.back().first, 1.4e-5, 1e-15);
  EXPECT_EQ(frames.size(), 29u); // t = 0 and every 0.5 µs
  for (const auto& [time, file] : frames) {
    auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    reader->SetFileName((out / file).c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_EQ(grid->GetNumberOfCells(), 2500) << file;
    EXPECT_NE(grid->GetPointData()->GetArray("velocity"), nullptr);
    EXPECT_NE(grid->GetPointData()->GetArray("displacement"), nullptr);
    EXPECT_NE(grid->GetCellData()->GetArray("stress"), nullptr);
    EXPECT_NE(grid->GetCellData()->GetArray("von_mises"), nullptr);
    EXPECT_NE(grid->GetCellData()->GetArray("pressure"), nullptr);
  }
}

TEST(Run, SphBarCaseWritesParticleFrames) {
  // The particle bar for 1 µs (the load pulse): every output exists, the particle frames are
  // readable by VTK with their arrays, the balances hold.
  const fs::path dir = scratch("sph_bar");
  const fs::path out = dir / "OUT";
  const auto r =
      run_sphfem("run " + sph_bar_case + " -o " + out.string() + " -q --set time.end=1e-6", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "model_particles.vtu"));
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(summary["counts"]["particles"].get<int>(), 6 * 6 * 101);
  EXPECT_EQ(summary["counts"]["elements"].get<int>(), 0);
  EXPECT_LT(summary["energy"]["balance_error"].get<double>(), 0.02);
  EXPECT_LT(summary["momentum_drift"].get<double>(), 1e-12);
  EXPECT_TRUE(summary["probes"]["mid"].contains("particle"));
  const auto frames = sphfem::post::read_pvd(out / "results.pvd");
  ASSERT_EQ(frames.size(), 3u); // t = 0, 0.5, 1 µs; particles only
  for (const auto& [time, file] : frames) {
    EXPECT_NE(file.find("sph_"), std::string::npos);
    auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    reader->SetFileName((out / file).c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_EQ(grid->GetNumberOfPoints(), 3636) << file;
    for (const char* array : {"velocity", "displacement", "stress", "von_mises", "pressure",
                              "density", "h", "neighbours", "body_id", "id"})
      EXPECT_NE(grid->GetPointData()->GetArray(array), nullptr) << array;
  }
}

TEST(Run, SphBarMatchesFeBar) {
  // Issue 3's acceptance: the particle bar's wave reaches the middle probe within 3% of the
  // time the FE bar's does, with a peak |vz| within 10% (measured: +0.04% and −4.6%, see
  // cases/bar_pressed_sph/README.md), and its energy balance closes within 2%.
  const fs::path dir = scratch("sph_vs_fe");
  const std::string quiet = " -q --set output.frames=false";
  const auto fe = run_sphfem("run " + bar_case + " -o " + (dir / "FE").string() + quiet, dir);
  ASSERT_EQ(fe.code, 0) << fe.err;
  const auto sph = run_sphfem("run " + sph_bar_case + " -o " + (dir / "SPH").string() + quiet, dir);
  ASSERT_EQ(sph.code, 0) << sph.err;
  const Front f = front(sphfem::post::read_history_csv(dir / "FE" / "history.csv"), "mid");
  const Front s = front(sphfem::post::read_history_csv(dir / "SPH" / "history.csv"), "mid");
  EXPECT_NEAR(s.arrival, f.arrival, 0.03 * f.arrival);
  EXPECT_NEAR(s.peak, f.peak, 0.10 * f.peak);
  const auto summary = nlohmann::json::parse(slurp(dir / "SPH" / "summary.json"));
  EXPECT_LT(summary["energy"]["balance_error"].get<double>(), 0.02);
}

TEST(Run, SolveReusesFreshModelAndRemeshesStaleOne) {
  const fs::path dir = scratch("stale");
  const fs::path out = dir / "OUT";
  ASSERT_EQ(run_sphfem("mesh " + bar_case + " -o " + out.string() + " -q", dir).code, 0);
  const auto made = fs::last_write_time(out / "model.h5");
  auto r = run_sphfem("solve " + bar_case + " -o " + out.string() + " --set time.end=2e-7", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(fs::last_write_time(out / "model.h5"), made);
  r = run_sphfem("solve " + bar_case + " -o " + out.string() +
                     " --set time.end=2e-7 --set bodies.bar.element_size=0.0025",
                 dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("stale"), std::string::npos);
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(summary["counts"]["elements"].get<int>(), 2 * 2 * 40);
}

namespace {

struct BadInput {
  const char* name;
  const char* from; // text of the valid case to replace
  const char* to;
  const char* expect; // in the one-line message
};

// One per bad-input class; the message must name the file, the line and the key.
const BadInput bad_inputs[] = {
    {"unknown_key", "  end: 1.4e-5", "  end: 1.4e-5\n  colour: red", "time.colour"},
    {"wrong_type", "density: 7830", "density: heavy", "materials.steel.density"},
    {"missing_key", "    youngs_modulus: 207.0e9  # Pa\n", "", "youngs_modulus"},
    {"density", "density: 7830", "density: -7830", "materials.steel.density"},
    {"youngs", "youngs_modulus: 207.0e9", "youngs_modulus: 0", "materials.steel.youngs_modulus"},
    {"poisson", "poisson_ratio: 0.3", "poisson_ratio: 0.5", "materials.steel.poisson_ratio"},
    {"negative_time", "end: 1.4e-5", "end: -1.4e-5", "time.end"},
    {"energy_limit", "  end: 1.4e-5", "  end: 1.4e-5\n  energy_limit: 0", "time.energy_limit"},
    {"empty_geometry", "max: [0.005, 0.005, 0.1]", "max: [0.005, 0.0, 0.1]", "bodies.bar.geometry"},
};

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "fixture text not found: " << from;
  return text.replace(at, from.size(), to);
}

} // namespace

TEST(Run, BadInputFailsWithOneLineAndWritesNothing) {
  const std::string valid = slurp(bar_case);
  for (const auto& bad : bad_inputs) {
    const fs::path dir = scratch(std::string("bad_") + bad.name);
    const fs::path file = dir / "case.yaml";
    std::ofstream(file) << replaced(valid, bad.from, bad.to);
    for (const char* command : {"run", "mesh", "solve"}) {
      const auto r = run_sphfem(
          std::string(command) + " " + file.string() + " -o " + (dir / "OUT").string(), dir);
      EXPECT_NE(r.code, 0) << bad.name;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad.name << ": " << r.err;
      EXPECT_NE(r.err.find(file.string() + ":"), std::string::npos) << bad.name << ": " << r.err;
      EXPECT_NE(r.err.find(bad.expect), std::string::npos) << bad.name << ": " << r.err;
      EXPECT_FALSE(fs::exists(dir / "OUT")) << bad.name << ": something was written";
    }
  }
}

TEST(Run, BadOverrideAndMissingFileFailCleanly) {
  const fs::path dir = scratch("bad_cli");
  auto r = run_sphfem("run " + bar_case + " -o " + (dir / "OUT").string() + " --set time.end", dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--set"), std::string::npos) << r.err;
  r = run_sphfem("run " + (dir / "missing.yaml").string() + " -o " + (dir / "OUT").string(), dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("missing.yaml"), std::string::npos) << r.err;
  // An imbalance is a multiple ≥ 1 of the mean: 0.5 would rebalance at every check.
  r = run_sphfem("run " + bar_case + " -o " + (dir / "OUT").string() + " --rebalance 0.5", dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--rebalance: expected 0 (never) or a multiple"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "OUT"));
}

TEST(Run, EveryCommandHasHelp) {
  const fs::path dir = scratch("help");
  for (const char* command : {"", "mesh ", "solve ", "run "}) {
    const auto r = run_sphfem(std::string(command) + "--help", dir);
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << command;
  }
}
