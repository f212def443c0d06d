// Computing the data of each figure of the paper, and checking the paper's claim on it: the
// module `funnel paper` and Python's funnel.paper_figure() both call (docs/paper.md).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "funnel/ensemble.hpp"
#include "funnel/paper/cases.hpp"

namespace funnel::paper {

/// What runs a batch of ensembles: run_sweep's signature and results (the CLI passes one that
/// spreads the work over MPI ranks; bit-identical results either way).
using SweepRunner = std::function<std::vector<EnsembleResult>(const std::vector<Params>&, const EnsembleOptions&,
                                                              const Progress&)>;

/// Ensembles requested by all theta-sweep figures, de-duplicated and run as one parallel batch.
class SweepCache {
 public:
  /// A cache whose ensembles (and every other figure's) run through `runner` (default: run_sweep
  /// in this process).
  explicit SweepCache(SweepRunner runner = {});
  /// Asks for the ensemble of `params` with `samples` releases from `dist`.
  void request(const Params& params, ReleaseDist dist, std::int64_t samples);
  /// Runs every requested ensemble not yet computed.
  void run(int threads, const Progress& progress);
  /// The runner of the batches.
  const SweepRunner& runner() const { return runner_; }
  /// A computed ensemble; throws std::out_of_range if it was never requested.
  const EnsembleResult& get(const Params& params, ReleaseDist dist, std::int64_t samples) const;
  /// Number of distinct ensembles requested.
  std::size_t size() const { return entries_.size(); }
  /// Collisions computed by all ensembles that have run (mirror halving included).
  std::int64_t simulated_collisions() const;

 private:
  using Key = std::tuple<std::string, int, std::int64_t>;
  static Key key(const Params& params, ReleaseDist dist, std::int64_t samples);
  /// The parameters that are run for `params`: beta0 = 0 without friction (mu = 0), where beta0
  /// changes no bit of any result, so that Figs. 3-5's three beta0 panels share their mu = 0 curve.
  static Params canonical(const Params& params);
  struct Entry {
    Params params;
    ReleaseDist dist;
    std::int64_t samples;
    EnsembleResult result;
    bool done = false;
  };
  std::map<Key, Entry> entries_;
  SweepRunner runner_;
};

/// What one figure writes: its CSV, extra metadata, and the check of the paper's claim.
struct FigureData {
  std::string csv;
  nlohmann::ordered_json extra = nlohmann::ordered_json::object();  ///< merged into figNN.json
  nlohmann::ordered_json check;  ///< {"claim", "measured", "holds"}
};

/// Adds the ensembles a theta-sweep figure needs to the cache (nothing for other kinds).
void request_sweeps(const FigureSpec& fig, SweepCache& cache);

/// The collisions of the theta-sweep batch attributed to each figure (by id): the collisions
/// simulated for each ensemble, split evenly among the figures that use it, so that the shares
/// add up to cache.simulated_collisions(). Figures of other kinds get 0.
std::map<std::string, double> attributed_collisions(const std::vector<FigureSpec>& figs, const SweepCache& cache);

/// Computes a figure (theta sweeps are read from the cache, which must have run; release scans
/// run through its runner); `progress` hears of the figure's own runs (release scans,
/// closed-funnel ensembles). Throws InputError for a definition it cannot compute.
FigureData compute_figure(const FigureSpec& fig, const SweepCache& cache, int threads, const Progress& progress = {});

/// One figure alone: its sweeps requested, run and computed (what Python's paper_figure calls).
FigureData compute_figure(const FigureSpec& fig, int threads, const Progress& progress = {});

}  // namespace funnel::paper
