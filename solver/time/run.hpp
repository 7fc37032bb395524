// The solve loop: builds the simulation from a case and its model, steps it to the end time
// and writes what DESIGN.md fixes — results.pvd + frames/*.vtu at each output interval,
// history.csv/.h5, summary.json and run.log — with progress on long runs. Stops with an
// Error (and keeps the frames written so far) when the run turns unstable.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <filesystem>
#include <nlohmann/json_fwd.hpp>

namespace sphfem {

struct SolveOptions {
  std::filesystem::path out_dir;
  bool echo = true; // log and progress on stderr
};

// Runs the case and returns the summary that was written to OUT/summary.json.
nlohmann::json solve(const Case& c, const Model& model, const SolveOptions& options);

} // namespace sphfem
