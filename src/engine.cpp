// The event loop of one trajectory (MODEL.md §3-7).
#include "funnel/engine.hpp"

#include <cmath>

#include "funnel/contact.hpp"
#include "funnel/roots.hpp"

namespace funnel {

std::string_view to_string(Status status) {
  switch (status) {
    case Status::Exited: return "exited";
    case Status::Rest: return "rest";
    case Status::Trapped: return "trapped";
  }
  return "?";
}

std::string_view to_string(EventKind kind) {
  switch (kind) {
    case EventKind::Face: return "face";
    case EventKind::Edge: return "edge";
    case EventKind::ContactStart: return "contact_start";
    case EventKind::ContactEnd: return "contact_end";
    case EventKind::Exit: return "exit";
  }
  return "?";
}

std::string_view to_string(Wall wall) { return wall == Wall::Left ? "left" : "right"; }

std::string_view to_string(Regime regime) {
  switch (regime) {
    case Regime::None: return "none";
    case Regime::Sliding: return "sliding";
    case Regime::Sticking: return "sticking";
    case Regime::Rolling: return "rolling";
  }
  return "?";
}

namespace {

/// The running trajectory: state, clock, observables and the optional log.
class Run {
 public:
  Run(const Params& params, const Geometry& g, const State& initial, EventSink* sink)
      : params_(params), g_(g), mat_(material(params)), law_(collision_constants(mat_)), sink_(sink), state_(initial) {
    e0_ = energy(initial, mat_.kappa, mat_.radius);
  }

  Trajectory finish() {
    loop();
    out_.final_state = state_;
    out_.energy_loss = e0_ - energy(state_, mat_.kappa, mat_.radius);
    return out_;
  }

 private:
  void loop() {
    FlightStart start;
    int stalled = 0;
    for (;;) {
      const NextEvent ev = next_event(g_, state_, start);
      if (!(time_ + ev.dt <= params_.t_max)) {  // also catches dt = never (a closed funnel at rest)
        state_ = advance(state_, std::fmin(params_.t_max - time_, 1e300));
        end(Status::Trapped, params_.t_max);
        return;
      }
      const double before = time_;
      state_ = advance(state_, ev.dt);
      time_ += ev.dt;
      stalled = time_ > before ? 0 : stalled + 1;
      if (stalled > max_stalled_events) {
        // In a closed funnel collisions pile up in no time only where the faces meet: they have
        // collapsed onto the vertex (a wedge collapse; beta0 = 1 keeps the spin's energy above
        // eps_rest), which is rest (found by fuzz/fuzz_physics). Elsewhere it is the Zeno guard.
        out_.stalled = !g_.closed;
        end(g_.closed ? Status::Rest : Status::Trapped, time_);
        return;
      }
      switch (ev.kind) {
        case EventKind::Exit:
          state_.r.y = g_.y_bottom;
          log_simple(EventKind::Exit, std::nullopt);
          end(Status::Exited, time_);
          return;
        case EventKind::Face:
          start = face_collision(ev.wall);
          break;
        case EventKind::Edge:
          start = edge_collision(ev.wall);
          break;
        default:
          break;
      }
      if (done_) return;
      if (sink_ != nullptr && sink_->finished()) {
        out_.stopped = true;
        end(Status::Trapped, time_);
        return;
      }
      if (out_.collisions >= params_.max_collisions) {
        end(Status::Trapped, time_);
        return;
      }
      if (g_.closed && energy(state_, mat_.kappa, mat_.radius) < params_.eps_rest) {
        end(Status::Rest, time_);  // energy above the vertex (E_vertex = 0) has run out
        return;
      }
    }
  }

  void end(Status status, double time) {
    out_.status = status;
    out_.duration = time;
    done_ = true;
  }

  /// Book-keeping shared by face and edge collisions; returns the collision.
  Collision apply_collision(EventKind kind, Wall wall, Vec2 n) {
    const Collision c = collide(state_, n, law_);
    ++out_.collisions;
    out_.impulse += std::sqrt(c.j_n * c.j_n + c.j_t * c.j_t);
    out_.normal_impulse += c.j_n;
    out_.energy_loss_events += c.energy_lost;
    if (sink_ != nullptr) {
      Event e = base_event(kind, wall);
      e.velocity_after = c.after.v;
      e.omega_after = c.after.omega;
      e.slip_before = c.slip;
      e.regime = c.regime;
      e.j_n = c.j_n;
      e.j_t = c.j_t;
      e.energy_lost = c.energy_lost;
      sink_->record(e);
    }
    state_ = c.after;
    return c;
  }

