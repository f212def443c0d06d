// Parallel ensembles and sweeps with a fixed reduction order (deterministic for any thread count).
#include "funnel/ensemble.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <iterator>
#include <map>
#include <utility>

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
  // An ensemble holds a record per chunk (up to 256) until its point is complete, 48 bytes a bin:
  // 10^6 bins took 12 GB; 10^4 bins (each 10^-4 of a wall, far below the ball's size) take 123 MB.
  if (!(o.wear_bins >= 0 && o.wear_bins <= 10'000)) {
    return ParamError{"wear-bins", std::to_string(o.wear_bins), "an integer 0 <= wear-bins <= 10^4 (0 = no wear record)"};
  }
  return std::nullopt;
}

namespace {

/// The funnel of `params` is its own mirror image (x -> -x): the paper's V without building it.
bool symmetric_funnel(const Params& params) { return params.plain_v() || make_funnel(params).symmetric; }

}  // namespace

std::optional<ParamError> validate(const Params& params, const EnsembleOptions& options) {
  if (options.dist != ReleaseDist::Disk || symmetric_funnel(params)) return std::nullopt;
  return ParamError{"release-dist", "disk",
                    "line, uniform or gaussian in a funnel that is not mirror symmetric (disk releases are the "
                    "cone's, at x0 = r > 0 only: they would never release over its left half)"};
}

