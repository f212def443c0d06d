// Parallel ensembles and sweeps with a fixed reduction order (deterministic for any thread count).
#include "funnel/ensemble.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "funnel/geometry.hpp"

namespace funnel {

std::string_view to_string(ReleaseDist dist) { return dist == ReleaseDist::Line ? "line" : "disk"; }

std::optional<ReleaseDist> parse_release_dist(std::string_view text) {
  if (text == "line") return ReleaseDist::Line;
  if (text == "disk") return ReleaseDist::Disk;
  return std::nullopt;
}

double release_fraction(ReleaseDist dist, std::int64_t k, std::int64_t n) {
  const double kk = static_cast<double>(k);
  const double nn = static_cast<double>(n);
  // (2k + 1 - N)/N equals -1 + (2k+1)/N; the integer numerator makes samples k and N-1-k
  // exact mirror images.
  if (dist == ReleaseDist::Line) return (2.0 * kk + 1.0 - nn) / nn;
  return std::sqrt((kk + 0.5) / nn);
}

int resolve_threads(int threads) { return threads > 0 ? threads : std::max(1, omp_get_num_procs()); }

namespace {

/// Work units per ensemble: the unit of scheduling and of the fixed-order reduction. A fixed
/// cap keeps the memory of an ensemble independent of N; the partition depends on N only, never
/// on the thread count, so the reduction order (and every bit of the result) is fixed.
constexpr std::int64_t max_chunks = 256;
constexpr std::int64_t min_chunk = 16;

/// Statistics of one block of samples.
struct BlockStats {
  Accumulator duration, impulse, normal_impulse, energy_loss, collisions, edge_collisions, contact_time;
  std::int64_t exited = 0, rest = 0, trapped = 0, total_collisions = 0, simulated_collisions = 0;

  void add(const Trajectory& t) {
    duration.add(t.duration);
    impulse.add(t.impulse);
    normal_impulse.add(t.normal_impulse);
    energy_loss.add(t.energy_loss);
    collisions.add(static_cast<double>(t.collisions));
    edge_collisions.add(static_cast<double>(t.edge_collisions));
    contact_time.add(t.contact_time);
    exited += t.status == Status::Exited;
    rest += t.status == Status::Rest;
    trapped += t.status == Status::Trapped;
    total_collisions += t.collisions;
  }

  void merge(const BlockStats& o) {
    duration.merge(o.duration);
    impulse.merge(o.impulse);
    normal_impulse.merge(o.normal_impulse);
    energy_loss.merge(o.energy_loss);
    collisions.merge(o.collisions);
    edge_collisions.merge(o.edge_collisions);
    contact_time.merge(o.contact_time);
    exited += o.exited;
    rest += o.rest;
    trapped += o.trapped;
    total_collisions += o.total_collisions;
    simulated_collisions += o.simulated_collisions;
  }
};

EnsembleResult to_result(const BlockStats& s, std::int64_t samples) {
  EnsembleResult r;
  r.samples = samples;
  r.duration = summarize(s.duration);
  r.impulse = summarize(s.impulse);
  r.normal_impulse = summarize(s.normal_impulse);
  r.energy_loss = summarize(s.energy_loss);
  r.collisions = summarize(s.collisions);
  r.edge_collisions = summarize(s.edge_collisions);
  r.contact_time = summarize(s.contact_time);
  r.exited = s.exited;
  r.rest = s.rest;
  r.trapped = s.trapped;
  r.total_collisions = s.total_collisions;
  r.simulated_collisions = s.simulated_collisions;
  return r;
}

/// The trajectory of the mirror-image release: same observables, mirrored final state.
Trajectory mirrored(Trajectory t) {
  t.final_state.r.x = -t.final_state.r.x;
  t.final_state.v.x = -t.final_state.v.x;
  t.final_state.omega = -t.final_state.omega;
  return t;
}

}  // namespace

std::vector<EnsembleResult> run_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                      const Progress& progress, const PointDone& point_done) {
  const std::int64_t n = options.samples;
  // The engine is exactly mirror symmetric and the line distribution's samples k and N-1-k
  // are exact mirror images, so only the first half (and the middle one) is simulated.
  const bool mirror = options.dist == ReleaseDist::Line;
  const std::int64_t n_unique = mirror ? (n + 1) / 2 : n;
  const std::int64_t blocks_per_point = std::min(max_chunks, (n_unique + min_chunk - 1) / min_chunk);
  const std::int64_t n_points = static_cast<std::int64_t>(points.size());
  const std::int64_t n_tasks = n_points * blocks_per_point;

  std::vector<Geometry> geometries;
  geometries.reserve(points.size());
  for (const Params& p : points) geometries.push_back(make_geometry(p));

  std::vector<EnsembleResult> results(points.size());
  if (options.keep_samples) {
    for (auto& r : results) r.per_sample.resize(static_cast<std::size_t>(n));
  }
  std::vector<BlockStats> blocks(static_cast<std::size_t>(n_tasks));
  std::vector<std::int64_t> pending(points.size(), blocks_per_point);  // chunks left per point
  std::int64_t finished = 0;

  // Reduces a point's chunks in index order: the same bits whatever the thread count.
  auto reduce = [&](std::int64_t point) {
    BlockStats total;
    for (std::int64_t b = 0; b < blocks_per_point; ++b) {
      total.merge(blocks[static_cast<std::size_t>(point * blocks_per_point + b)]);
    }
    EnsembleResult& r = results[static_cast<std::size_t>(point)];
    std::vector<Sample> kept = std::move(r.per_sample);
    r = to_result(total, n);
    r.per_sample = std::move(kept);
  };

#pragma omp parallel for schedule(dynamic, 1) num_threads(resolve_threads(options.threads))
  for (std::int64_t task = 0; task < n_tasks; ++task) {
    const std::int64_t point = task / blocks_per_point;
    const std::int64_t chunk = task % blocks_per_point;
    const std::int64_t first = chunk * n_unique / blocks_per_point;
    const std::int64_t last = (chunk + 1) * n_unique / blocks_per_point;
    const Params& params = points[static_cast<std::size_t>(point)];
    const Geometry& g = geometries[static_cast<std::size_t>(point)];
    BlockStats& stats = blocks[static_cast<std::size_t>(task)];
    for (std::int64_t k = first; k < last; ++k) {
      const double fraction = release_fraction(options.dist, k, n);
      const Trajectory t = simulate_release(params, g, fraction);
      const std::int64_t partner = mirror ? n - 1 - k : k;
      stats.add(t);
      stats.simulated_collisions += t.collisions;
      if (partner != k) stats.add(t);
      if (options.keep_samples) {
        auto& kept = results[static_cast<std::size_t>(point)].per_sample;
        kept[static_cast<std::size_t>(k)] = {fraction, t};
        if (partner != k) kept[static_cast<std::size_t>(partner)] = {-fraction, mirrored(t)};
      }
    }
#pragma omp critical(funnel_sweep)
    {
      if (--pending[static_cast<std::size_t>(point)] == 0) {
        reduce(point);
        if (point_done) point_done(static_cast<std::size_t>(point), results[static_cast<std::size_t>(point)]);
      }
      ++finished;
      if (progress) progress(finished, n_tasks);
    }
  }
  return results;
}

EnsembleResult run_ensemble(const Params& params, const EnsembleOptions& options, const Progress& progress) {
  return std::move(run_sweep({params}, options, progress).front());
}

}  // namespace funnel
