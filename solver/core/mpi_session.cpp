#include "solver/core/mpi_session.hpp"

#include <cstdlib>
#include <initializer_list>

#ifdef SPHFEM_HAVE_MPI
#include <mpi.h>
#endif

namespace sphfem {

bool MpiSession::launched() {
  // Open MPI's mpirun, MPICH's Hydra and Slurm's PMI-2 set the first two; PMIx (Open MPI 4+,
  // Slurm's --mpi=pmix) the third.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name) != nullptr)
      return true;
  return false;
}

#ifdef SPHFEM_HAVE_MPI

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched())
    return;
  int provided = 0; // MPI_Init's errors are fatal: it aborts the job with MPI's own message
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  started_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (started_)
    MPI_Finalize();
}

#else

MpiSession::MpiSession(int&, char**&) {}

MpiSession::~MpiSession() = default;

#endif

} // namespace sphfem
