// The solve loop: builds the simulation from a case and its model, steps it to the end time
// and writes what DESIGN.md fixes — results.pvd + frames/*.vtu at each output interval,
// history.csv/.h5, summary.json, run.log and checkpoint.h5 (output.checkpoint's cadence and at
// the end) — with progress on long runs. Stops with an Error (and keeps the frames written so
// far) when the run turns unstable. SIGINT/SIGTERM finish the step, write a checkpoint and throw
// Interrupted. With a restart file it continues that checkpoint's run: refused if the case's
// physics keys or the model differ from the checkpoint's; the continued run writes what the
// uninterrupted one would, bit for bit (but wall times; tests/e2e/restart_test.cpp).
// Started on several MPI ranks (issue 28) every rank steps its share of the elements
// (solver/parallel/subdomain.hpp) and rank 0 writes the same files a single process would: the
// checkpoint holds the whole state, so a run continues on any number of ranks
// (tests/e2e/mpi_launch_test.cpp).
#pragma once

#include "solver/core/error.hpp"
#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <filesystem>
#include <nlohmann/json_fwd.hpp>

namespace sphfem {

struct SolveOptions {
  std::filesystem::path out_dir;
  bool echo = true;              // log and progress on stderr
  std::filesystem::path restart; // a checkpoint.h5 to continue from (empty: start at t = 0)
  // A distributed run: a new decomposition when the largest rank's cost per step passes this
  // multiple of the mean (checked at each history row and frame; 0: never).
  double rebalance = 1.02;
};

// A run stopped by SIGINT or SIGTERM after writing its checkpoint.
class Interrupted : public Error {
public:
  Interrupted(const std::string& what, int signal) : Error(what), signal_(signal) {}
  int signal() const { return signal_; }

private:
  int signal_;
};

// Runs the case and returns the summary that was written to OUT/summary.json.
nlohmann::json solve(const Case& c, const Model& model, const SolveOptions& options);

} // namespace sphfem