  FlightStart face_collision(Wall wall) {
    const Vec2 n = face_normal(g_, wall);
    // Put the centre exactly on the centre line, so that the next flight starts at distance 0.
    const double delta = face_distance(g_, wall, state_.r);
    state_.r = state_.r - delta * n;
    const Collision c = apply_collision(EventKind::Face, wall, n);
    FlightStart start;
    if (c.p_after >= params_.p_c) {
      start.on_face = wall;
      return start;
    }
    sustained_contact(wall, n, c.p_after);
    start.left_contact = wall;
    return start;
  }

  FlightStart edge_collision(Wall wall) {
    const Vec2 e = edge_point(g_, wall);
    const Vec2 d = state_.r - e;
    const double dist = std::sqrt(dot(d, d));
    const Vec2 n = (1.0 / dist) * d;
    state_.r = e + g_.radius * n;  // exactly on the edge circle
    ++out_.edge_collisions;
    const Collision c = apply_collision(EventKind::Edge, wall, n);
    FlightStart start;
    start.on_edge = wall;
    // A normal speed below p_c is taken as 0 by the next edge search (flight.cpp, edge_time).
    if (c.p_after < params_.p_c) start.slow_edge = wall;
    return start;
  }

  /// Inelastic collapse onto a face: drop the residual normal speed and slide in closed form.
  void sustained_contact(Wall wall, Vec2 n, double p_after) {
    ++out_.contacts;
    const State before = state_;
    state_.v = state_.v - p_after * n;
    const double lost = energy(before, mat_.kappa, mat_.radius) - energy(state_, mat_.kappa, mat_.radius);
    out_.energy_loss_events += lost;
    const ContactResult res = slide_to_end(state_, wall, g_, mat_);
    if (sink_ != nullptr) {
      Event e = base_event(EventKind::ContactStart, wall);
      e.velocity_before = before.v;
      e.velocity_after = state_.v;
      e.regime = res.first_regime;
      e.energy_lost = lost;
      sink_->record(e);
    }
    if (time_ + res.duration > params_.t_max) {
      // The cap falls inside the contact: stop there (rare; observables up to the collapse).
      end(Status::Trapped, params_.t_max);
      return;
    }
    time_ += res.duration;
    out_.contact_time += res.duration;
    out_.impulse += res.impulse;
    out_.normal_impulse += res.normal_impulse;
    const State arrived = res.end;
    state_ = res.end;
    double lost_end = res.energy_lost;
    if (g_.closed) {
      // A closed funnel's contact ends at the vertex: the particle rests there (MODEL.md §5).
      lost_end += energy(arrived, mat_.kappa, mat_.radius);
      state_.v = {0.0, 0.0};
      state_.omega = 0.0;
    }
    out_.energy_loss_events += lost_end;
    if (sink_ != nullptr) {
      Event e = base_event(EventKind::ContactEnd, wall);
      e.position = arrived.r;
      e.velocity_before = arrived.v;
      e.omega_before = arrived.omega;
      e.velocity_after = state_.v;
      e.omega_after = state_.omega;
      e.regime = res.last_regime;
      e.j_n = res.normal_impulse;
      e.j_t = res.tangential_impulse;
      e.energy_lost = lost_end;
      sink_->record(e);
    }
    if (g_.closed) end(Status::Rest, time_);
  }

  Event base_event(EventKind kind, std::optional<Wall> wall) const {
    Event e;
    e.time = time_;
    e.kind = kind;
    e.wall = wall;
    e.position = state_.r;
    e.velocity_before = state_.v;
    e.omega_before = state_.omega;
    e.velocity_after = state_.v;
    e.omega_after = state_.omega;
    return e;
  }

  void log_simple(EventKind kind, std::optional<Wall> wall) {
    if (sink_ != nullptr) sink_->record(base_event(kind, wall));
  }

  const Params& params_;
  const Geometry& g_;
  const Material mat_;
  const CollisionConstants law_;
  EventSink* sink_;
  State state_;
  double time_ = 0.0;
  double e0_ = 0.0;
  bool done_ = false;
  Trajectory out_;
};

}  // namespace

Trajectory simulate(const Params& params, const Geometry& g, const State& initial, EventSink* sink) {
  return Run(params, g, initial, sink).finish();
}

Trajectory simulate_release(const Params& params, const Geometry& g, double fraction, EventSink* sink) {
  State s;
  s.r = release_point(g, fraction);
  return simulate(params, g, s, sink);
}

}  // namespace funnel
