// `sphfem partition` (app/partition_command.hpp) as a user runs it on the paper's glued bar
// (hexahedra + particles + background particles): every entity in exactly one rank, the costs
// balanced, the files written for ParaView, the same answer on repeat, bad input refused; and
// a run's work frame by frame, with the yielding particles of a punched plate costing their
// return.
#include "solver/time/cost_estimate.hpp"
#include "tests/support/command.hpp"
#include "tests/support/punch_case.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using sphfem::test::slurp;

namespace {

const std::string case_file = std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_pressed/case.yaml";

} // namespace

TEST(PartitionCommand, ShareTheGluedBarAmongThreeRanks) {
  const sphfem::test::Scratch scratch("partition_command");
  const std::string out = (scratch.dir / "out").string();
  const auto mesh = sphfem::test::run_sphfem("mesh " + case_file + " -o " + out, scratch.dir);
  ASSERT_EQ(mesh.code, 0) << mesh.err;
  std::smatch counts; // "mesh: N nodes, E hexahedra, P particles"
  ASSERT_TRUE(std::regex_search(mesh.err, counts,
                                std::regex(R"((\d+) nodes, (\d+) hexahedra, (\d+) particles)")));

  const auto first =
      sphfem::test::run_sphfem("partition " + case_file + " -o " + out + " -n 3", scratch.dir);
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_NE(first.err.find("imbalance"), std::string::npos) << first.err;
  const auto json = nlohmann::json::parse(slurp(scratch.dir / "out" / "partition.json"));
  ASSERT_EQ(json["ranks"], 3);
  ASSERT_EQ(json["parts"].size(), 3u);
  long long nodes = 0, elements = 0, particles = 0, ghosts = 0;
  for (const auto& p : json["parts"]) {
    nodes += p["nodes"].get<long long>();
    elements += p["elements"].get<long long>();
    particles += p["particles"].get<long long>();
    ghosts += p["ghost_points"].get<long long>();
    EXPECT_GT(p["cost_s_per_step"].get<double>(), 0);
  }
  EXPECT_EQ(nodes, std::stoll(counts[1]));
  EXPECT_EQ(elements, std::stoll(counts[2]));
  EXPECT_EQ(particles, std::stoll(counts[3]));
  EXPECT_GT(ghosts, 0); // the cuts cross the particles
  EXPECT_LT(json["imbalance"].get<double>(), 1.05);
  EXPECT_GT(json["skin_m"].get<double>(), 0);
  for (const char* file : {"partition.vtu", "partition_particles.vtu"})
    EXPECT_NE(slurp(scratch.dir / "out" / file).find("Name=\"rank\""), std::string::npos) << file;

  const std::string before = slurp(scratch.dir / "out" / "partition.json");
  const auto again =
      sphfem::test::run_sphfem("partition " + case_file + " -o " + out + " -n 3 -q", scratch.dir);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(again.err.empty()) << again.err;
  EXPECT_EQ(slurp(scratch.dir / "out" / "partition.json"), before);
}

TEST(PartitionCommand, ARunsWorkFrameByFrame) {
  // A short run of the glued bar: elastic, nothing killed, so each rank's cost per step stays
  // what the decomposition counted at t = 0 — two neighbour counts of independent code (the
  // solver's kinematics loop, the decomposition's search) that must agree. By region, entities
  // change rank as they cross a cut: the pressed bar shortens by a fraction of Δp, and the
  // particles' cut, placed among particles and background particles, can pass that close to a
  // layer of them; so by region the work is only moved, never made or lost.
  const sphfem::test::Scratch scratch("partition_command_run");
  const std::string run = (scratch.dir / "run").string(), out = (scratch.dir / "out").string();
  const auto solved = sphfem::test::run_sphfem(
      "run " + case_file + " -o " + run + " -q --set time.end=2e-6", scratch.dir);
  ASSERT_EQ(solved.code, 0) << solved.err;
  const auto part = sphfem::test::run_sphfem(
      "partition " + case_file + " -o " + out + " -n 3 --run " + run, scratch.dir);
  ASSERT_EQ(part.code, 0) << part.err;
  const auto json = nlohmann::json::parse(slurp(scratch.dir / "out" / "partition.json"));
  ASSERT_TRUE(json.contains("run"));
  const std::string csv = slurp(scratch.dir / "out" / "partition_run.csv");
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "time_s,imbalance,region_imbalance,cost_s_rank0,cost_s_rank1,cost_s_rank2,"
                  "region_cost_s_rank0,region_cost_s_rank1,region_cost_s_rank2");
  int frames = 0;
  double region_imbalance_max = 0;
  while (std::getline(lines, line)) {
    std::istringstream row(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(row, cell, ','))
      v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 9u) << line;
    double kept = 0, by_region = 0, total = 0, region_largest = 0;
    for (int q = 0; q < 3; ++q) {
      const double census = json["parts"][q]["cost_s_per_step"].get<double>();
      EXPECT_NEAR(v[3 + q], census, 1e-3 * census) << "frame " << frames << ", rank " << q;
      if (frames == 0) { // nothing has moved yet
        EXPECT_NEAR(v[6 + q], census, 1e-3 * census) << "rank " << q;
      }
      kept += v[3 + q];
      by_region += v[6 + q];
      total += census;
      region_largest = std::max(region_largest, v[6 + q]);
    }
    EXPECT_NEAR(by_region, kept, 1e-12 * total) << "frame " << frames;
    EXPECT_NEAR(v[2], 3 * region_largest / by_region, 1e-7) << "frame " << frames; // CSV digits
    region_imbalance_max = std::max(region_imbalance_max, v[2]);
    ++frames;
  }
  EXPECT_EQ(frames, json["run"]["frames"].get<int>());
  // The run's imbalance is of each rank's summed cost (both phases), the census's per rank.
  double largest = 0, total = 0;
  for (int q = 0; q < 3; ++q) {
    const double cost = json["parts"][q]["cost_s_per_step"].get<double>();
    largest = std::max(largest, cost);
    total += cost;
  }
  EXPECT_NEAR(json["run"]["entities_kept"]["imbalance_max"]["value"].get<double>(),
              3 * largest / total, 1e-3);
  EXPECT_NEAR(json["run"]["by_region"]["imbalance_max"]["value"].get<double>(),
              region_imbalance_max, 1e-6);
  EXPECT_GE(frames, 2);
  EXPECT_TRUE(fs::exists(scratch.dir / "out" / "partition_run.png"));

  // Another case's run is refused, naming it.
  const std::string other = std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_impact/case.yaml";
  const auto wrong = sphfem::test::run_sphfem(
      "partition " + other + " -o " + (scratch.dir / "other").string() + " -n 2 --run " + run,
      scratch.dir);
  EXPECT_EQ(wrong.code, 1);
  EXPECT_NE(wrong.err.find("not of this case"), std::string::npos) << wrong.err;
}

