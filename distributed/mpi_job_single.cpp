// MpiJob without MPI: always rank 0 of 1.
#include <cstdlib>

#include "mpi_job.h"

namespace pt::dist {

MpiJob::MpiJob(int*, char***) {}
MpiJob::~MpiJob() = default;
MpiJob::Readiness MpiJob::agree_ready(bool ready_here) const { return {ready_here, ready_here}; }
void MpiJob::abort(int code) const { std::exit(code); }

}  // namespace pt::dist
