// This process's place in a distributed run (issue 28): MPI is started only when a launcher
// (mpirun/mpiexec, or srun with PMI/PMIx) started the process, so that a plain `sphfem run`
// needs no mpirun and pays nothing for MPI (Open MPI 4.1's start-up without a launcher, its
// "singleton", takes ≈ 0.7 s here). Built without MPI (-DSPHFEM_MPI=OFF), or not launched, the
// process is rank 0 of 1. One per process, for its whole life (constructed first in main).
#pragma once

namespace sphfem {

class MpiSession {
public:
  // MPI_Init_thread with MPI_THREAD_FUNNELED (OpenMP threads inside, MPI on the master) when
  // launched; nothing otherwise.
  MpiSession(int& argc, char**& argv);
  ~MpiSession(); // MPI_Finalize if started
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  // Whether a launcher's environment says this process is one of a parallel job's ranks.
  static bool launched();

private:
  int rank_ = 0;
  int size_ = 1;
  bool started_ = false;
};

} // namespace sphfem
