// Classification of the long-time state of a closed funnel (docs/theory.md).
#include "funnel/closed.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/geometry.hpp"
#include "funnel/watch.hpp"

namespace funnel {

std::string_view to_string(FinalState state) {
  switch (state) {
    case FinalState::Periodic: return "periodic";
    case FinalState::Rest: return "rest";
    case FinalState::Undecided: return "undecided";
  }
  return "?";
}

void OrbitWatch::record(const Event& e) {
  if (e.kind != EventKind::Face && e.kind != EventKind::Edge) return;
  Memory& m = memory_;
  const double speed = std::hypot(e.velocity_before.x, e.velocity_before.y);
  const bool alternates = m.have_last && e.wall && *e.wall != m.last_wall;
  const bool no_slip = std::fabs(e.slip_before) <= test_.slip_tol * speed;
  const bool seen = test_.two_back ? m.have_prev : m.have_last;
  const Vec2 same = test_.two_back ? m.prev : m.last;  // the collision whose height must repeat
  const bool level = seen && std::fabs(e.position.y - same.y) <= test_.height_tol * std::fabs(e.position.y);
  m.streak = alternates && no_slip && level ? m.streak + 1 : 0;
  m.have_prev = m.have_last;
  m.prev = m.last;
  m.last = e.position;
  if (e.wall) m.last_wall = *e.wall;
  m.have_last = true;
}

namespace {

/// Releases a task of run_closed classifies together (so that the batched path's lanes stay busy).
constexpr std::int64_t closed_batch = 64;

Params closed_params(const Params& params, const ClosedOptions& options) {
  Params p = params;
  p.gap = 0.0;
  p.t_max = options.max_time;
  p.max_collisions = options.max_collisions;
  return p;
}

/// The periodic test of a closed funnel. With e < 1 on a wall every collision there loses
/// (1 - e^2) p^2 / 2, so there is no periodic orbit: the test can never pass (a slowly decaying
/// bounce at e = 1 - 1e-7 repeats its heights within height_tol and was taken for the orbit).
/// In a funnel that is not mirror symmetric the orbit's two heights differ: each collision is
/// compared with the one two before it, on the same wall.
OrbitTest orbit_test(const ClosedOptions& o, const Funnel& f) {
  const bool elastic = f.sides[0].material.e == 1.0 && f.sides[1].material.e == 1.0;
  return {elastic ? o.window : std::numeric_limits<int>::max(), o.slip_tol, o.height_tol, !f.symmetric};
}

ClosedSample classify(const Params& p, double fraction, const Trajectory& t, const OrbitWatch& watch) {
  ClosedSample s;
  s.fraction = fraction;
  s.collisions = t.collisions;
  s.time = t.duration;
  s.energy = energy(t.final_state, p.inertia, p.radius);
  if (t.status == Status::Rest) {
    s.state = FinalState::Rest;  // the collision points collapse onto the vertex, x = 0
  } else {
    s.state = t.stopped ? FinalState::Periodic : FinalState::Undecided;
    // A collision that never happened has no position: NaN (null, an empty field), not the
    // vertex's 0 (a cap of a few time units or collisions leaves one or none).
    constexpr double none = std::numeric_limits<double>::quiet_NaN();
    s.x_last = t.collisions >= 1 ? watch.last().x : none;
    s.y_last = t.collisions >= 1 ? watch.last().y : none;
    s.x_prev = t.collisions >= 2 ? watch.prev().x : none;
    s.y_prev = t.collisions >= 2 ? watch.prev().y : none;
  }
  return s;
}

}  // namespace

ClosedSample classify_release(const Params& params, double fraction, const ClosedOptions& options) {
  const Params p = closed_params(params, options);
  const Funnel g = make_funnel(p);
  OrbitWatch watch(orbit_test(options, g));
  const Trajectory t = simulate_release(p, g, fraction, &watch);
  return classify(p, fraction, t, watch);
}

ClosedResult run_closed(const Params& params, const EnsembleOptions& ensemble, const ClosedOptions& options,
                        const Progress& progress) {
  const std::int64_t n = ensemble.samples;
  const Params p = closed_params(params, options);
  const Funnel g = make_funnel(p);
  ClosedResult r;
  r.samples.resize(static_cast<std::size_t>(n));
  const std::int64_t tasks = (n + closed_batch - 1) / closed_batch;
  std::int64_t finished = 0;
  // Each task's releases run together, each with its own watch (simulate_many: the batched
  // path of a V); every sample is the same as classify_release's.
#pragma omp parallel for schedule(dynamic, 1) num_threads(resolve_threads(ensemble.threads))
  for (std::int64_t task = 0; task < tasks; ++task) {
    // Cancelled (Ctrl-C in Python): the tasks not yet begun are skipped; the result is discarded.
    if (ensemble.cancel != nullptr && ensemble.cancel->load(std::memory_order_relaxed)) continue;
    const std::int64_t first = task * closed_batch;
    const std::int64_t last = std::min(n, first + closed_batch);
    std::vector<double> fractions;
    std::vector<State> initial;
    for (std::int64_t k = first; k < last; ++k) {
      fractions.push_back(sample_fraction(ensemble, k));
      initial.push_back(release_state(p, g, fractions.back()));
    }
    std::vector<OrbitWatch> watches(initial.size(), OrbitWatch(orbit_test(options, g)));
    std::vector<Trajectory> out(initial.size());
    simulate_many(p, g, initial, out, watches);
    for (std::size_t i = 0; i < initial.size(); ++i) {
      r.samples[static_cast<std::size_t>(first) + i] = classify(p, fractions[i], out[i], watches[i]);
    }
    if (progress) {
#pragma omp critical(funnel_closed_progress)
      progress(++finished, tasks);
    }
  }
  for (const ClosedSample& s : r.samples) {
    r.periodic += s.state == FinalState::Periodic;
    r.rest += s.state == FinalState::Rest;
    r.undecided += s.state == FinalState::Undecided;
  }
  r.periodic_fraction = static_cast<double>(r.periodic) / static_cast<double>(n);
  return r;
}

}  // namespace funnel
