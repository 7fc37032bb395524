// Runs started by an MPI launcher (issue 28). One rank is the plain run, file for file. On 2 and
// 3 ranks each rank steps its share of the hexahedra and particles (solver/parallel/
// subdomain.hpp, particle_share.hpp) and the run writes what the single process writes, bit for
// bit: the paper's bar under a pressure pulse in hexahedra, in particles and half and half
// (attachment: background particles and ties), its bars struck end on end (kernel contact of
// particles against hexahedra), a Johnson–Cook bar pulled until its elements erode, a quarter
// block of particles crushed on a fixed face across two symmetry planes until most of its
// particles are killed, and that block's checkpoint written on 2 ranks continued on 3. What a
// distributed run cannot step yet (the surface contact) is refused before anything is written,
// as are the commands that do not share their work.
// mpirun runs as root in CI, hence --allow-run-as-root; --oversubscribe lets three ranks start
// on two cores.
#include "tests/support/command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using sphfem::test::slurp;

namespace {

const std::string source = std::string(SPHFEM_SOURCE_DIR) + "/cases/";
const std::string quiet = " -q --set output.frames=false";

std::string launcher(int ranks) {
  return std::string(SPHFEM_MPIEXEC) + " --allow-run-as-root --oversubscribe -np " +
         std::to_string(ranks) + " ";
}

// `sphfem ARGS` on `ranks` ranks (0: without mpirun); stdout and stderr kept in dir.
sphfem::test::Result sphfem_on(int ranks, const std::string& args, const fs::path& dir) {
  return sphfem::test::run_shell(
      (ranks > 0 ? launcher(ranks) : std::string()) + SPHFEM_BINARY + " " + args, dir);
}

// A Johnson–Cook bar with damage and erosion, fixed at one end and pulled at the other: its
// elements yield, fail and are removed (tests/fem/erosion_test.cpp).
const char* eroding_bar = R"(
name: eroding_bar
time: {end: 4.0e-5, cfl: 0.6, output_interval: 1.0e-5, history_interval: 1.0e-6}
materials:
  soft:
    model: johnson_cook
    density: 7850
    youngs_modulus: 200.0e9
    poisson_ratio: 0.3
    johnson_cook: {A: 2.0e8, B: 2.0e8, n: 0.5, C: 0, rate_form: power, reference_strain_rate: 1}
    damage: {D1: 0.05, D2: 0, D3: 0, D4: 0, critical_damage: 1}
    erosion: true
bodies:
  bar:
    method: fem
    geometry: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.02]}}
    element_size: 0.001
    material: soft
boundary_conditions:
  - {type: fixed, body: bar, face: zmin}
  - {type: velocity, body: bar, face: zmax, velocity: [~, ~, 50.0]}
)";

// A quarter of a Johnson–Cook block of particles (symmetry planes x = 0 and y = 0: mirror
// images) driven at 400 m/s onto its fixed bottom face: it yields, its particles fail and are
// killed (in compression and in tension), the neighbour lists are rebuilt.
const char* crushed_quarter = R"(
name: crushed_quarter
time: {end: 1.5e-5, output_interval: 5.0e-6, history_interval: 5.0e-7}
materials:
  soft:
    model: johnson_cook
    density: 7850
    youngs_modulus: 200.0e9
    poisson_ratio: 0.3
    johnson_cook: {A: 2.0e8, B: 2.0e8, n: 0.5, C: 0, rate_form: power, reference_strain_rate: 1}
    damage: {D1: 0.3, D2: 0, D3: 0, D4: 0, critical_damage: 1}
bodies:
  block:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.008]}}
    spacing: 0.0005
    material: soft
    velocity: [0, 0, -400.0]
boundary_conditions:
  - {type: symmetry, body: block, face: xmin}
  - {type: symmetry, body: block, face: ymin}
  - {type: fixed, body: block, face: zmin}
)";