namespace {

// Streams of the counter-based generator: one per random quantity of a sample.
constexpr std::uint64_t stream_position = 0;   // uniform x0/L
constexpr std::uint64_t stream_velocity_u = 1;
constexpr std::uint64_t stream_velocity_v = 2;
constexpr std::uint64_t stream_gaussian = 16;  // + attempt: truncated normal x0/L
constexpr int max_gaussian_attempts = 10000;

/// Chunks per ensemble (chunk_count): the unit of scheduling and of the fixed-order reduction. A
/// fixed cap keeps the memory of an ensemble independent of N; the partition depends on N only,
/// never on the thread or process count, so the reduction order (and every bit) is fixed.
constexpr std::int64_t max_chunks = 256;
constexpr std::int64_t min_chunk = 16;

/// Adds one trajectory to a chunk's statistics.
void add(ChunkStats& s, const Trajectory& t) {
  // Every observable in table order, the exit ones (ExitX onwards) for exited samples only: a
  // plain index loop, which the compiler unrolls into straight code (a walk over the observable
  // table cost half of the statistics' time).
  constexpr auto first_exit = static_cast<std::size_t>(Observable::ExitX);
  const std::size_t count = t.status == Status::Exited ? observable_count : first_exit;
  for (std::size_t i = 0; i < count; ++i) s.acc[i].add(value(t, static_cast<Observable>(i)));
  s.exited += t.status == Status::Exited;
  s.rest += t.status == Status::Rest;
  s.trapped += t.status == Status::Trapped;
  s.capped += t.capped;
  s.stalled += t.stalled;
  s.total_collisions += t.collisions;
}

/// Merges chunk `o` into `s` (Chan's formula: the result depends on the order of merges).
void merge(ChunkStats& s, const ChunkStats& o) {
  for (std::size_t i = 0; i < s.acc.size(); ++i) s.acc[i].merge(o.acc[i]);
  s.exited += o.exited;
  s.rest += o.rest;
  s.trapped += o.trapped;
  s.capped += o.capped;
  s.stalled += o.stalled;
  s.total_collisions += o.total_collisions;
  s.simulated_collisions += o.simulated_collisions;
  s.wear.merge(o.wear);
}

EnsembleResult to_result(const ChunkStats& s, std::int64_t samples) {
  EnsembleResult r;
  r.samples = samples;
  for (std::size_t i = 0; i < s.acc.size(); ++i) r.stats[i] = summarize(s.acc[i]);
  r.exited = s.exited;
  r.rest = s.rest;
  r.trapped = s.trapped;
  r.capped = s.capped;
  r.stalled = s.stalled;
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

State sample_release(const Params& params, const Geometry&, const EnsembleOptions& options, std::int64_t k) {
  return sample_release(params, make_funnel(params), options, k);
}

State sample_release(const Params& params, const Funnel& f, const EnsembleOptions& options, std::int64_t k) {
  State s = release_state(params, f, sample_fraction(options, k));
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
         options.velocity_sd == 0.0 && symmetric_funnel(params);
}

Trajectory mirrored(Trajectory t) {
  t.final_state = mirror_state(t.final_state);
  t.exit_state = mirror_state(t.exit_state);
  return t;
}

std::int64_t chunk_count(std::int64_t samples) {
  return std::max<std::int64_t>(1, std::min(max_chunks, (samples + min_chunk - 1) / min_chunk));
}

namespace {

/// Samples simulated: where the releases are symmetric only the first half and the middle one
/// (the engine is exactly mirror symmetric and the line distribution's samples k and N-1-k are
/// exact mirror images).
std::int64_t unique_samples(bool halved, std::int64_t n) { return halved ? (n + 1) / 2 : n; }

/// The simulated samples [first, last) of chunk `chunk`: a partition that depends on N (and on
/// the mirror symmetry) only.
std::pair<std::int64_t, std::int64_t> chunk_range(bool halved, std::int64_t n, std::int64_t chunk) {
  const std::int64_t n_unique = unique_samples(halved, n);
  const std::int64_t chunks = chunk_count(n);
  return {chunk * n_unique / chunks, (chunk + 1) * n_unique / chunks};
}

/// Samples a task runs together at least (several chunks of one point when chunks are small):
/// enough to keep the lanes of the batched path busy as trajectories of very different lengths
/// end (src/engine.cpp), as long as every thread still gets tasks_per_thread tasks.
constexpr std::int64_t min_batch = 2048;
constexpr std::int64_t tasks_per_thread = 8;

/// True once the run is cancelled (Ctrl-C in Python): the work under way stops, its results
/// incomplete, and is not recorded.
bool cancelled(const EnsembleOptions& options) {
  return options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed);
}

/// Releases run together at most: the memory of a task stays bounded whatever N.
constexpr std::int64_t max_block = 4096;

/// Chunks [c0, c1) of a chain of points (`points`, with their funnels): one point, or points
/// that differ only in mu, in ascending mu (friction_chains). Returns each point's chunks, in
/// chain order, each with its samples in index order (the one computation behind run_chunk, a
/// chain of one, and run_sweep). Without a wear record the trajectories run together, in blocks
/// of at most max_block releases (simulate_many: the batched path of a V), and along a chain a
/// release runs again only if its trajectory at the point before slid: otherwise it is the same
/// trajectory (Trajectory::slid, docs/model.md §4). Each chunk's statistics are the same either
/// way.
std::vector<std::vector<ChunkStats>> compute_chain(std::span<const Params* const> points,
                                                   std::span<const Funnel* const> funnels, const EnsembleOptions& options,
                                                   bool halved, std::int64_t c0, std::int64_t c1) {
  const std::int64_t n = options.samples;
  const Params& first = *points.front();
  const Funnel& g = *funnels.front();  // the releases are the same along a chain
  const std::size_t members = points.size();
  std::vector<std::vector<ChunkStats>> out(members, std::vector<ChunkStats>(static_cast<std::size_t>(c1 - c0)));
  for (std::size_t m = 0; m < members; ++m) {
    for (std::int64_t c = c0; c < c1; ++c) {
      ChunkStats& stats = out[m][static_cast<std::size_t>(c - c0)];
      stats.wear = Wear::make(*funnels[m], options.wear_bins);
      if (options.keep_samples) {
        const auto [begin, end] = chunk_range(halved, n, c);
        stats.samples.reserve(static_cast<std::size_t>(std::max<std::int64_t>(0, end - begin)));
      }
    }
  }
  // Adds sample k's trajectory t (`computed`: run here, not reused) to chunk c of point m.
  auto add_sample = [&](std::size_t m, std::int64_t c, std::int64_t k, const State& release, const Trajectory& t,
                        bool computed, const Wear* wear) {
    ChunkStats& stats = out[m][static_cast<std::size_t>(c - c0)];
    add(stats, t);
    if (computed) stats.simulated_collisions += t.collisions;
    if (wear != nullptr) stats.wear.merge(*wear);
    if (const std::int64_t partner = halved ? n - 1 - k : k; partner != k) {
      add(stats, mirrored(t));
      if (wear != nullptr) stats.wear.merge(*wear, true);
    }
    if (options.keep_samples) stats.samples.push_back({sample_fraction(options, k), release, t});
  };
  const std::int64_t first_sample = chunk_range(halved, n, c0).first, last_sample = chunk_range(halved, n, c1 - 1).second;

  if (options.wear_bins > 0) {
    // With a wear record: one trajectory at a time, each with its own record (no chain), one
    // record per point cleared between them (a fresh one, and its mirror image's copy, cost
    // more than the trajectory at 10^4 bins).
    std::vector<Wear> wears;
    for (std::size_t m = 0; m < members; ++m) wears.push_back(Wear::make(*funnels[m], options.wear_bins));
    std::int64_t c = c0;
    for (std::int64_t k = first_sample; k < last_sample; ++k) {
      while (k >= chunk_range(halved, n, c).second) ++c;
      if (cancelled(options)) return out;  // incomplete: the caller discards it
      const State release = sample_release(first, g, options, k);
      for (std::size_t m = 0; m < members; ++m) {
        Wear& wear = wears[m];
        wear.clear();
        add_sample(m, c, k, release, simulate(*points[m], *funnels[m], release, nullptr, &wear), true, &wear);
      }
    }
    return out;
  }

  // Kept by each thread from task to task: a block's buffers (half a megabyte of trajectories)
  // allocated afresh for every task came from the kernel each time, page by page (2% of Fig. 3's
  // time in page faults). Every element is written before it is read.
  thread_local std::vector<State> releases, subset;
  thread_local std::vector<Trajectory> runs, subset_runs;
  thread_local std::vector<std::size_t> rerun;
  thread_local std::vector<char> computed;
  for (std::int64_t block_first = first_sample; block_first < last_sample; block_first += max_block) {
    if (cancelled(options)) return out;  // incomplete: the caller discards it
    const std::int64_t block_last = std::min(last_sample, block_first + max_block);
    releases.clear();
    for (std::int64_t b = block_first; b < block_last; ++b) releases.push_back(sample_release(first, g, options, b));
    for (std::size_t m = 0; m < members; ++m) {
      if (m == 0) {
        // The chain's first point runs every release.
        runs.resize(releases.size());
        simulate_many(*points[m], *funnels[m], releases, runs, options.cancel);
        if (cancelled(options)) return out;
        computed.assign(releases.size(), 1);
      } else {
        // The next points run again only the releases whose trajectory slid.
        rerun.clear();
        subset.clear();
        for (std::size_t i = 0; i < releases.size(); ++i) {
          if (runs[i].slid) {
            rerun.push_back(i);
            subset.push_back(releases[i]);
          }
        }
        subset_runs.resize(subset.size());
        simulate_many(*points[m], *funnels[m], subset, subset_runs, options.cancel);
        if (cancelled(options)) return out;
        computed.assign(releases.size(), 0);
        for (std::size_t j = 0; j < rerun.size(); ++j) {
          runs[rerun[j]] = subset_runs[j];
          computed[rerun[j]] = 1;
        }
      }
      std::int64_t c = c0;
      for (std::int64_t k = block_first; k < block_last; ++k) {
        while (k >= chunk_range(halved, n, c).second) ++c;
        const auto i = static_cast<std::size_t>(k - block_first);
        add_sample(m, c, k, releases[i], runs[i], computed[i] != 0, nullptr);
      }
    }
  }
  return out;
}

}  // namespace

ChunkStats run_chunk(const Params& params, const EnsembleOptions& options, std::int64_t chunk) {
  const Funnel g = make_funnel(params);
  const Params* p = &params;
  const Funnel* f = &g;
  return std::move(compute_chain({&p, 1}, {&f, 1}, options, mirror_symmetric(params, options), chunk, chunk + 1)[0][0]);
}

void fold_chunk(ChunkStats& prefix, ChunkStats next) {
  merge(prefix, next);
  if (prefix.samples.empty()) {
    prefix.samples = std::move(next.samples);
  } else {
    prefix.samples.insert(prefix.samples.end(), std::make_move_iterator(next.samples.begin()),
                          std::make_move_iterator(next.samples.end()));
  }
}

EnsembleResult reduce_chunks(const Params& params, const EnsembleOptions& options, std::vector<ChunkStats> chunks) {
  const std::int64_t n = options.samples;
  const bool halved = mirror_symmetric(params, options);
  // Folded in chunk-index order: the same bits whatever computed the chunks, and in what order.
  ChunkStats total;
  for (ChunkStats& c : chunks) fold_chunk(total, std::move(c));
  EnsembleResult r = to_result(total, n);
  if (halved) {
    // The samples come in exact mirror pairs (and the middle one, at x0 = 0, falls straight
    // through): the mean of an observable that changes sign is exactly 0, where the running
    // mean would leave rounding residues of ~1e-20.
    for (const ObservableInfo& o : observables()) {
      if (o.mirror_odd) r.stats[static_cast<std::size_t>(o.id)].mean = 0.0;
    }
  }
  if (options.keep_samples) {
    // The chunks cover the simulated samples 0, 1, ... contiguously, in order.
    r.per_sample.resize(static_cast<std::size_t>(n));
    const std::int64_t kept = std::min<std::int64_t>(static_cast<std::int64_t>(total.samples.size()), n);
    for (std::int64_t k = 0; k < kept; ++k) {
      Sample& s = total.samples[static_cast<std::size_t>(k)];
      const std::int64_t partner = halved ? n - 1 - k : k;
      if (partner != k) {
        r.per_sample[static_cast<std::size_t>(partner)] = {-s.fraction, mirror_state(s.release), mirrored(s.trajectory)};
      }
      r.per_sample[static_cast<std::size_t>(k)] = std::move(s);
    }
  }
  return r;
}

namespace {

/// Longest chain of points run together: the tasks of a long sweep over mu stay many.
constexpr std::size_t max_chain = 8;

/// Compares every parameter but mu (bit patterns, in table order; then the wall profile object):
/// negative, 0 or positive; 0 for points that differ at most in mu.
int compare_but_mu(const Params& a, const Params& b) {
  for (const ParameterInfo& p : parameters(Space::ThreeD)) {
    if (p.name == "mu") continue;
    const auto x = std::bit_cast<std::uint64_t>(p.get(a)), y = std::bit_cast<std::uint64_t>(p.get(b));
    if (x != y) return x < y ? -1 : 1;
  }
  if (a.profile == b.profile) return 0;
  return std::less<const ProfileSpec*>()(a.profile.get(), b.profile.get()) ? -1 : 1;
}

/// The points' funnels and whether each ensemble is mirror symmetric (halved), as compute_chain
/// and friction_chains take them.
struct PointSetup {
  std::vector<Funnel> funnels;
  std::vector<char> mirror;
};

PointSetup setup(const std::vector<Params>& points, const EnsembleOptions& options) {
  PointSetup out;
  out.funnels.reserve(points.size());
  out.mirror.reserve(points.size());
  for (const Params& p : points) {
    out.funnels.push_back(make_funnel(p));
    out.mirror.push_back(mirror_symmetric(p, options) ? 1 : 0);
  }
  return out;
}

/// The sweep's points in the chains that compute_chain runs together: points that differ only in
/// mu, in ascending mu, and are all mirror symmetric or all not (`mirror`: a wall profile may
/// give one side its own mu), with the same release line, at most max_chain per chain (each point a chain of its own with a
/// wear record). Chains in the order of their first point.
std::vector<std::vector<std::size_t>> friction_chains(const std::vector<Params>& points, const std::vector<Funnel>& funnels,
                                                      const std::vector<char>& mirror, const EnsembleOptions& options) {
  // compute_chain takes the releases from a chain's first funnel: the release line must be the
  // same, bit for bit (it is, for walls that differ only in mu; checked, not assumed).
  auto same_releases = [&](std::size_t a, std::size_t b) {
    const Funnel &f = funnels[a], &g = funnels[b];
    return std::bit_cast<std::uint64_t>(f.x_release_mid) == std::bit_cast<std::uint64_t>(g.x_release_mid) &&
           std::bit_cast<std::uint64_t>(f.half_width) == std::bit_cast<std::uint64_t>(g.half_width) &&
           std::bit_cast<std::uint64_t>(f.y_release) == std::bit_cast<std::uint64_t>(g.y_release);
  };
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const bool chained = options.wear_bins == 0;
  if (chained) {
    std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
      const int c = compare_but_mu(points[i], points[j]);
      return c != 0 ? c < 0 : points[i].mu < points[j].mu;
    });
  }
  std::vector<std::vector<std::size_t>> chains;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t a = i > 0 ? order[i - 1] : 0, b = order[i];
    if (chained && i > 0 && chains.back().size() < max_chain && mirror[a] == mirror[b] && compare_but_mu(points[a], points[b]) == 0 &&
        same_releases(a, b)) {
      chains.back().push_back(order[i]);
    } else {
      chains.push_back({order[i]});
    }
  }
  std::sort(chains.begin(), chains.end(), [](const auto& a, const auto& b) {
    return *std::min_element(a.begin(), a.end()) < *std::min_element(b.begin(), b.end());
  });
  return chains;
}

}  // namespace

