// Ensembles over release states (docs/model.md §8) and sweeps over parameter grids, in parallel.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/observables.hpp"
#include "funnel/params.hpp"
#include "funnel/stats.hpp"
#include "funnel/wear.hpp"

namespace funnel {

/// Distribution of the release positions.
enum class ReleaseDist {
  Line,      ///< 2D funnel: x0_k / L = (2k + 1 - N)/N, uniformly spaced (the paper's)
  Disk,      ///< axisymmetric cone: r_k / L = sqrt((k + 1/2)/N), uniform over the disk
  Uniform,   ///< x0 / L uniform random in (-1, 1)
  Gaussian,  ///< x0 / L normal (mean, sd), truncated to (-1, 1) by drawing again
};

/// "line", "disk", "uniform" or "gaussian".
std::string_view to_string(ReleaseDist dist);
/// Parses a distribution's name; nullopt otherwise.
std::optional<ReleaseDist> parse_release_dist(std::string_view text);

/// Release position x0/L of sample k of N for the deterministic distributions (line, disk).
double release_fraction(ReleaseDist dist, std::int64_t k, std::int64_t n);

/// How to run an ensemble.
struct EnsembleOptions {
  std::int64_t samples = default_samples;  ///< N, 1 <= N <= 10^9
  ReleaseDist dist = ReleaseDist::Line;
  int threads = 0;                          ///< 0: all cores; else 1..1024
  bool keep_samples = false;                ///< also return every trajectory (O(N) memory)
  std::uint64_t seed = 1;                   ///< key of the random numbers (uniform, gaussian, velocity-sd)
  double release_mean = 0.0;                ///< gaussian: mean of x0/L, -1 < mean < 1
  double release_sd = 0.1;                  ///< gaussian: standard deviation of x0/L, > 0
  double velocity_sd = 0.0;                 ///< standard deviation of each initial velocity component, sqrt(gH), >= 0
  int wear_bins = 0;                        ///< bins per wall of the wear record (0: none), <= 10^4
  /// When set and it becomes true, the work not yet started is skipped and the results are
  /// incomplete (e.g. Ctrl-C in Python); the caller checks it after the run.
  std::atomic<bool>* cancel = nullptr;
};

/// Checks the options (the same checks for the CLI, Python and `funnel paper`); the first
/// invalid one, if any, as a ParamError naming the option.
std::optional<ParamError> validate(const EnsembleOptions& options);

/// Checks that the funnel of `params` takes the options' releases: `disk` releases are the
/// cone's (docs/model.md §8), x0 = r > 0 only, which stand for the whole funnel only in a
/// mirror-symmetric one (in an asymmetric V or profile they would never release over its left
/// half). The 2D runs' check; the 3D funnel is a cone by construction.
std::optional<ParamError> validate(const Params& params, const EnsembleOptions& options);

/// Release position x0/L of sample k, in (-1, 1) (random distributions keyed by (seed, k)).
double sample_fraction(const EnsembleOptions& options, std::int64_t k);

/// The release state of sample k: its position from the distribution, the parameters' release
/// velocity and spin, plus a random velocity of standard deviation velocity_sd per component.
/// Random numbers are keyed by (seed, k): the same for any thread count or split of the work.
State sample_release(const Params& params, const Funnel& f, const EnsembleOptions& options, std::int64_t k);
/// The same, building the funnel from the parameters.
State sample_release(const Params& params, const Geometry& g, const EnsembleOptions& options, std::int64_t k);

/// True when the releases draw random numbers (uniform or gaussian positions, random velocities).
bool is_random(const EnsembleOptions& options);

/// True when the ensemble is its own mirror image (x -> -x): a mirror-symmetric funnel, line
/// releases at zero horizontal velocity and spin, no random velocities. Only then is half of it
/// simulated.
bool mirror_symmetric(const Params& params, const EnsembleOptions& options);

/// Per-sample outputs of an ensemble, kept only on request.
struct Sample {
  double fraction = 0.0;  ///< x0 / L
  State release;          ///< the release state
  Trajectory trajectory;  ///< its observables
};

/// Statistics of an ensemble.
struct EnsembleResult {
  std::int64_t samples = 0;
  std::array<Summary, observable_count> stats{};   ///< every observable; exit ones over the exited samples
  std::int64_t exited = 0, rest = 0, trapped = 0;  ///< count of each status
  std::int64_t capped = 0;   ///< ended by the collision cap inside the funnel (Trajectory::capped; among `trapped`)
  std::int64_t stalled = 0;  ///< ended by the Zeno guard (Trajectory::stalled; among `trapped`)
  std::int64_t total_collisions = 0;               ///< summed over the samples
  std::int64_t simulated_collisions = 0;           ///< collisions actually computed (mirror halving)
  Wear wear;                                       ///< per-sample mean wear (options.wear_bins > 0)
  std::vector<Sample> per_sample;                  ///< filled when keep_samples

