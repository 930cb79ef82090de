// MpiJob with Open MPI. MPI is initialised only in a process mpirun started
// (it sets OMPI_COMM_WORLD_SIZE), so a plain `pathtracer` run stays a plain
// process. MPI_THREAD_SERIALIZED: rank 0 talks to the other ranks from a
// second thread while its main thread renders, never both at once.
#include <mpi.h>

#include <cstdio>
#include <cstdlib>

#include "mpi_job.h"

namespace pt::dist {

MpiJob::MpiJob(int* argc, char*** argv) {
  if (!std::getenv("OMPI_COMM_WORLD_SIZE")) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
  joined_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (provided < MPI_THREAD_SERIALIZED && size_ > 1) {
    if (rank_ == 0) std::fprintf(stderr, "error: this MPI library cannot be used from two threads of a rank\n");
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
}

MpiJob::~MpiJob() {
  if (joined_) MPI_Finalize();
}

MpiJob::Readiness MpiJob::agree_ready(bool ready_here) const {
  if (size_ == 1) return {ready_here, ready_here};
  int mine = ready_here ? 1 : 0, all = 0, first = mine;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  MPI_Bcast(&first, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return {all == 1, first == 1};
}

void MpiJob::abort(int code) const {
  if (joined_) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

}  // namespace pt::dist
