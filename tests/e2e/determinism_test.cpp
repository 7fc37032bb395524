// Determinism (issue 9): the same case gives the same files twice (the checkpoint too), and the
// same files at 1, 2 and 3 threads — bit for bit, not within a tolerance. By design: every
// reduction is a deterministic sum over fixed chunks, the neighbour lists are sorted and
// independent of the thread split, and loops write only their own entities (gather, no atomics).
// The scene is the coarse Børvik quarter at 303.5 m/s to 20 µs: particles, hexahedra, background
// particles, contact, mirror images, plasticity and damage all take part.
#include "tests/support/command.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;
using sphfem::test::slurp;

namespace {

const std::string case_file = std::string(SPHFEM_SOURCE_DIR) + "/cases/borvik_12mm/case.yaml";

const std::string keys =
    " -q --set preset=coarse --set time.end=2e-5 --set time.output_interval=1e-5";

// Solves in DIR/NAME from the model meshed once in DIR/mesh (meshing is not under test).
fs::path solve(const fs::path& dir, const std::string& name, int threads) {
  const fs::path out = dir / name, mesh = dir / "mesh";
  const std::string sphfem = "env -u DISPLAY " + std::string(SPHFEM_BINARY);
  if (!fs::exists(mesh / "model.h5")) {
    const std::string meshing = sphfem + " mesh " + case_file + " -o " + mesh.string() + keys;
    EXPECT_EQ(std::system(meshing.c_str()), 0) << meshing;
  }
  fs::create_directories(out);
  fs::copy_file(mesh / "model.h5", out / "model.h5");
  const std::string cmd = sphfem + " solve " + case_file + " -o " + out.string() + keys + " -j " +
                          std::to_string(threads) + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return out;
}

void expect_same_files(const fs::path& a, const fs::path& b) {
  for (const char* file : {"history.csv", "history.h5", "results.pvd"})
    EXPECT_TRUE(slurp(a / file) == slurp(b / file)) << file << " differs: " << b;
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(a / "frames")) {
    EXPECT_TRUE(slurp(entry.path()) == slurp(b / "frames" / entry.path().filename()))
        << entry.path().filename() << " differs: " << b;
    ++frames;
  }
  EXPECT_EQ(frames, 6); // 0, 10, 20 µs, FE and particles
  EXPECT_EQ(sphfem::test::summary_without_timing(a), sphfem::test::summary_without_timing(b));
}

} // namespace

TEST(Determinism, SameFilesTwiceAndAtAnyThreadCount) {
  const sphfem::test::Scratch scratch("determinism");
  const fs::path two = solve(scratch.dir, "two", 2), two_again = solve(scratch.dir, "two_again", 2);
  expect_same_files(two, two_again);
  // The checkpoint too, byte for byte (it names its thread count, so only at the same one).
  EXPECT_TRUE(slurp(two / "checkpoint.h5") == slurp(two_again / "checkpoint.h5"));
  expect_same_files(two, solve(scratch.dir, "one", 1));
  expect_same_files(two, solve(scratch.dir, "three", 3));
}
