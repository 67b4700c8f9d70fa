#pragma once
// MPI for a design's runs (study/design_runner.hpp): the process group
// `demcal doe` splits a design over. When demcal is built with MPI (CMake option
// DEMCAL_MPI, on when MPI is found) and started by an MPI launcher (mpirun,
// mpiexec, srun with PMI: recognised by the variables they set), the session
// initialises MPI (thread level "funneled": only the main thread calls MPI)
// and the campaign is split over MPI_COMM_WORLD; otherwise it is a group of
// one and MPI is never touched, so a plain `demcal doe` needs no MPI runtime.

#include "study/design_runner.hpp"

namespace demcal::study {

class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  // Whether MPI was initialised here.
  bool active() const { return active_; }
  ProcessGroup group() const;

  // Whether this binary was built with MPI.
  static bool built_with_mpi();

 private:
  bool active_ = false;
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace demcal::study
