// A build without MPI (FUNNEL_MPI=OFF or no MPI found): one process, rank 0 of 1.
#include "mpi_run.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace funnel::cli {

MpiSession::MpiSession(int& /*argc*/, char**& /*argv*/) {
  // A task of `srun -n K` other than task 0 would run the whole command again beside it, over
  // the same output files.
  if (const char* task = std::getenv("SLURM_PROCID"); task != nullptr && std::string(task) != "0") {
    std::fprintf(stderr, "funnel: error: started as task %s of srun, but this funnel was built without MPI "
                 "(FUNNEL_MPI=OFF): run one task (docs/cluster.md)\n", task);
    std::exit(2);
  }
}
MpiSession::~MpiSession() = default;
int MpiSession::serve() { return 0; }
void MpiSession::finish(int /*code*/) {}

std::string mpi_help() {
  return "Many processes: this funnel was built without MPI (FUNNEL_MPI=OFF); see docs/cluster.md.";
}

int mpi_rank() { return 0; }
int mpi_size() { return 1; }

std::vector<EnsembleResult> distributed_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                              const Progress& progress, const PointDone& point_done) {
  return run_sweep(points, options, progress, point_done);
}

}  // namespace funnel::cli
