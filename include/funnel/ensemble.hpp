// Ensembles over release positions (MODEL.md §8) and sweeps over parameter grids, in parallel.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/params.hpp"
#include "funnel/stats.hpp"

namespace funnel {

/// Distribution of the release positions.
enum class ReleaseDist {
  Line,  ///< 2D funnel: x0_k = L (-1 + (2k+1)/N)
  Disk,  ///< axisymmetric cone: r_k = L sqrt((k + 1/2)/N), uniform over the disk
};

/// "line" or "disk".
std::string_view to_string(ReleaseDist dist);
/// Parses "line" or "disk"; nullopt otherwise.
std::optional<ReleaseDist> parse_release_dist(std::string_view text);

/// Release position x0/L of sample k of N, in (-1, 1).
double release_fraction(ReleaseDist dist, std::int64_t k, std::int64_t n);

/// How to run an ensemble.
struct EnsembleOptions {
  std::int64_t samples = default_samples;  ///< N >= 1
  ReleaseDist dist = ReleaseDist::Line;
  int threads = 0;                          ///< 0: all cores
  bool keep_samples = false;                ///< also return every trajectory (O(N) memory)
};

/// Per-sample outputs of an ensemble, kept only on request.
struct Sample {
  double fraction = 0.0;  ///< x0 / L
  Trajectory trajectory;  ///< its observables
};

/// Statistics of an ensemble.
struct EnsembleResult {
  std::int64_t samples = 0;
  Summary duration, impulse, normal_impulse, energy_loss, collisions, edge_collisions, contact_time;
  std::int64_t exited = 0, rest = 0, trapped = 0;  ///< count of each status
  std::int64_t total_collisions = 0;               ///< summed over the samples
  std::int64_t simulated_collisions = 0;           ///< collisions actually computed (mirror halving)
  std::vector<Sample> per_sample;                  ///< filled when keep_samples
};

/// Called with (finished work units, total work units); from one thread at a time.
using Progress = std::function<void(std::int64_t, std::int64_t)>;

/// Runs the ensemble of one parameter set. Bit-identical for any thread count. For the line
/// distribution only the releases x0 <= 0 are simulated: the engine is exactly mirror
/// symmetric, so each result also stands for its mirror image.
EnsembleResult run_ensemble(const Params& params, const EnsembleOptions& options, const Progress& progress = {});

/// Called once per finished point with its index and result; from one thread at a time, in
/// completion order (not index order).
using PointDone = std::function<void(std::size_t, const EnsembleResult&)>;

/// Runs one ensemble per parameter set, all in one parallel pool; results in input order. Each
/// point's result is the same, bit for bit, as run_ensemble of that point alone.
std::vector<EnsembleResult> run_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                      const Progress& progress = {}, const PointDone& point_done = {});

/// Number of threads used for `threads` = 0 (all cores) or the value itself.
int resolve_threads(int threads);

}  // namespace funnel
