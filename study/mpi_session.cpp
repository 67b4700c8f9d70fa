#include "study/mpi_session.hpp"

#include <cstdlib>

#ifdef DEMCAL_HAVE_MPI
#include <mpi.h>
#endif

namespace demcal::study {

namespace {

// Variables the common launchers set in every process they start.
[[maybe_unused]] bool started_by_mpi_launcher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE",
                        "MPI_LOCALNRANKS", "MV2_COMM_WORLD_SIZE"})
    if (std::getenv(v) != nullptr) return true;
  return false;
}

}  // namespace

bool MpiSession::built_with_mpi() {
#ifdef DEMCAL_HAVE_MPI
  return true;
#else
  return false;
#endif
}

MpiSession::MpiSession() {
#ifdef DEMCAL_HAVE_MPI
  if (!started_by_mpi_launcher()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  active_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
#endif
}

MpiSession::~MpiSession() {
#ifdef DEMCAL_HAVE_MPI
  if (active_) MPI_Finalize();
#endif
}

ProcessGroup MpiSession::group() const {
  ProcessGroup g;
  g.rank = rank_;
  g.size = size_;
#ifdef DEMCAL_HAVE_MPI
  if (active_ && size_ > 1)
    g.all_true = [](bool ok) {
      int in = ok ? 1 : 0, all = 0;
      MPI_Allreduce(&in, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
      return all != 0;
    };
#endif
  return g;
}

}  // namespace demcal::study
