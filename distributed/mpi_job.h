// This process's place in an MPI job. Built with Open MPI (mpi_job.cpp), a
// process that mpirun started joins its job; built without it
// (mpi_job_single.cpp), or started without mpirun, it is rank 0 of 1 and
// behaves as a plain process.
#pragma once

namespace pt::dist {

class MpiJob {
 public:
  MpiJob(int* argc, char*** argv);
  ~MpiJob();
  MpiJob(const MpiJob&) = delete;
  MpiJob& operator=(const MpiJob&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// Collective: every rank says whether its setup (scene, BVH, output
  /// checks) succeeded. Returns what rank 0 must know to report once.
  struct Readiness {
    bool all = true;    ///< every rank is ready
    bool rank0 = true;  ///< rank 0 is ready (its message covers the others' if not)
  };
  Readiness agree_ready(bool ready_here) const;

  /// Ends every rank of the job now with exit status `code` (a rank that
  /// cannot go on must not leave the others waiting for it).
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0, size_ = 1;
  [[maybe_unused]] bool joined_ = false;  ///< MPI_Init ran (only builds with MPI read it)
};

}  // namespace pt::dist
