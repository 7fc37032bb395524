// Entry point of the `sphfem` command (app/commands.hpp does the work). MPI is started first
// when a launcher started this process (solver/core/mpi_session.hpp); the domain decomposition
// that would share a run among ranks is not built yet (issue 28), so a job of several ranks is
// refused before anything is read or written: N copies of one run would write the same files.
#include "app/commands.hpp"
#include "solver/core/mpi_session.hpp"

#include <iostream>

int main(int argc, char** argv) {
  const sphfem::MpiSession mpi(argc, argv);
  if (mpi.size() > 1) {
    if (mpi.rank() == 0)
      std::cerr << "sphfem: error: started on " << mpi.size()
                << " MPI ranks, but this version runs a simulation on one process (domain "
                   "decomposition is not available yet). Run it without mpirun, or with -np 1; "
                   "use --threads for the cores of one machine.\n";
    return 2;
  }
  return sphfem::run_command_line(argc, argv);
}