fs::path write_case(const fs::path& dir, const std::string& name, const char* text) {
  const fs::path file = dir / (name + ".yaml");
  std::ofstream(file) << text;
  return file;
}

// Runs `case_file` on one process and on 2 and 3 ranks; each writes the same history, bit for
// bit, and the same summary (but timing, the rank count and the round-off of the momentum
// drift). Returns the single run's summary.
nlohmann::json expect_ranks_repeat_one_process(const std::string& case_file,
                                               const std::string& name) {
  const sphfem::test::Scratch scratch(name);
  const auto plain = sphfem_on(
      0, "run " + case_file + " -o " + (scratch.dir / "one").string() + quiet, scratch.dir);
  EXPECT_EQ(plain.code, 0) << plain.err;
  const auto one = sphfem::test::summary_without_timing(scratch.dir / "one");
  for (int ranks : {2, 3}) {
    const fs::path out = scratch.dir / ("ranks" + std::to_string(ranks));
    const auto r =
        sphfem_on(ranks, "run " + case_file + " -o " + out.string() + quiet, scratch.dir);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(slurp(out / "run.log").find("distributed over " + std::to_string(ranks) + " MPI"),
              std::string::npos);
    EXPECT_TRUE(slurp(scratch.dir / "one" / "history.csv") == slurp(out / "history.csv"))
        << ranks << " ranks";
    auto summary = sphfem::test::summary_without_timing(out);
    EXPECT_EQ(summary["ranks"], ranks);
    EXPECT_GT(summary["halo_bytes_per_entity_step"].get<double>(), 0.0);
    summary.erase("ranks");
    summary.erase("halo_bytes_per_entity_step");
    summary.erase("case_file");
    auto reference = one;
    reference.erase("case_file");
    // The state is the same bit for bit; the momentum balance's accumulators (the symmetry
    // planes' and the supports' impulses) are sums over ranks in rank order, so their drift —
    // itself round-off — differs in its last digits.
    for (const auto* drift : {&summary, &reference})
      EXPECT_LT((*drift)["momentum_drift"].get<double>(), 1e-12);
    summary.erase("momentum_drift");
    reference.erase("momentum_drift");
    EXPECT_EQ(summary, reference) << ranks << " ranks";
  }
  return one;
}

} // namespace

TEST(MpiLaunch, OneRankWritesWhatAPlainRunWrites) {
  const sphfem::test::Scratch scratch("mpi_launch_one");
  const std::string case_file = source + "bar_impact/case.yaml";
  const std::string keys = " -q --set time.end=4e-5 --set output.frames=false";
  const auto plain = sphfem_on(
      0, "run " + case_file + " -o " + (scratch.dir / "plain").string() + keys, scratch.dir);
  ASSERT_EQ(plain.code, 0) << plain.err;
  const auto launched = sphfem_on(
      1, "run " + case_file + " -o " + (scratch.dir / "launched").string() + keys, scratch.dir);
  ASSERT_EQ(launched.code, 0) << launched.err;
  for (const char* file : {"history.csv", "history.h5"})
    EXPECT_TRUE(slurp(scratch.dir / "plain" / file) == slurp(scratch.dir / "launched" / file))
        << file;
  EXPECT_EQ(sphfem::test::summary_without_timing(scratch.dir / "plain"),
            sphfem::test::summary_without_timing(scratch.dir / "launched"));
}

TEST(MpiLaunch, ElasticBarOnTwoAndThreeRanksIsTheOneProcessRun) {
  expect_ranks_repeat_one_process(source + "bar_pressed_fe/case.yaml", "mpi_bar_pressed_fe");
}

TEST(MpiLaunch, ErodingBarOnTwoAndThreeRanksIsTheOneProcessRun) {
  const sphfem::test::Scratch scratch("mpi_eroding_bar_case");
  const fs::path case_file = write_case(scratch.dir, "eroding_bar", eroding_bar);
  const auto one = expect_ranks_repeat_one_process(case_file.string(), "mpi_eroding_bar");
  EXPECT_GT(one["bodies"]["bar"]["eroded_elements"].get<int>(), 0); // the test erodes
}

