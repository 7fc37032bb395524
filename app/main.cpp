// Entry point of the `sphfem` command (app/commands.hpp does the work). MPI is started first
// when a launcher started this process (solver/core/mpi_session.hpp); `run` and `solve` then
// share the simulation among the ranks (solver/parallel/), the other commands refuse to run on
// several ranks.
#include "app/commands.hpp"
#include "solver/core/mpi_session.hpp"

int main(int argc, char** argv) {
  const sphfem::MpiSession mpi(argc, argv);
  return sphfem::run_command_line(argc, argv);
}