std::vector<std::vector<std::size_t>> friction_chains(const std::vector<Params>& points, const EnsembleOptions& options) {
  const PointSetup ps = setup(points, options);
  return friction_chains(points, ps.funnels, ps.mirror, options);
}

std::vector<ChunkStats> run_chunks(const std::vector<Params>& points, const EnsembleOptions& options,
                                   const std::vector<ChunkId>& ids) {
  // The points the ids name, in chains (friction_chains); a group is the members of one chain
  // that have the same chunk among the ids, run together by compute_chain. Any subset of a chain
  // is a chain: the reuse holds for every larger mu.
  std::vector<std::size_t> named;
  for (const ChunkId& id : ids) named.push_back(id.point);
  std::sort(named.begin(), named.end());
  named.erase(std::unique(named.begin(), named.end()), named.end());
  std::vector<Params> used;
  for (const std::size_t point : named) used.push_back(points[point]);
  const PointSetup ps = setup(used, options);
  const std::vector<Funnel>& funnels = ps.funnels;
  const std::vector<char>& mirror = ps.mirror;
  const auto local = [&named](std::size_t point) {
    return static_cast<std::size_t>(std::lower_bound(named.begin(), named.end(), point) - named.begin());
  };
  struct Group {
    std::int64_t chunk = 0;
    std::vector<std::size_t> members;  // local indices, in ascending mu
    std::vector<std::size_t> slots;    // the members' positions in ids
  };
  std::vector<Group> groups;
  std::vector<std::pair<std::size_t, std::size_t>> repeated;  // an id named again: (position, first position)
  {
    std::map<std::pair<std::size_t, std::int64_t>, std::size_t> slot_of;  // (local point, chunk) -> position in ids
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const auto [it, added] = slot_of.emplace(std::pair{local(ids[i].point), ids[i].chunk}, i);
      if (!added) repeated.emplace_back(i, it->second);
    }
    const std::vector<std::vector<std::size_t>> chains = friction_chains(used, funnels, mirror, options);
    for (const std::vector<std::size_t>& chain : chains) {
      std::map<std::int64_t, std::size_t> group_of;  // chunk -> group of this chain
      for (const std::size_t m : chain) {  // in ascending mu
        for (auto it = slot_of.lower_bound({m, 0}); it != slot_of.end() && it->first.first == m; ++it) {
          const auto [entry, added] = group_of.emplace(it->first.second, groups.size());
          if (added) groups.push_back({it->first.second, {}, {}});
          Group& g = groups[entry->second];
          g.members.push_back(m);
          g.slots.push_back(it->second);
        }
      }
    }
  }
  std::vector<ChunkStats> out(ids.size());
  const auto n = static_cast<std::int64_t>(groups.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(resolve_threads(options.threads))
  for (std::int64_t i = 0; i < n; ++i) {
    if (cancelled(options)) continue;
    const Group& g = groups[static_cast<std::size_t>(i)];
    std::vector<const Params*> chain_points;
    std::vector<const Funnel*> chain_funnels;
    for (const std::size_t m : g.members) {
      chain_points.push_back(&used[m]);
      chain_funnels.push_back(&funnels[m]);
    }
    std::vector<std::vector<ChunkStats>> stats =
        compute_chain(chain_points, chain_funnels, options, mirror[g.members.front()] != 0, g.chunk, g.chunk + 1);
    if (cancelled(options)) continue;  // stopped part way: not recorded
    for (std::size_t k = 0; k < g.members.size(); ++k) out[g.slots[k]] = std::move(stats[k][0]);
  }
  for (const auto& [again, first] : repeated) out[again] = out[first];
  return out;
}