  /// The statistics of one observable.
  const Summary& operator[](Observable o) const { return stats[static_cast<std::size_t>(o)]; }
};

/// Called with (finished work units, total work units); from one thread at a time.
using Progress = std::function<void(std::int64_t, std::int64_t)>;

/// Runs the ensemble of one parameter set. Bit-identical for any thread count. When the
/// ensemble is mirror symmetric only the releases x0 <= 0 are simulated: the engine is exactly
/// mirror symmetric, so each result also stands for its mirror image.
EnsembleResult run_ensemble(const Params& params, const EnsembleOptions& options, const Progress& progress = {});

// ---- Chunks: the unit of work, shared by run_sweep and by runs over many processes ----

/// Number of chunks of an ensemble of N samples, min(256, ceil(N / 16)): the unit of work and
/// of the fixed-order reduction (docs/model.md §8). It depends on N only, never on threads or
/// processes, which is what makes every split of the work give the same bits.
std::int64_t chunk_count(std::int64_t samples);

/// Partial statistics of one chunk of an ensemble: a plain value (no pointers into the run),
/// which may be computed anywhere, copied between processes, and reduced later in chunk order.
struct ChunkStats {
  std::array<Accumulator, observable_count> acc{};  ///< per observable, samples in index order (exit ones: exited only)
  std::int64_t exited = 0, rest = 0, trapped = 0;   ///< status counts, mirror images included
  std::int64_t capped = 0, stalled = 0;             ///< among `trapped`: the collision cap, the Zeno guard
  std::int64_t total_collisions = 0;                ///< collisions of the chunk's samples and their mirror images
  std::int64_t simulated_collisions = 0;            ///< collisions actually computed (mirror halving)
  Wear wear;                                        ///< summed wear record, not yet per sample (wear_bins > 0)
  std::vector<Sample> samples;                      ///< keep_samples: the simulated samples, in index order
};

/// Computes chunk `chunk` (0 <= chunk < chunk_count(options.samples)) of the ensemble of
/// `params` on the calling thread. Where the ensemble is mirror symmetric a chunk holds only
/// releases x0 <= 0 (and counts their mirror images).
ChunkStats run_chunk(const Params& params, const EnsembleOptions& options, std::int64_t chunk);

/// One work unit of a sweep: chunk `chunk` of the ensemble of grid point `point`.
struct ChunkId {
  std::size_t point = 0;   ///< index into the points of the sweep
  std::int64_t chunk = 0;  ///< 0 <= chunk < chunk_count(options.samples)
};

/// Computes the chunks `ids` of the points' ensembles in parallel (options.threads); results in
/// the order of `ids`, each the same, bit for bit, as run_chunk's. Honours options.cancel.
/// Points among them that differ only in mu run the same chunk as a chain, as in run_sweep: a
/// release runs again at a larger mu only if its trajectory slid (docs/model.md §4), so
/// simulated_collisions counts only those.
std::vector<ChunkStats> run_chunks(const std::vector<Params>& points, const EnsembleOptions& options,
                                   const std::vector<ChunkId>& ids);

/// Folds `next`, the chunk that follows those already folded into `prefix` (chunks 0 .. c-1 of
/// one ensemble, or none: a default ChunkStats), into it: statistics merged (Chan), samples
/// appended. Folding the chunks one by one from chunk 0 is what reduce_chunks does, so a prefix
/// folded anywhere (on another process, say) stands for its chunks, bit for bit.
void fold_chunk(ChunkStats& prefix, ChunkStats next);

/// Reduces the chunks of one ensemble, in chunk-index order and covering every chunk, into its
/// result: chunks[i] is one chunk (run_chunk), except that chunks[0] may be the fold of chunks
/// 0 .. k (fold_chunk). The same bits as run_ensemble, whatever thread or process computed each
/// chunk and in whatever order.
EnsembleResult reduce_chunks(const Params& params, const EnsembleOptions& options, std::vector<ChunkStats> chunks);

/// Called once per finished point with its index and result; from one thread at a time, in
/// completion order (not index order).
using PointDone = std::function<void(std::size_t, const EnsembleResult&)>;

/// Runs one ensemble per parameter set, all in one parallel pool of chunks (run_chunk, then
/// reduce_chunks as soon as a point's chunks are done); results in input order. Each point's
/// result is the same, bit for bit, as run_ensemble of that point alone.
std::vector<EnsembleResult> run_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                      const Progress& progress = {}, const PointDone& point_done = {});

/// The chains run_sweep runs together: lists of the points' indices, each of points that differ
/// only in mu, in ascending mu (at most 8; a point alone if no other qualifies), the chains in
/// the order of their first point. An MPI run deals a chain's chunks chunk by chunk, so that
/// run_chunks gets the members' same chunk together.
std::vector<std::vector<std::size_t>> friction_chains(const std::vector<Params>& points, const EnsembleOptions& options);

/// Number of threads used for `threads` = 0 (all cores) or the value itself.
int resolve_threads(int threads);

/// The trajectory of the mirror-image release: the same observables with x, u and spin negated.
Trajectory mirrored(Trajectory t);

}  // namespace funnel
