// Parallel 3D ensembles with a fixed reduction order (deterministic for any thread count).
#include "funnel/ensemble3d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "funnel/random.hpp"

namespace funnel {

namespace {

/// Work units per ensemble, as in 2D: the partition depends on N only, never on the threads.
constexpr std::int64_t max_chunks = 256;
constexpr std::int64_t min_chunk = 16;
/// Trajectories a task runs side by side (simulate_3d_many keeps its lanes busy over them).
constexpr std::int64_t balls_per_task = 128;

struct BlockStats3 {
  std::array<Accumulator, observable_count_3d> acc;
  std::int64_t exited = 0, rest = 0, trapped = 0, periodic = 0, stalled = 0, capped = 0, total_collisions = 0, ode_steps = 0;

  void add(const Trajectory3& t) {
    for (const ObservableInfo& o : observables_3d()) {
      if (o.exited_only && t.status != Status::Exited) continue;
      acc[static_cast<std::size_t>(o.id)].add(value(t, o.id));
    }
    exited += t.status == Status::Exited;
    rest += t.status == Status::Rest;
    trapped += t.status == Status::Trapped;
    periodic += t.periodic;
    stalled += t.stalled;
    capped += t.capped;
    total_collisions += t.collisions;
    ode_steps += t.ode_steps;
  }

  void merge(const BlockStats3& o) {
    for (std::size_t i = 0; i < acc.size(); ++i) acc[i].merge(o.acc[i]);
    exited += o.exited;
    rest += o.rest;
    trapped += o.trapped;
    periodic += o.periodic;
    stalled += o.stalled;
    capped += o.capped;
    total_collisions += o.total_collisions;
    ode_steps += o.ode_steps;
  }

