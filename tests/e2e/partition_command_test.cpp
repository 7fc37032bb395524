// `sphfem partition` (app/partition_command.hpp) as a user runs it on the paper's glued bar
// (hexahedra + particles + background particles): every entity in exactly one rank, the costs
// balanced, the files written for ParaView, the same answer on repeat, bad input refused.
#include "tests/support/command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <regex>
#include <string>

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