namespace {

// Σ over a particle frame's live particles of what their current state adds to a particle's
// cost per step: StepCost::entry per neighbour and StepCost::yielding_point when it yields.
double particles_current_cost(const fs::path& frame) {
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(frame.c_str());
  reader->Update();
  vtkPointData* pd = reader->GetOutput()->GetPointData();
  vtkDataArray *n = pd->GetArray("neighbours"), *killed = pd->GetArray("killed"),
               *yielding = pd->GetArray("yielding");
  EXPECT_TRUE(n && killed && yielding) << frame;
  double cost = 0;
  for (vtkIdType k = 0; n && killed && yielding && k < pd->GetNumberOfTuples(); ++k)
    if (killed->GetComponent(k, 0) == 0)
      cost += sphfem::StepCost::particle + sphfem::StepCost::entry * n->GetComponent(k, 0) +
              sphfem::StepCost::yielding_point * yielding->GetComponent(k, 0);
  return cost;
}

} // namespace

TEST(PartitionCommand, YieldingParticlesCostTheirReturnInARunsWork) {
  // The punch (tests/support/punch_case.hpp): a Weldox 460 E plate of particles struck at
  // 800 m/s; at 5 µs most of it yields. The elements (elastic) and the background particles
  // cost what they did at t = 0, so the ranks' total cost changes from the first frame to the
  // second by what the particles' frames say: their neighbour counts and yielding flags.
  const sphfem::test::Scratch scratch("partition_command_yielding");
  const fs::path punch = scratch.dir / "punch.yaml";
  std::ofstream(punch) << sphfem::test::punch_case(0.012, 0.005, 0.012);
  const std::string run = (scratch.dir / "run").string(), out = (scratch.dir / "out").string();
  const auto solved = sphfem::test::run_sphfem(
      "run " + punch.string() + " -o " + run + " -q --set time.end=5e-6", scratch.dir);
  ASSERT_EQ(solved.code, 0) << solved.err;
  const auto part = sphfem::test::run_sphfem(
      "partition " + punch.string() + " -o " + out + " -n 2 --run " + run, scratch.dir);
  ASSERT_EQ(part.code, 0) << part.err;
  std::istringstream lines(slurp(scratch.dir / "out" / "partition_run.csv"));
  std::string line;
  std::getline(lines, line);
  std::vector<double> total;
  while (std::getline(lines, line)) {
    std::istringstream row(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(row, cell, ','))
      v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 7u) << line;
    total.push_back(v[3] + v[4]);
  }
  ASSERT_EQ(total.size(), 2u);
  const fs::path frames = scratch.dir / "run" / "frames";
  const double first = particles_current_cost(frames / "sph_000000.vtu"),
               second = particles_current_cost(frames / "sph_000001.vtu");
  EXPECT_NEAR(total[1] - total[0], second - first, 1e-8 * total[0]);
  // Most of the plate yields: the flags are more than the neighbour counts' change.
  EXPECT_GT(second - first, 0.1 * total[0]);
}

TEST(PartitionCommand, BadInputIsRefused) {
  const sphfem::test::Scratch scratch("partition_command_bad");
  const std::string out = (scratch.dir / "out").string();
  const auto zero =
      sphfem::test::run_sphfem("partition " + case_file + " -o " + out + " -n 0", scratch.dir);
  EXPECT_NE(zero.code, 0);
  EXPECT_NE(zero.err.find("--ranks"), std::string::npos) << zero.err;
  EXPECT_FALSE(fs::exists(scratch.dir / "out"));
  const auto missing = sphfem::test::run_sphfem(
      "partition " + (scratch.dir / "no_such.yaml").string() + " -o " + out + " -n 2", scratch.dir);
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("no_such.yaml"), std::string::npos) << missing.err;
}