std::vector<EnsembleResult> run_sweep(const std::vector<Params>& points, const EnsembleOptions& options,
                                      const Progress& progress, const PointDone& point_done) {
  const PointSetup ps = setup(points, options);
  const std::vector<Funnel>& funnels = ps.funnels;
  const std::vector<char>& mirror = ps.mirror;
  // Points that differ only in mu run as chains: a trajectory that did not slide is the next
  // point's too (compute_chain).
  const std::vector<std::vector<std::size_t>> chains = friction_chains(points, funnels, mirror, options);
  const auto n_chains = static_cast<std::int64_t>(chains.size());
  // The same partition for every point; a task is a group of consecutive chunks of one chain
  // (one chunk unless chunks are smaller than min_batch samples). Grouping changes no bit: each
  // chunk's statistics are its own samples' in index order.
  const std::int64_t n_chunks = chunk_count(options.samples);
  const std::int64_t per_chunk = std::max<std::int64_t>(1, options.samples / 2 / n_chunks);
  const std::int64_t spread = n_chains * n_chunks / (tasks_per_thread * resolve_threads(options.threads));
  const std::int64_t group =
      std::clamp<std::int64_t>((min_batch + per_chunk - 1) / per_chunk, 1, std::max<std::int64_t>(1, std::min(n_chunks, spread)));
  const std::int64_t n_groups = (n_chunks + group - 1) / group;
  const std::int64_t n_tasks = n_chains * n_groups;

  std::vector<EnsembleResult> results(points.size());
  std::vector<std::vector<ChunkStats>> chunks(points.size());  // of the points in progress only
  std::vector<std::int64_t> pending(points.size(), n_chunks);   // chunks left per point
  std::int64_t finished = 0;

#pragma omp parallel for schedule(dynamic, 1) num_threads(resolve_threads(options.threads))
  for (std::int64_t task = 0; task < n_tasks; ++task) {
    if (cancelled(options)) continue;
    const std::vector<std::size_t>& chain = chains[static_cast<std::size_t>(task / n_groups)];
    const std::int64_t c0 = (task % n_groups) * group;
    const std::int64_t c1 = std::min(n_chunks, c0 + group);
    std::vector<const Params*> chain_points;
    std::vector<const Funnel*> chain_funnels;
    for (const std::size_t point : chain) {
      chain_points.push_back(&points[point]);
      chain_funnels.push_back(&funnels[point]);
    }
    std::vector<std::vector<ChunkStats>> stats =
        compute_chain(chain_points, chain_funnels, options, mirror[chain.front()] != 0, c0, c1);
    if (cancelled(options)) continue;  // stopped part way: not recorded
#pragma omp critical(funnel_sweep)
    {
      for (std::size_t m = 0; m < chain.size(); ++m) {
        const std::size_t point = chain[m];
        std::vector<ChunkStats>& mine = chunks[point];
        if (mine.empty()) mine.resize(static_cast<std::size_t>(n_chunks));
        for (std::int64_t c = c0; c < c1; ++c) {
          mine[static_cast<std::size_t>(c)] = std::move(stats[m][static_cast<std::size_t>(c - c0)]);
        }
        pending[point] -= c1 - c0;
        if (pending[point] == 0) {
          results[point] = reduce_chunks(points[point], options, std::move(mine));
          mine = {};
          if (point_done) point_done(point, results[point]);
        }
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
