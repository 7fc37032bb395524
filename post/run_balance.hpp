// How the work of a finished run moves among the ranks of a fixed decomposition (issue 28's
// rebalancing): for each frame of RUN/results.pvd, each rank's cost per step with the particles
// alive then, at their neighbour counts then, and the elements not eroded, those whose material
// point yields then costing their return (the frames' `yielding` flag; absent: none yields)
// (solver/parallel/decomposition.hpp, part_costs), the entities owned as at t = 0 or by the
// region they are in. Used by `sphfem partition --run`.
// Verified by tests/e2e/partition_command_test.cpp.
#pragma once

#include "solver/parallel/decomposition.hpp"

#include <filesystem>
#include <vector>

namespace sphfem::post {

// Two ownerships, each rank's cost per frame and per rank in s per step (one thread), and the
// imbalance (largest rank's cost / mean, both phases summed: a drift of either shows) per frame:
// each entity kept on its rank of t = 0, and each entity with the rank whose region (RCB's box:
// the particles' or the elements') it is in then, keeping its rank while on that region's face —
// what migration at neighbour-list rebuilds would give.
struct RunBalance {
  std::vector<double> time_s;
  std::vector<std::vector<double>> cost_s, region_cost_s;
  std::vector<double> imbalance, region_imbalance;
};

// Reads the run's frames; throws sphfem::Error when they are missing, unreadable or not of the
// decomposition's model (particle ids out of range, another element count).
RunBalance run_balance(const std::filesystem::path& run_dir, const Decomposition& d,
                       const EntityCosts& costs);

// `csv`: time_s,imbalance,region_imbalance,cost_s_rank0,…,region_cost_s_rank0,…; `png`: the
// largest and the smallest rank's cost over the mean against time in µs, both ownerships.
void write_run_balance(const RunBalance& b, const std::filesystem::path& csv,
                       const std::filesystem::path& png);

} // namespace sphfem::post