TEST(MpiLaunch, ElasticParticleBarOnTwoAndThreeRanksIsTheOneProcessRun) {
  expect_ranks_repeat_one_process(source + "bar_pressed_sph/case.yaml", "mpi_bar_pressed_sph");
}

TEST(MpiLaunch, AttachedBarOnTwoAndThreeRanksIsTheOneProcessRun) {
  expect_ranks_repeat_one_process(source + "bar_pressed/case.yaml", "mpi_bar_pressed");
}

TEST(MpiLaunch, BarsInKernelContactOnTwoAndThreeRanksAreTheOneProcessRun) {
  const auto one =
      expect_ranks_repeat_one_process(source + "bar_impact/case.yaml", "mpi_bar_impact");
  // The bars met at ±200 m/s and rebounded.
  EXPECT_LT(one["bodies"]["bar_a"]["com_velocity"][2].get<double>(), -150.0);
}

TEST(MpiLaunch, CrushedQuarterOfParticlesOnTwoAndThreeRanksIsTheOneProcessRun) {
  const sphfem::test::Scratch scratch("mpi_crushed_quarter_case");
  const fs::path case_file = write_case(scratch.dir, "crushed_quarter", crushed_quarter);
  const auto one = expect_ranks_repeat_one_process(case_file.string(), "mpi_crushed_quarter");
  EXPECT_GT(one["bodies"]["block"]["killed_particles"].get<int>(), 100); // the test kills
}

TEST(MpiLaunch, ACheckpointOfTwoRanksContinuesOnThree) {
  // The same checkpoint time of the crushed quarter reached on one process and on two ranks;
  // each continued (on one process, on three ranks) to the end writes the same history. The
  // checkpoint holds the particles in the order of its last neighbour list, which the three
  // ranks take over.
  const sphfem::test::Scratch scratch("mpi_restart");
  const std::string case_file =
      write_case(scratch.dir, "crushed_quarter", crushed_quarter).string();
  const std::string half = quiet + " --set time.end=7e-6";
  const fs::path one = scratch.dir / "one", two = scratch.dir / "two";
  ASSERT_EQ(sphfem_on(0, "run " + case_file + " -o " + one.string() + half, scratch.dir).code, 0);
  ASSERT_EQ(sphfem_on(2, "run " + case_file + " -o " + two.string() + half, scratch.dir).code, 0);
  for (const auto& [out, ranks] : {std::pair{one, 0}, std::pair{two, 3}}) {
    const auto r = sphfem_on(ranks,
                             "solve " + case_file + " -o " + out.string() + quiet + " --restart " +
                                 (out / "checkpoint.h5").string(),
                             scratch.dir);
    ASSERT_EQ(r.code, 0) << r.err;
  }
  EXPECT_TRUE(slurp(one / "history.csv") == slurp(two / "history.csv"));
  EXPECT_NE(slurp(two / "run.log").find("restart from"), std::string::npos);
}

TEST(MpiLaunch, WhatRanksCannotShareIsRefusedBeforeAnythingIsWritten) {
  const sphfem::test::Scratch scratch("mpi_refused");
  const fs::path out = scratch.dir / "out";
  // The surface contact: bar_impact's bars with `model: surface`.
  auto r = sphfem_on(2,
                     "run " + source + "bar_impact/case.yaml -o " + out.string() + quiet +
                         " --set 'contact.0={bodies: [bar_a, bar_b], model: surface}'",
                     scratch.dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("does not share the surface contact yet"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("-np 1"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  // A command that does not share its work: N ranks would write the same files.
  r = sphfem_on(2, "mesh " + source + "bar_pressed_fe/case.yaml -o " + out.string(), scratch.dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("only `sphfem run` and `sphfem solve`"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}
