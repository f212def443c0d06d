// Classification of the long-time state of a closed funnel (docs/theory.md).
#include "funnel/closed.hpp"

#include <omp.h>

#include <cmath>

#include "funnel/engine.hpp"
#include "funnel/geometry.hpp"

namespace funnel {

std::string_view to_string(FinalState state) {
  switch (state) {
    case FinalState::Periodic: return "periodic";
    case FinalState::Rest: return "rest";
    case FinalState::Undecided: return "undecided";
  }
  return "?";
}

namespace {

/// Watches the collisions and reports the period-2 orbit once `window` consecutive collisions
/// alternate walls, have (almost) no slip and repeat the previous collision's height.
class OrbitWatch final : public EventSink {
 public:
  explicit OrbitWatch(const ClosedOptions& o) : opt_(o) {}

  void record(const Event& e) override {
    if (e.kind != EventKind::Face && e.kind != EventKind::Edge) return;
    const double speed = std::hypot(e.velocity_before.x, e.velocity_before.y);
    const bool alternates = have_last_ && e.wall && *e.wall != last_wall_;
    const bool no_slip = std::fabs(e.slip_before) <= opt_.slip_tol * speed;
    const bool level = have_last_ && std::fabs(e.position.y - last_.y) <= opt_.height_tol * std::fabs(e.position.y);
    streak_ = alternates && no_slip && level ? streak_ + 1 : 0;
    prev_ = last_;
    last_ = e.position;
    if (e.wall) last_wall_ = *e.wall;
    have_last_ = true;
  }

  bool finished() const override { return streak_ >= opt_.window; }

  Vec2 last() const { return last_; }
  Vec2 prev() const { return prev_; }

 private:
  const ClosedOptions& opt_;
  int streak_ = 0;
  bool have_last_ = false;
  Wall last_wall_ = Wall::Left;
  Vec2 last_, prev_;
};

}  // namespace

ClosedSample classify_release(const Params& params, double fraction, const ClosedOptions& options) {
  Params p = params;
  p.gap = 0.0;
  p.t_max = options.max_time;
  p.max_collisions = options.max_collisions;
  const Geometry g = make_geometry(p);
  OrbitWatch watch(options);
  const Trajectory t = simulate_release(p, g, fraction, &watch);
  ClosedSample s;
  s.fraction = fraction;
  s.collisions = t.collisions;
  s.time = t.duration;
  s.energy = energy(t.final_state, p.inertia, p.radius);
  if (t.status == Status::Rest) {
    s.state = FinalState::Rest;  // the collision points collapse onto the vertex, x = 0
  } else {
    s.state = t.stopped ? FinalState::Periodic : FinalState::Undecided;
    s.x_last = watch.last().x;
    s.y_last = watch.last().y;
    s.x_prev = watch.prev().x;
    s.y_prev = watch.prev().y;
  }
  return s;
}

ClosedResult run_closed(const Params& params, const EnsembleOptions& ensemble, const ClosedOptions& options) {
  const std::int64_t n = ensemble.samples;
  ClosedResult r;
  r.samples.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(dynamic, 1) num_threads(resolve_threads(ensemble.threads))
  for (std::int64_t k = 0; k < n; ++k) {
    r.samples[static_cast<std::size_t>(k)] = classify_release(params, sample_fraction(ensemble, k), options);
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
