// Parallel ensembles and sweeps with a fixed reduction order (deterministic for any thread count).
#include "funnel/ensemble.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "funnel/geometry.hpp"
#include "funnel/random.hpp"

namespace funnel {

std::string_view to_string(ReleaseDist dist) {
  switch (dist) {
    case ReleaseDist::Line: return "line";
    case ReleaseDist::Disk: return "disk";
    case ReleaseDist::Uniform: return "uniform";
    case ReleaseDist::Gaussian: return "gaussian";
  }
  return "?";
}

std::optional<ReleaseDist> parse_release_dist(std::string_view text) {
  for (const ReleaseDist d : {ReleaseDist::Line, ReleaseDist::Disk, ReleaseDist::Uniform, ReleaseDist::Gaussian}) {
    if (text == to_string(d)) return d;
  }
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

std::optional<ParamError> validate(const EnsembleOptions& o) {
  auto err = [](const char* name, double v, const char* range) {
    return ParamError{name, format_number(v), range};
  };
  if (!(o.samples >= 1 && o.samples <= 1'000'000'000)) {
    return ParamError{"samples", std::to_string(o.samples), "an integer 1 <= samples <= 10^9"};
  }
  if (!(o.threads >= 0 && o.threads <= 1024)) {
    return ParamError{"threads", std::to_string(o.threads), "an integer 0 <= threads <= 1024 (0 = all cores)"};
  }
  if (!(o.release_mean > -1.0 && o.release_mean < 1.0)) return err("release", o.release_mean, "-1 < release < 1 (x0/L)");
  if (!(o.release_sd > 0.0 && o.release_sd <= 10.0)) return err("release-sd", o.release_sd, "0 < release-sd <= 10 (units of L)");
  if (!(o.velocity_sd >= 0.0 && o.velocity_sd <= 1e3)) {
    return err("velocity-sd", o.velocity_sd, "0 <= velocity-sd <= 1000 (units of sqrt(gH))");
  }
  if (!(o.wear_bins >= 0 && o.wear_bins <= 1'000'000)) {
    return ParamError{"wear-bins", std::to_string(o.wear_bins), "an integer 0 <= wear-bins <= 10^6 (0 = no wear record)"};
  }
  return std::nullopt;
}

namespace {

// Streams of the counter-based generator: one per random quantity of a sample.
constexpr std::uint64_t stream_position = 0;   // uniform x0/L
constexpr std::uint64_t stream_velocity_u = 1;
constexpr std::uint64_t stream_velocity_v = 2;
constexpr std::uint64_t stream_gaussian = 16;  // + attempt: truncated normal x0/L
constexpr int max_gaussian_attempts = 10000;

/// Work units per ensemble: the unit of scheduling and of the fixed-order reduction. A fixed
/// cap keeps the memory of an ensemble independent of N; the partition depends on N only, never
/// on the thread count, so the reduction order (and every bit of the result) is fixed.
constexpr std::int64_t max_chunks = 256;
constexpr std::int64_t min_chunk = 16;

/// Statistics of one block of samples.
struct BlockStats {
  std::array<Accumulator, observable_count> acc;
  std::int64_t exited = 0, rest = 0, trapped = 0, total_collisions = 0, simulated_collisions = 0;
  Wear wear;

  void add(const Trajectory& t) {
    for (const ObservableInfo& o : observables()) {
      if (o.exited_only && t.status != Status::Exited) continue;
      acc[static_cast<std::size_t>(o.id)].add(value(t, o.id));
    }
    exited += t.status == Status::Exited;
    rest += t.status == Status::Rest;
    trapped += t.status == Status::Trapped;
    total_collisions += t.collisions;
  }

  void merge(const BlockStats& o) {
    for (std::size_t i = 0; i < acc.size(); ++i) acc[i].merge(o.acc[i]);
    exited += o.exited;
    rest += o.rest;
    trapped += o.trapped;
    total_collisions += o.total_collisions;
    simulated_collisions += o.simulated_collisions;
    wear.merge(o.wear);
  }
};

EnsembleResult to_result(const BlockStats& s, std::int64_t samples) {
  EnsembleResult r;
  r.samples = samples;
  for (std::size_t i = 0; i < s.acc.size(); ++i) r.stats[i] = summarize(s.acc[i]);
  r.exited = s.exited;
  r.rest = s.rest;
  r.trapped = s.trapped;
  r.total_collisions = s.total_collisions;
  r.simulated_collisions = s.simulated_collisions;
  r.wear = s.wear;
  r.wear.scale(1.0 / static_cast<double>(samples));
  return r;
}

/// The mirror image x -> -x of a state. Written 0 - x, not -x: a zero stays +0, as the direct
/// simulation of the mirror release has it (a particle that falls straight through keeps u = +0).
State mirror_state(State s) {
  s.r.x = 0.0 - s.r.x;
  s.v.x = 0.0 - s.v.x;
  s.omega = 0.0 - s.omega;
  return s;
}

}  // namespace

double sample_fraction(const EnsembleOptions& o, std::int64_t k) {
  const auto index = static_cast<std::uint64_t>(k);
  switch (o.dist) {
    case ReleaseDist::Line:
    case ReleaseDist::Disk: return release_fraction(o.dist, k, o.samples);
    case ReleaseDist::Uniform: return 2.0 * uniform01(o.seed, stream_position, index) - 1.0;
    case ReleaseDist::Gaussian:
      // Truncated to (-1, 1) by drawing again; with |mean| < 1 and sd <= 10 a draw falls
      // inside with probability > 7%, so the cap is never reached in practice.
      for (int attempt = 0; attempt < max_gaussian_attempts; ++attempt) {
        const double x = o.release_mean + o.release_sd * standard_normal(o.seed, stream_gaussian + attempt, index);
        if (x > -1.0 && x < 1.0) return x;
      }
      return o.release_mean;
  }
  return 0.0;
}

State sample_release(const Params& params, const Geometry& g, const EnsembleOptions& options, std::int64_t k) {
  State s = release_state(params, g, sample_fraction(options, k));
  if (options.velocity_sd > 0.0) {
    const auto index = static_cast<std::uint64_t>(k);
    s.v.x += options.velocity_sd * standard_normal(options.seed, stream_velocity_u, index);
    s.v.y += options.velocity_sd * standard_normal(options.seed, stream_velocity_v, index);
  }
  return s;
}

bool is_random(const EnsembleOptions& o) {
  return o.dist == ReleaseDist::Uniform || o.dist == ReleaseDist::Gaussian || o.velocity_sd > 0.0;
}

bool mirror_symmetric(const Params& params, const EnsembleOptions& options) {
  return options.dist == ReleaseDist::Line && params.release_u == 0.0 && params.release_spin == 0.0 &&
         options.velocity_sd == 0.0;
}

Trajectory mirrored(Trajectory t) {
  t.final_state = mirror_state(t.final_state);
  t.exit_state = mirror_state(t.exit_state);
  return t;
}

std::vector<EnsembleResult> run_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                      const Progress& progress, const PointDone& point_done) {
  const std::int64_t n = options.samples;
  const std::int64_t n_points = static_cast<std::int64_t>(points.size());

  // Per point: the engine is exactly mirror symmetric and the line distribution's samples k and
  // N-1-k are exact mirror images, so where the releases are symmetric only the first half (and
  // the middle one) is simulated.
  std::vector<Geometry> geometries;
  std::vector<char> mirror;
  geometries.reserve(points.size());
  for (const Params& p : points) {
    geometries.push_back(make_geometry(p));
    mirror.push_back(mirror_symmetric(p, options) ? 1 : 0);
  }
  auto unique_of = [&](std::int64_t point) { return mirror[static_cast<std::size_t>(point)] ? (n + 1) / 2 : n; };
  // The same partition for every point (that of the symmetric case when any point is).
  const std::int64_t blocks_per_point = std::min(max_chunks, (n + min_chunk - 1) / min_chunk);
  const std::int64_t n_tasks = n_points * blocks_per_point;

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
    if (mirror[static_cast<std::size_t>(point)]) {
      // The samples come in exact mirror pairs (and the middle one, at x0 = 0, falls straight
      // through): the mean of an observable that changes sign is exactly 0, where the running
      // mean would leave rounding residues of ~1e-20.
      for (const ObservableInfo& o : observables()) {
        if (o.mirror_odd) r.stats[static_cast<std::size_t>(o.id)].mean = 0.0;
      }
    }
  };

#pragma omp parallel for schedule(dynamic, 1) num_threads(resolve_threads(options.threads))
  for (std::int64_t task = 0; task < n_tasks; ++task) {
    if (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed)) continue;
    const std::int64_t point = task / blocks_per_point;
    const std::int64_t chunk = task % blocks_per_point;
    const std::int64_t n_unique = unique_of(point);
    const std::int64_t first = chunk * n_unique / blocks_per_point;
    const std::int64_t last = (chunk + 1) * n_unique / blocks_per_point;
    const Params& params = points[static_cast<std::size_t>(point)];
    const Geometry& g = geometries[static_cast<std::size_t>(point)];
    const bool halved = mirror[static_cast<std::size_t>(point)] != 0;
    BlockStats& stats = blocks[static_cast<std::size_t>(task)];
    Wear wear = Wear::make(g, options.wear_bins);
    stats.wear = wear;
    for (std::int64_t k = first; k < last; ++k) {
      const double fraction = sample_fraction(options, k);
      const State release = sample_release(params, g, options, k);
      if (options.wear_bins > 0) wear = Wear::make(g, options.wear_bins);
      const Trajectory t = simulate(params, g, release, nullptr, options.wear_bins > 0 ? &wear : nullptr);
      const std::int64_t partner = halved ? n - 1 - k : k;
      stats.add(t);
      stats.simulated_collisions += t.collisions;
      stats.wear.merge(wear);
      if (partner != k) {
        const Trajectory m = mirrored(t);
        stats.add(m);
        stats.wear.merge(wear.mirrored());
      }
      if (options.keep_samples) {
        auto& kept = results[static_cast<std::size_t>(point)].per_sample;
        kept[static_cast<std::size_t>(k)] = {fraction, release, t};
        if (partner != k) kept[static_cast<std::size_t>(partner)] = {-fraction, mirror_state(release), mirrored(t)};
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
