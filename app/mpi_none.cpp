// A build without MPI (FUNNEL_MPI=OFF or no MPI found): one process, rank 0 of 1.
#include "mpi_run.hpp"

namespace funnel::cli {

MpiSession::MpiSession(int& /*argc*/, char**& /*argv*/) {}
MpiSession::~MpiSession() = default;
int MpiSession::serve() { return 0; }
void MpiSession::finish(int /*code*/) {}

int mpi_rank() { return 0; }
int mpi_size() { return 1; }

std::vector<EnsembleResult> distributed_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                              const Progress& progress, const PointDone& point_done) {
  return run_sweep(points, options, progress, point_done);
}

}  // namespace funnel::cli
