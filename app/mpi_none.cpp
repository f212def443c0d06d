// A build without MPI (FUNNEL_MPI=OFF or no MPI found): one process, rank 0 of 1.
#include "mpi_run.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace funnel::cli {

MpiSession::MpiSession(int& /*argc*/, char**& /*argv*/) {
  // A process of `mpirun -np K` or `srun -n K` other than the first would run the whole command
  // again beside it, over the same output files.
  for (const char* var : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"}) {
    const char* rank = std::getenv(var);
    if (rank == nullptr || std::string(rank) == "0") continue;
    std::fprintf(stderr, "funnel: error: started as process %s of mpirun or srun, but this funnel was built without "
                 "MPI (FUNNEL_MPI=OFF): run one process (docs/cluster.md)\n", rank);
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
