// Started by an MPI launcher (solver/core/mpi_session.hpp, issue 28): with one rank the run is
// the plain run, file for file; with several ranks, which this version cannot share a run
// among yet, it is refused before anything is read or written. mpirun runs as root in CI, hence
// --allow-run-as-root; --oversubscribe lets two ranks start on any machine.
#include "tests/support/command.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using sphfem::test::slurp;

namespace {

const std::string case_file = std::string(SPHFEM_SOURCE_DIR) + "/cases/bar_impact/case.yaml";
const std::string keys = " -q --set time.end=4e-5 --set output.frames=false";

std::string launcher(int ranks) {
  return std::string(SPHFEM_MPIEXEC) + " --allow-run-as-root --oversubscribe -np " +
         std::to_string(ranks) + " ";
}

} // namespace

TEST(MpiLaunch, OneRankWritesWhatAPlainRunWrites) {
  const sphfem::test::Scratch scratch("mpi_launch_one");
  const auto plain = sphfem::test::run_shell(std::string(SPHFEM_BINARY) + " run " + case_file +
                                                 " -o " + (scratch.dir / "plain").string() + keys,
                                             scratch.dir);
  ASSERT_EQ(plain.code, 0) << plain.err;
  const auto launched =
      sphfem::test::run_shell(launcher(1) + SPHFEM_BINARY + " run " + case_file + " -o " +
                                  (scratch.dir / "launched").string() + keys,
                              scratch.dir);
  ASSERT_EQ(launched.code, 0) << launched.err;
  for (const char* file : {"history.csv", "history.h5"})
    EXPECT_TRUE(slurp(scratch.dir / "plain" / file) == slurp(scratch.dir / "launched" / file))
        << file;
  EXPECT_EQ(sphfem::test::summary_without_timing(scratch.dir / "plain"),
            sphfem::test::summary_without_timing(scratch.dir / "launched"));
}

TEST(MpiLaunch, SeveralRanksAreRefusedBeforeAnythingIsWritten) {
  const sphfem::test::Scratch scratch("mpi_launch_two");
  const fs::path out = scratch.dir / "out";
  const auto r = sphfem::test::run_shell(launcher(2) + SPHFEM_BINARY + " run " + case_file +
                                             " -o " + out.string() + keys,
                                         scratch.dir);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("started on 2 MPI ranks"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("without mpirun, or with -np 1"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}
