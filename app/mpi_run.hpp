// Runs over many processes with MPI (docs/cluster.md): rank 0 runs the command, deals the work and writes every output.
#pragma once

#include <string>
#include <vector>

#include "funnel/ensemble.hpp"

namespace funnel::cli {

/// MPI for the lifetime of main(). It is initialised only when the process was started by an MPI
/// launcher (mpirun, mpiexec, srun); otherwise, and in a build without FUNNEL_MPI, the process
/// is a single rank 0 and nothing else changes.
///
/// Rank 0 parses the command line and runs the command as a single process would: it alone
/// reads and writes files and prints. The other ranks run no command: they serve() rank 0,
/// computing the chunks of ensembles it deals them, until rank 0 finish()es with its exit code,
/// which they then exit with too (so bad input is reported once and every rank exits with 2).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  /// Ends MPI.
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  /// On a rank other than 0: computes what rank 0 deals until it finishes; returns its exit code.
  int serve();
  /// On rank 0: tells the other ranks that the command ended with exit code `code`.
  void finish(int code);
};

/// This process's rank, 0 .. mpi_size() - 1 (0 without MPI).
int mpi_rank();
/// Number of processes of the run (1 without MPI).
int mpi_size();

/// The `--help` note on running under mpirun (or on a build without MPI).
std::string mpi_help();

/// run_sweep over every rank, called on rank 0 (the other ranks are in MpiSession::serve):
/// rank 0 sends the options to the others, then deals them units of consecutive (point, chunk)
/// tasks, with their points, as they ask for more, computes units itself on a second thread,
/// reduces each point in chunk order as soon as its chunks are back and calls `progress` and
/// `point_done` as run_sweep does. The results are bit-identical to run_sweep's for any number
/// of ranks and threads; with one rank it is run_sweep.
std::vector<EnsembleResult> distributed_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                              const Progress& progress = {}, const PointDone& point_done = {});

}  // namespace funnel::cli
