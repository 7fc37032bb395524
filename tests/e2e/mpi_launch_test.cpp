// Runs started by an MPI launcher (issue 28). One rank is the plain run, file for file. On 2 and
// 3 ranks each rank steps its share of the hexahedra and particles (solver/parallel/
// subdomain.hpp, particle_share.hpp) and the run writes what the single process writes, bit for
// bit: the paper's bar under a pressure pulse in hexahedra, in particles and half and half
// (attachment: background particles and ties), its bars struck end on end (kernel contact and
// surface contact of particles against hexahedra), two slabs of hexahedra with unlike meshes
// pressed face to face (surface contact both ways, across the ranks' cuts), a Johnson–Cook bar
// pulled until its elements erode, a quarter block of particles crushed on a fixed face across
// two symmetry planes until most of its particles are killed (cut anew as it runs, and, never
// cut anew, its particles changing rank), a struck pellet flying alone across the cuts (it
// changes rank with its whole state), that block's checkpoint written on 2 ranks continued
// on 3, and the first 30 µs of the coarse Børvik shot; the halo a run's ranks
// receive is what the partition census counts. Their frames are one
// piece per rank that the post tool reads as the single process's frames. The commands that do
// not share their work are refused on several ranks before anything is written.
// mpirun runs as root in CI, hence --allow-run-as-root; --oversubscribe lets three ranks start
// on two cores.
#include "tests/support/command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

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

// Two elastic slabs of hexahedra, their meshes unlike (10 and 13 mm), driven into each other
// face to face: surface contact both ways; the ranks' cuts (along x, the longest side) cross
// the contact.
const char* pressed_slabs = R"(
name: pressed_slabs
time: {end: 6.0e-5, cfl: 0.6, output_interval: 2.0e-5, history_interval: 1.0e-6}
materials:
  steel: {model: elastic, density: 7830, youngs_modulus: 207.0e9, poisson_ratio: 0.3}
bodies:
  lower:
    method: fem
    geometry: {box: {min: [0, 0, -0.032], max: [0.2, 0.04, -0.002]}}
    element_size: 0.01
    h_factor: 0.55
    material: steel
    velocity: [0, 0, 100]
  upper:
    method: fem
    geometry: {box: {min: [0.003, 0.002, 0.002], max: [0.198, 0.038, 0.032]}}
    element_size: 0.013
    h_factor: 0.55
    material: steel
    velocity: [0, 0, -100]
contact:
  - {bodies: [lower, upper], model: surface}
)";

// A column of particles at rest beside a pellet that a hammer strikes (surface contact): the
// pellet leaves along the column at ≈ 540 m/s, ringing, 4 mm from the column (beyond the list
// cutoff, so in no other rank's halo), and crosses the ranks' cuts along z.
const char* passing_pellet = R"(
name: passing_pellet
time: {end: 2.5e-5, output_interval: 1.0e-5, history_interval: 5.0e-7}
materials:
  steel: {model: elastic, density: 7850, youngs_modulus: 200.0e9, poisson_ratio: 0.3}
bodies:
  column:
    method: sph
    geometry: {box: {min: [0, 0, 0], max: [0.002, 0.002, 0.02]}}
    spacing: 0.0005
    material: steel
  hammer:
    method: sph
    geometry: {box: {min: [0.006, 0, 0.0], max: [0.0075, 0.0015, 0.0015]}}
    spacing: 0.0005
    material: steel
    velocity: [0, 0, 600.0]
  pellet:
    method: sph
    geometry: {box: {min: [0.006, 0, 0.0017], max: [0.0075, 0.0015, 0.0032]}}
    spacing: 0.0005
    material: steel
contact:
  - {bodies: [hammer, pellet], model: surface}
)";

fs::path write_case(const fs::path& dir, const std::string& name, const char* text) {
  const fs::path file = dir / (name + ".yaml");
  std::ofstream(file) << text;
  return file;
}

