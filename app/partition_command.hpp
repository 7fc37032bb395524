// `sphfem partition`: how a case would be shared among N MPI ranks (issue 28) — the domain
// decomposition (solver/parallel/decomposition.hpp: Zoltan's RCB weighted by each entity's
// measured cost) and what each rank would hold and receive every step (solver/parallel/halo.hpp),
// printed as a table and written to OUT/partition.json, with the ranks on the mesh and the
// particles in OUT/partition.vtu and OUT/partition_particles.vtu for ParaView. With --run, how
// the work of a finished run of the case moves among those ranks, frame by frame
// (post/run_balance.hpp). Verified by tests/e2e/partition_command_test.cpp.
#pragma once

#include "solver/io/case.hpp"
#include "solver/state/model.hpp"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sphfem {

struct PartitionCommandOptions {
  std::string case_file, out_dir;
  std::vector<std::string> overrides;
  int ranks = 1;
  std::string run_dir; // a finished run of the case: how its work moves among the ranks
  bool quiet = false;
};

// Adds the subcommand to `app`, filling `o` when it is parsed.
CLI::App* add_partition_command(CLI::App& app, PartitionCommandOptions& o);

// Decomposes `model` (the case's, meshed by the caller) and writes the files. The halo's skin
// is the run's neighbour-list skin (sph.skin × the largest 2h); the costs count the mirror
// images of the case's symmetry planes. Throws sphfem::Error on bad input.
void run_partition_command(const PartitionCommandOptions& o, const Case& c, const Model& model);

} // namespace sphfem
