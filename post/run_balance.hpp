// How the work of a finished run moves among the ranks of a fixed decomposition (issue 28's
// rebalancing): for each frame of RUN/results.pvd, each rank's cost per step with the particles
// alive then, at their neighbour counts then, and the elements not eroded
// (solver/parallel/decomposition.hpp, part_costs). Used by `sphfem partition --run`.
// Verified by tests/e2e/partition_command_test.cpp.
#pragma once

#include "solver/parallel/decomposition.hpp"

#include <filesystem>
#include <vector>

namespace sphfem::post {

struct RunBalance {
  std::vector<double> time_s;
  std::vector<std::vector<double>> cost_s; // per frame, per rank: s per step (one thread)
  std::vector<double> imbalance;           // per frame: largest rank's cost / mean
};

// Reads the run's frames; throws sphfem::Error when they are missing, unreadable or not of the
// decomposition's model (particle ids out of range, another element count).
RunBalance run_balance(const std::filesystem::path& run_dir, const Decomposition& d,
                       const EntityCosts& costs);

// `csv`: time_s,imbalance,cost_s_rank0,…; `png`: the largest and the smallest rank's cost over
// the mean against time in µs.
void write_run_balance(const RunBalance& b, const std::filesystem::path& csv,
                       const std::filesystem::path& png);

} // namespace sphfem::post