  Ensemble3Result result(std::int64_t samples) const {
    Ensemble3Result r;
    r.samples = samples;
    for (std::size_t i = 0; i < acc.size(); ++i) r.stats[i] = summarize(acc[i]);
    r.exited = exited;
    r.rest = rest;
    r.trapped = trapped;
    r.periodic = periodic;
    r.stalled = stalled;
    r.capped = capped;
    r.total_collisions = total_collisions;
    r.ode_steps = ode_steps;
    return r;
  }
};

}  // namespace

double value(const Trajectory3& t, Observable o) {
  const bool exited = t.status == Status::Exited;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const State3& x = t.exit_state;
  switch (o) {
    case Observable::Duration: return t.duration;
    case Observable::Impulse: return t.impulse;
    case Observable::NormalImpulse: return t.normal_impulse;
    case Observable::EnergyLoss: return t.energy_loss;
    case Observable::Collisions: return static_cast<double>(t.collisions);
    case Observable::EdgeCollisions: return static_cast<double>(t.edge_collisions);
    case Observable::FaceCollisions: return static_cast<double>(t.collisions - t.edge_collisions);
    case Observable::Contacts: return static_cast<double>(t.contacts);
    case Observable::EdgeContacts: return static_cast<double>(t.edge_contacts);
    case Observable::ContactTime: return t.contact_time;
    case Observable::ExitX: return exited ? x.r.x : nan;
    case Observable::ExitU: return exited ? x.v.x : nan;
    case Observable::ExitV: return exited ? x.v.y : nan;
    case Observable::ExitSpeed: return exited ? std::sqrt(dot(x.v, x.v)) : nan;
    case Observable::ExitAngle:
      return exited ? std::atan2(std::sqrt(x.v.x * x.v.x + x.v.z * x.v.z), -x.v.y) * (180.0 / std::numbers::pi) : nan;
    case Observable::ExitSpin: return exited ? x.omega.z : nan;
    case Observable::ExitZ: return exited ? x.r.z : nan;
    case Observable::ExitW: return exited ? x.v.z : nan;
    case Observable::ExitSpinX: return exited ? x.omega.x : nan;
    case Observable::ExitSpinY: return exited ? x.omega.y : nan;
    case Observable::Orbits: return std::fabs(t.orbits);
  }
  return nan;
}

State3 ensemble_release_3d(const Params& params, const Cone& cone, const Ensemble3Options& options, std::int64_t k) {
  State3 s = release_state_3d(params, cone, release_fraction(options.dist, k, options.samples));
  if (options.velocity_sd > 0.0) {
    const auto index = static_cast<std::uint64_t>(k);
    s.v.x += options.velocity_sd * standard_normal(options.seed, release_velocity_u_stream, index);
    s.v.z += options.velocity_sd * standard_normal(options.seed, release_velocity_w_stream, index);
  }
  return s;
}

std::vector<Ensemble3Result> run_sweep_3d(const std::vector<Params>& points, const Ensemble3Options& options,
                                          const Progress& progress, const PointDone3& point_done) {
  return run_sweep_3d(points, std::vector<double>(points.size(), options.velocity_sd), options, progress, point_done);
}

std::vector<Ensemble3Result> run_sweep_3d(const std::vector<Params>& points, const std::vector<double>& velocity_sds,
                                          const Ensemble3Options& options, const Progress& progress,
                                          const PointDone3& point_done) {
  const std::int64_t n = options.samples;
  const std::int64_t blocks_per_point = std::min(max_chunks, (n + min_chunk - 1) / min_chunk);
  // A task runs consecutive blocks of a point, about balls_per_task trajectories side by side
  // (simulate_3d_many), or fewer so that every thread has four tasks; each block keeps its own
  // statistics, reduced in index order, so the grouping (and the thread count) changes no bit.
  const auto n_points = static_cast<std::int64_t>(points.size());
  const int n_threads = resolve_threads(options.threads);
  const std::int64_t points_or_one = std::max<std::int64_t>(n_points, 1);
  const std::int64_t wanted = std::max((n + balls_per_task - 1) / balls_per_task,
                                       (4 * n_threads + points_or_one - 1) / points_or_one);
  const std::int64_t tasks_per_point = std::max<std::int64_t>(1, std::min(wanted, blocks_per_point));
  const std::int64_t n_tasks = n_points * tasks_per_point;
  const std::int64_t n_blocks = n_points * blocks_per_point;
  std::vector<Cone> cones;
  cones.reserve(points.size());
  for (const Params& p : points) cones.push_back(make_cone(p));
  std::vector<Ensemble3Result> results(points.size());
  if (options.keep_samples) {
    for (auto& r : results) r.per_sample.resize(static_cast<std::size_t>(n));
  }
  std::vector<BlockStats3> blocks(static_cast<std::size_t>(n_blocks));
  std::vector<std::int64_t> pending(points.size(), tasks_per_point);
  std::int64_t finished = 0;
  const auto block_begin = [&](std::int64_t block) { return block * n / blocks_per_point; };

#pragma omp parallel for schedule(dynamic, 1) num_threads(n_threads)
  for (std::int64_t task = 0; task < n_tasks; ++task) {
    const std::int64_t point = task / tasks_per_point;
    const std::int64_t part = task % tasks_per_point;
    const std::int64_t first_block = part * blocks_per_point / tasks_per_point;
    const std::int64_t last_block = (part + 1) * blocks_per_point / tasks_per_point;
    const std::int64_t first = block_begin(first_block);
    const std::int64_t last = block_begin(last_block);
    const Params& params = points[static_cast<std::size_t>(point)];
    const Cone& cone = cones[static_cast<std::size_t>(point)];
    Ensemble3Options point_options = options;
    point_options.velocity_sd = velocity_sds[static_cast<std::size_t>(point)];
    std::vector<State3> starts;
    starts.reserve(static_cast<std::size_t>(last - first));
    for (std::int64_t k = first; k < last; ++k) starts.push_back(ensemble_release_3d(params, cone, point_options, k));
    std::vector<Trajectory3> runs(starts.size());
    // A 3D trajectory may take seconds: once cancelled, the runs stop at their next event.
    simulate_3d_many(params, cone, starts, runs, options.cancel);
    const bool cancelled = options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed);
    for (std::int64_t block = first_block; block < last_block && !cancelled; ++block) {
      BlockStats3& stats = blocks[static_cast<std::size_t>(point * blocks_per_point + block)];
      for (std::int64_t k = block_begin(block); k < block_begin(block + 1); ++k) {
        const auto i = static_cast<std::size_t>(k - first);
        stats.add(runs[i]);
        if (options.keep_samples) {
          results[static_cast<std::size_t>(point)].per_sample[static_cast<std::size_t>(k)] = {
              release_fraction(options.dist, k, n), starts[i].v, runs[i]};
        }
      }
    }
#pragma omp critical(funnel_sweep_3d)
    {
      if (--pending[static_cast<std::size_t>(point)] == 0) {
        // Reduce the point's chunks in index order: the same bits whatever the thread count.
        BlockStats3 total;
        for (std::int64_t b = 0; b < blocks_per_point; ++b) {
          total.merge(blocks[static_cast<std::size_t>(point * blocks_per_point + b)]);
        }
        Ensemble3Result& r = results[static_cast<std::size_t>(point)];
        std::vector<Sample3> kept = std::move(r.per_sample);
        r = total.result(n);
        r.per_sample = std::move(kept);
        if (point_done) point_done(static_cast<std::size_t>(point), r);
      }
      ++finished;
      if (progress) progress(finished, n_tasks);
    }
  }
  return results;
}

Ensemble3Result run_ensemble_3d(const Params& params, const Ensemble3Options& options, const Progress& progress) {
  return std::move(run_sweep_3d({params}, options, progress).front());
}

}  // namespace funnel