// Runs `case_file` on one process and on 2 and 3 ranks; each writes the same history, bit for
// bit, and the same summary (but timing and what only a distributed run reports). The ranks do
// not gather their state for it: the history's sums are exact sums of each rank's own entities.
// Every particle's row is held by its rank, and no rank holds more than the model's. Returns
// the single run's summary; `shares`, when given, receives how often the runs of 2 and 3 ranks
// shared their work anew (rebalances), how many particles changed rank between (migrations) and
// the most particles' rows a rank held at the end.
struct Shares {
  std::vector<int> rebalances;
  std::vector<long long> migrations;
  std::vector<long long> most_held;
};
nlohmann::json expect_ranks_repeat_one_process(const std::string& case_file,
                                               const std::string& name,
                                               const std::string& keys = "",
                                               Shares* shares = nullptr) {
  const sphfem::test::Scratch scratch(name);
  const auto plain = sphfem_on(
      0, "run " + case_file + " -o " + (scratch.dir / "one").string() + quiet + keys, scratch.dir);
  EXPECT_EQ(plain.code, 0) << plain.err;
  const auto one = sphfem::test::summary_without_timing(scratch.dir / "one");
  for (int ranks : {2, 3}) {
    const fs::path out = scratch.dir / ("ranks" + std::to_string(ranks));
    const auto r =
        sphfem_on(ranks, "run " + case_file + " -o " + out.string() + quiet + keys, scratch.dir);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(slurp(out / "run.log").find("distributed over " + std::to_string(ranks) + " MPI"),
              std::string::npos);
    EXPECT_TRUE(slurp(scratch.dir / "one" / "history.csv") == slurp(out / "history.csv"))
        << ranks << " ranks";
    auto summary = sphfem::test::summary_without_timing(out);
    EXPECT_EQ(summary["ranks"], ranks);
    EXPECT_GT(summary["halo_bytes_per_entity_step"].get<double>(), 0.0);
    const auto particles = one["counts"]["particles"].get<long long>();
    const auto held = summary["rows_held_per_rank"]["particles"].get<std::vector<long long>>();
    EXPECT_EQ(held.size(), static_cast<std::size_t>(ranks));
    EXPECT_GE(std::accumulate(held.begin(), held.end(), 0LL), particles);
    const long long most = held.empty() ? 0 : *std::ranges::max_element(held);
    EXPECT_LE(most, particles);
    for (const long long background : summary["rows_held_per_rank"]["background_particles"])
      EXPECT_LE(background, one["counts"]["background_particles"].get<long long>());
    if (shares != nullptr) {
      shares->rebalances.push_back(summary["rebalances"].get<int>());
      shares->migrations.push_back(summary["migrations"].get<long long>());
      shares->most_held.push_back(most);
    }
    summary.erase("ranks");
    summary.erase("halo_bytes_per_entity_step");
    summary.erase("rebalances");
    summary.erase("migrations");
    summary.erase("rows_held_per_rank");
    EXPECT_EQ(summary["peak_resident_MB_per_rank"].size(), static_cast<std::size_t>(ranks));
    summary.erase("peak_resident_MB_per_rank");
    // Every rank reads a halo from the others.
    const double mean = summary["halo_fraction"]["mean"], largest = summary["halo_fraction"]["max"];
    EXPECT_GT(mean, 0.0);
    EXPECT_LE(mean, largest);
    summary.erase("halo_fraction");
    summary.erase("case_file");
    auto reference = one;
    reference.erase("case_file");
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
  // Shared anew as the bar yields and erodes (a threshold low enough to do so at 2 and 3
  // ranks): each element's stress, plastic strain and damage go to its new ranks with it.
  Shares shares;
  const auto one = expect_ranks_repeat_one_process(case_file.string(), "mpi_eroding_bar",
                                                   " --rebalance 1.001", &shares);
  EXPECT_GT(one["bodies"]["bar"]["eroded_elements"].get<int>(), 0); // the test erodes
  ASSERT_EQ(shares.rebalances.size(), 2u);
  EXPECT_GT(shares.rebalances[0], 0) << "2 ranks";
  EXPECT_GT(shares.rebalances[1], 0) << "3 ranks";
}

TEST(MpiLaunch, ElasticParticleBarOnTwoAndThreeRanksIsTheOneProcessRun) {
  // A rank holds the rows of its particles and of those within reach of them only: of a bar cut
  // across its length, a part and a few layers beyond.
  Shares shares;
  const auto one = expect_ranks_repeat_one_process(source + "bar_pressed_sph/case.yaml",
                                                   "mpi_bar_pressed_sph", "", &shares);
  const auto particles = one["counts"]["particles"].get<long long>();
  ASSERT_EQ(shares.most_held.size(), 2u);
  EXPECT_LT(shares.most_held[0], 0.75 * double(particles)) << "2 ranks";
  EXPECT_LT(shares.most_held[1], 0.6 * double(particles)) << "3 ranks";
}

TEST(MpiLaunch, AttachedBarOnTwoAndThreeRanksIsTheOneProcessRun) {
  expect_ranks_repeat_one_process(source + "bar_pressed/case.yaml", "mpi_bar_pressed");
}

TEST(MpiLaunch, TheRanksHaloIsWhatThePartitionCensusCounts) {
  // The halo a run's ranks receive (its exchange lists: halo rows, nodes of their elements that
  // others own, background particles filled or returned across ranks) over what they own, as
  // summary.json reports it, against `sphfem partition`'s census of the same decomposition,
  // counted apart from the run (ghost points within h_i + h_j + skin, foreign nodes): at the
  // start, before the particles move, the two agree — particles, hexahedra, their attachment.
  const sphfem::test::Scratch scratch("mpi_halo_census");
  const std::string case_file = source + "bar_pressed/case.yaml";
  for (int ranks : {2, 3}) {
    const fs::path run = scratch.dir / ("run" + std::to_string(ranks));
    const fs::path census = scratch.dir / ("census" + std::to_string(ranks));
    const auto r = sphfem_on(
        ranks, "run " + case_file + " -o " + run.string() + quiet + " --set time.end=2e-6",
        scratch.dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto p = sphfem_on(
        0, "partition " + case_file + " -o " + census.string() + " -n " + std::to_string(ranks),
        scratch.dir);
    ASSERT_EQ(p.code, 0) << p.err;
    const auto measured = nlohmann::json::parse(slurp(run / "summary.json"))["halo_fraction"];
    const auto counted = nlohmann::json::parse(slurp(census / "partition.json"))["halo_fraction"];
    for (const char* which : {"mean", "max"}) {
      const double m = measured[which], c = counted[which];
      EXPECT_GT(c, 0.01) << which;
      EXPECT_NEAR(m, c, 1e-12 * c) << which << ", " << ranks << " ranks";
    }
  }
}

TEST(MpiLaunch, BarsInKernelContactOnTwoAndThreeRanksAreTheOneProcessRun) {
  const auto one =
      expect_ranks_repeat_one_process(source + "bar_impact/case.yaml", "mpi_bar_impact");
  // The bars met at ±200 m/s and rebounded.
  EXPECT_LT(one["bodies"]["bar_a"]["com_velocity"][2].get<double>(), -150.0);
}

TEST(MpiLaunch, BarsInSurfaceContactOnTwoAndThreeRanksAreTheOneProcessRun) {
  // bar_impact with the surface contact (its README's second table).
  const auto one = expect_ranks_repeat_one_process(
      source + "bar_impact/case.yaml", "mpi_bar_impact_surface",
      " --set 'contact.0={bodies: [bar_a, bar_b], model: surface}'");
  EXPECT_LT(one["bodies"]["bar_a"]["com_velocity"][2].get<double>(), -150.0);
}

TEST(MpiLaunch, SlabsInSurfaceContactOnTwoAndThreeRanksAreTheOneProcessRun) {
  const sphfem::test::Scratch scratch("mpi_pressed_slabs_case");
  const fs::path case_file = write_case(scratch.dir, "pressed_slabs", pressed_slabs);
  // Shared anew as they run (a threshold low enough to do so on 3 ranks; 2 share the slabs
  // evenly): each new cut changes the rows a rank lists, and its contact candidates are found
  // again from them.
  Shares shares;
  const auto one = expect_ranks_repeat_one_process(case_file.string(), "mpi_pressed_slabs",
                                                   " --rebalance 1.001", &shares);
  // They met: each slab has lost a quarter of its 100 m/s or more.
  EXPECT_GT(one["bodies"]["upper"]["com_velocity"][2].get<double>(), -75.0);
  ASSERT_EQ(shares.rebalances.size(), 2u);
  EXPECT_GT(shares.rebalances[1], 0) << "3 ranks";
}

TEST(MpiLaunch, CrushedQuarterOfParticlesOnTwoAndThreeRanksIsTheOneProcessRun) {
  const sphfem::test::Scratch scratch("mpi_crushed_quarter_case");
  // As the particles are killed their work leaves the ranks holding them: the ranks share it
  // anew (a threshold low enough to do so several times) and stay the one process's run.
  const fs::path case_file = write_case(scratch.dir, "crushed_quarter", crushed_quarter);
  Shares shares;
  const auto one = expect_ranks_repeat_one_process(case_file.string(), "mpi_crushed_quarter",
                                                   " --rebalance 1.02", &shares);
  EXPECT_GT(one["bodies"]["block"]["killed_particles"].get<int>(), 100); // the test kills
  ASSERT_EQ(shares.rebalances.size(), 2u);
  EXPECT_GT(shares.rebalances[1], 0) << "3 ranks";
}

TEST(MpiLaunch, CrushedQuarterWhoseParticlesChangeRankIsTheOneProcessRun) {
  const sphfem::test::Scratch scratch("mpi_migrating_quarter_case");
  // Never cut anew: the block's upper particles, crushed down into the lower ranks' regions,
  // change rank at the neighbour-list rebuilds, and the run stays the one process's. A
  // checkpoint every 20 steps gathers the state on rank 0 alone: the others' copies of rows
  // they do not own go stale, and are never read.
  const fs::path case_file = write_case(scratch.dir, "crushed_quarter", crushed_quarter);
  Shares shares;
  expect_ranks_repeat_one_process(
      case_file.string(), "mpi_migrating_quarter",
      " --rebalance 0 --set time.end=8e-6 --set output.checkpoint.steps=20", &shares);
  ASSERT_EQ(shares.migrations.size(), 2u);
  EXPECT_EQ(shares.rebalances, (std::vector<int>{0, 0}));
  EXPECT_GT(shares.migrations[0], 50) << "2 ranks";
  EXPECT_GT(shares.migrations[1], 50) << "3 ranks";
}

TEST(MpiLaunch, APelletFlyingAloneChangesRankWithItsWholeState) {
  const sphfem::test::Scratch scratch("mpi_passing_pellet_case");
  // Never cut anew: the pellet (27 particles) goes to the next rank's region, where no rank
  // read it before, once at 2 ranks and twice at 3. Its new owner steps it from the state its
  // old one sends: its stress and velocities ring from the blow, so a move of positions alone
  // would not be the one process's run.
  const fs::path case_file = write_case(scratch.dir, "passing_pellet", passing_pellet);
  Shares shares;
  const auto one = expect_ranks_repeat_one_process(case_file.string(), "mpi_passing_pellet",
                                                   " --rebalance 0", &shares);
  EXPECT_GT(one["bodies"]["pellet"]["com_velocity"][2].get<double>(), 500.0); // it was struck
  EXPECT_GT(one["bodies"]["pellet"]["internal_energy"].get<double>(), 0.0);   // and rings
  EXPECT_EQ(shares.rebalances, (std::vector<int>{0, 0}));
  EXPECT_EQ(shares.migrations, (std::vector<long long>{27, 54}));
}

TEST(MpiLaunch, ACheckpointOfTwoRanksContinuesOnThreeAndOnOne) {
  // The same checkpoint time of the crushed quarter reached on one process and on two ranks;
  // each continued (on one process, on three ranks) to the end writes the same history. The
  // checkpoint holds the particles and the positions of its last neighbour build, from which
  // the three ranks list their rows (with the mirror images that build had).
  const sphfem::test::Scratch scratch("mpi_restart");
  const std::string case_file =
      write_case(scratch.dir, "crushed_quarter", crushed_quarter).string();
  // The ranks' run writes frames: those after the restart are three pieces each, listed after
  // the two-piece frames before it.
  const std::string half = " -q --set time.end=7e-6";
  const fs::path one = scratch.dir / "one", two = scratch.dir / "two",
                 two_on_one = scratch.dir / "two_on_one";
  ASSERT_EQ(sphfem_on(0, "run " + case_file + " -o " + one.string() + half, scratch.dir).code, 0);
  ASSERT_EQ(sphfem_on(2, "run " + case_file + " -o " + two.string() + half, scratch.dir).code, 0);
  // The ranks' checkpoint continued on one process too (each rank had the mirror images of the
  // rows it binned only; reading makes those of every row anew).
  fs::copy(two, two_on_one, fs::copy_options::recursive);
  for (const auto& [out, ranks] :
       {std::pair{one, 0}, std::pair{two, 3}, std::pair{two_on_one, 0}}) {
    const auto r = sphfem_on(ranks,
                             "solve " + case_file + " -o " + out.string() + " -q --restart " +
                                 (out / "checkpoint.h5").string(),
                             scratch.dir);
    ASSERT_EQ(r.code, 0) << r.err;
  }
  EXPECT_TRUE(slurp(one / "history.csv") == slurp(two / "history.csv"));
  EXPECT_TRUE(slurp(one / "history.csv") == slurp(two_on_one / "history.csv"));
  EXPECT_NE(slurp(two / "run.log").find("restart from"), std::string::npos);
  const std::string listed = slurp(two / "results.pvd");
  for (int frame = 0; frame < 5; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "sph_%06d", frame);
    EXPECT_NE(listed.find(std::string("frames/") + name + ".pvtu"), std::string::npos) << name;
    const std::string pvtu = slurp(two / "frames" / (std::string(name) + ".pvtu"));
    EXPECT_EQ(pvtu.find("_2.vtu") != std::string::npos, frame >= 3) << name; // 7 µs: frame 2
  }
  EXPECT_EQ(listed,
            std::regex_replace(slurp(one / "results.pvd"), std::regex(R"(\.vtu")"), ".pvtu\""));
}

TEST(MpiLaunch, FramesOfTwoAndThreeRanksArePiecesThatReadAsTheOneProcessFrames) {
  // Each rank writes its piece of every frame, rank 0 the .pvtu naming the pieces, and
  // results.pvd lists those. The post tool reads them back in the model's order: the report's
  // section, deflection, fragments and plug — of hexahedra eroding (their nodes in two pieces
  // where the ranks' elements meet) and of particles killed — are the single process's, byte for
  // byte. A missing piece stops the post tool with the frame named.
  const sphfem::test::Scratch scratch("mpi_frames");
  for (const auto& [name, text] :
       {std::pair{"eroding_bar", eroding_bar}, std::pair{"crushed_quarter", crushed_quarter}}) {
    const std::string case_file = write_case(scratch.dir, name, text).string();
    const fs::path one = scratch.dir / (std::string(name) + "_one");
    const auto plain =
        sphfem_on(0, "run " + case_file + " -o " + one.string() + " -q", scratch.dir);
    ASSERT_EQ(plain.code, 0) << plain.err;
    const std::string listed = slurp(one / "results.pvd");
    int listed_frames = 0;
    for (std::size_t at = 0; (at = listed.find("<DataSet", at)) != std::string::npos; ++at)
      ++listed_frames;
    EXPECT_GE(listed_frames, 4) << name;
    for (int ranks : {2, 3}) {
      const fs::path out = scratch.dir / (std::string(name) + "_" + std::to_string(ranks));
      const auto r =
          sphfem_on(ranks, "run " + case_file + " -o " + out.string() + " -q", scratch.dir);
      ASSERT_EQ(r.code, 0) << r.err;
      // The same frames at the same times, each a .pvtu of one piece per rank.
      const std::string expected = std::regex_replace(listed, std::regex(R"(\.vtu")"), ".pvtu\"");
      EXPECT_EQ(slurp(out / "results.pvd"), expected) << name << ", " << ranks << " ranks";
      int frames = 0;
      for (const auto& entry : fs::directory_iterator(out / "frames")) {
        if (entry.path().extension() != ".pvtu")
          continue;
        ++frames;
        const std::string pvtu = slurp(entry.path());
        const std::string stem = entry.path().stem().string();
        for (int rank = 0; rank < ranks; ++rank) {
          const std::string piece = stem + "_" + std::to_string(rank) + ".vtu";
          EXPECT_NE(pvtu.find("<Piece Source=\"" + piece + "\"/>"), std::string::npos) << piece;
          EXPECT_TRUE(fs::is_regular_file(out / "frames" / piece)) << piece;
        }
        const std::string beyond = stem + "_" + std::to_string(ranks) + ".vtu";
        EXPECT_EQ(pvtu.find(beyond), std::string::npos) << beyond;
      }
      EXPECT_EQ(frames, listed_frames) << name;
      for (const char* file :
           {"section.csv", "section.json", "deflection.csv", "fragments.csv", "plug.json"}) {
        if (fs::exists(one / "report" / file)) {
          EXPECT_TRUE(slurp(one / "report" / file) == slurp(out / "report" / file))
              << name << ", " << ranks << " ranks: report/" << file;
        }
      }
    }
    ASSERT_TRUE(fs::exists(one / "report" / "section.csv")) << name;
  }
  const fs::path broken = scratch.dir / "eroding_bar_2";
  fs::remove(broken / "frames" / "fe_000004_1.vtu");
  const auto r =
      sphfem_on(0, "post section " + broken.string() + " --plane 0,0.002,0,0,1,0", scratch.dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("fe_000004.pvtu: cannot read the frame (VTK: File for piece 1"),
            std::string::npos)
      << r.err;
  // A rank that cannot write its piece (a folder where its file goes) stops every rank; it names
  // the file, and the frame is not listed.
  const fs::path blocked = scratch.dir / "blocked";
  fs::create_directories(blocked / "frames" / "fe_000000_1.vtu" / "in_the_way");
  const auto stopped = sphfem_on(
      2, "run " + (scratch.dir / "eroding_bar.yaml").string() + " -o " + blocked.string() + " -q",
      scratch.dir);
  EXPECT_NE(stopped.code, 0);
  EXPECT_NE(stopped.err.find("error on MPI rank 1: " + (blocked / "frames").string() +
                             "/fe_000000_1.vtu: cannot replace the file"),
            std::string::npos)
      << stopped.err;
  EXPECT_NE(stopped.err.find("frame 0: another MPI rank could not write its piece"),
            std::string::npos)
      << stopped.err;
  EXPECT_FALSE(fs::exists(blocked / "results.pvd"));
  EXPECT_FALSE(fs::exists(blocked / "frames" / "fe_000000_1.vtu.tmp"));
}

TEST(MpiLaunch, CoarseBorvikShotOnTwoRanksIsTheOneProcessRun) {
  // The first 30 µs at 303.5 m/s: the projectile's face in surface contact with the core's
  // particles, the plate clamped at its rim, two symmetry planes. The history is the same bit for
  // bit, the clamped rim's work (itself round-off: the rim does not move) included.
  const sphfem::test::Scratch scratch("mpi_borvik");
  const std::string keys = quiet + " --set preset=coarse --set time.end=3e-5" +
                           " --set projectile.velocity=303.5 --set time.history_interval=1e-6";
  const std::string case_file = source + "borvik_12mm/case.yaml";
  const fs::path one = scratch.dir / "one", two = scratch.dir / "two";
  ASSERT_EQ(sphfem_on(0, "run " + case_file + " -o " + one.string() + keys, scratch.dir).code, 0);
  const auto r = sphfem_on(2, "run " + case_file + " -o " + two.string() + keys, scratch.dir);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream a(slurp(one / "history.csv")), b(slurp(two / "history.csv"));
  std::string header, line_a, line_b;
  ASSERT_TRUE(std::getline(a, header));
  ASSERT_TRUE(std::getline(b, line_b));
  ASSERT_EQ(header, line_b);
  std::vector<std::string> columns;
  for (std::istringstream h(header); std::getline(h, line_a, ',');)
    columns.push_back(line_a);
  int rows = 0;
  while (std::getline(a, line_a)) {
    ASSERT_TRUE(std::getline(b, line_b));
    std::istringstream ca(line_a), cb(line_b);
    std::string x, y;
    for (const std::string& column : columns) {
      std::getline(ca, x, ',');
      std::getline(cb, y, ',');
      EXPECT_EQ(x, y) << column << ", row " << rows;
    }
    ++rows;
  }
  EXPECT_FALSE(std::getline(b, line_b));
  EXPECT_EQ(rows, 31);
  const auto summary = nlohmann::json::parse(slurp(two / "summary.json"));
  const auto reference = nlohmann::json::parse(slurp(one / "summary.json"));
  EXPECT_EQ(summary["bodies"], reference["bodies"]);
  EXPECT_EQ(summary["energy"], reference["energy"]);
  EXPECT_EQ(summary["momentum_drift"], reference["momentum_drift"]);
  // A rank holds the background particles of its nodes and of those near its particles only:
  // with 5 list cutoffs around its own for the surface contact, the core's particles and 1 329
  // background particles are all near on one rank, 1 012 of them on the other.
  const auto held =
      summary["rows_held_per_rank"]["background_particles"].get<std::vector<double>>();
  ASSERT_EQ(held.size(), 2u);
  EXPECT_LT(std::ranges::min(held),
            0.9 * reference["counts"]["background_particles"].get<double>());
  // The projectile has struck: it has lost more than 10% of its speed and is still going.
  EXPECT_GT(reference["bodies"]["projectile"]["com_velocity"][2].get<double>(), -273.0);
  EXPECT_LT(reference["bodies"]["projectile"]["com_velocity"][2].get<double>(), -150.0);
}

TEST(MpiLaunch, CommandsThatDoNotShareTheirWorkAreRefusedBeforeAnythingIsWritten) {
  const sphfem::test::Scratch scratch("mpi_refused");
  const fs::path out = scratch.dir / "out";
  // N ranks would write the same files.
  const auto r =
      sphfem_on(2, "mesh " + source + "bar_pressed_fe/case.yaml -o " + out.string(), scratch.dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("only `sphfem run` and `sphfem solve`"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}
