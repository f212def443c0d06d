// The event loop of one trajectory (docs/model.md §3-7).
#include "funnel/engine.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "funnel/contact.hpp"
#include "funnel/edge_contact.hpp"
#include "funnel/wear.hpp"
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
    case EventKind::EdgeContactStart: return "edge_contact_start";
    case EventKind::EdgeContactEnd: return "edge_contact_end";
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

/// The mirror image x -> -x of a state: the right wall's edge contacts are solved as the left
/// wall's, so that the engine stays exactly mirror symmetric.
State mirror(const State& s) {
  State m = s;
  m.r.x = 0.0 - s.r.x;  // 0 - x keeps a zero +0 (see ensemble.cpp)
  m.v.x = 0.0 - s.v.x;
  m.omega = 0.0 - s.omega;
  return m;
}

/// Hand-overs between a face and its edge within one sustained contact after which the run is
/// stopped as trapped: a guard that no physical contact reaches (each hand-over back to the
/// face needs friction to reverse the motion on the edge, which dissipates energy).
constexpr int max_hand_overs = 1000;

/// The running trajectory: state, clock, observables and the optional log.
class Run {
 public:
  Run(const Params& params, const Geometry& g, const State& initial, EventSink* sink, Wear* wear)
      : params_(params), g_(g), mat_(material(params)), law_(collision_constants(mat_)), sink_(sink), wear_(wear),
        state_(initial) {
    e0_ = energy(initial, mat_.kappa, mat_.radius);
    // The left edge's arc of contact normals, from the face's normal n_L down to the wall's
    // underside; the right edge is solved in the mirror image.
    const double top = std::atan2(g_.cos_t, g_.sin_t);
    left_arc_ = {edge_point(g_, Wall::Left), top - std::numbers::pi, top};
  }

  Trajectory finish() {
    loop();
    out_.final_state = state_;
    const double e_end = energy(state_, mat_.kappa, mat_.radius);
    out_.energy_loss = e0_ - e_end;
    // A loss within rounding of zero below it (an elastic run) is reported as 0, not -2e-16.
    const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * std::fmax(std::fabs(e0_), std::fabs(e_end));
    if (out_.energy_loss < 0.0 && out_.energy_loss > -rounding) out_.energy_loss = 0.0;
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
          out_.exit_state = state_;
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
    const double j = std::sqrt(c.j_n * c.j_n + c.j_t * c.j_t);
    out_.impulse += j;
    out_.normal_impulse += c.j_n;
    out_.energy_loss_events += c.energy_lost;
    if (wear_ != nullptr) {
      if (kind == EventKind::Edge) {
        wear_->add_edge(wall, c.j_n, j, true);
      } else {
        wear_->add_collision(wall, distance_up_face(wall, state_.r), c.j_n, j);
      }
    }
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

  /// Distance of the contact point up the face from the face's end (C*, or the vertex).
  double distance_up_face(Wall wall, Vec2 r) const {
    const double ws = wall_sign(wall);
    return ws * g_.cos_t * (r.x - ws * g_.x_face_end) + g_.sin_t * (r.y - g_.y_face_end);
  }

  FlightStart face_collision(Wall wall) {
    const Vec2 n = face_normal(g_, wall);
    // Put the centre exactly on the centre line, so that the next flight starts at distance 0.
    const double delta = face_distance(g_, wall, state_.r);
    state_.r = state_.r - delta * n;
    const Collision c = apply_collision(EventKind::Face, wall, n);
    if (c.p_after >= params_.p_c) {
      FlightStart start;
      start.on_face = wall;
      return start;
    }
    // Inelastic collapse: drop the residual normal speed and go on in sustained contact.
    const State before = state_;
    state_.v = state_.v - c.p_after * n;
    return sustained_contact(wall, false, before);
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
    if (c.p_after >= params_.p_c) {
      start.on_edge = wall;
      return start;
    }
    // The edge chatter has collapsed. Without its residual normal speed the particle either
    // stays on the edge (the normal force it needs is positive) or flies off curving away from
    // the edge circle, whose quartic then has no root at t = 0+ (its linear term taken as 0).
    State tangential = state_;
    tangential.v = state_.v - c.p_after * n;
    if (edge_normal_force(tangential, e, g_.radius) > 0.0) return sustained_contact(wall, true, state_);
    start.on_edge = wall;
    start.slow_edge = wall;
    return start;
  }

  /// Sustained contact after a collapse on `wall`'s face (on_edge false) or edge, through every
  /// hand-over between the face and its edge, until the particle flies off, rests at the vertex
  /// of a closed funnel, or the time cap falls inside it. `before` is the state before the
  /// residual normal speed was dropped (the particle is already tangential in state_).
  FlightStart sustained_contact(Wall wall, bool on_edge, const State& before) {
    State entry = before;
    if (on_edge) {
      const Vec2 n = (1.0 / g_.radius) * (state_.r - edge_point(g_, wall));
      state_.v = state_.v - dot(state_.v, n) * n;
    }
    for (int hop = 0; hop < max_hand_overs; ++hop) {
      if (!on_edge) {
        face_contact(wall, entry);
        if (done_) return {};
        // At C*: the edge holds the particle if the normal force it needs is positive
        // (v^2 < a cos(theta)); otherwise it flies on, tangent to the face and the edge circle.
        if (!(edge_normal_force(state_, edge_point(g_, wall), g_.radius) > 0.0)) {
          FlightStart start;
          start.skip_face = wall;
          start.skip_edge = wall;
          return start;
        }
      } else {
        edge_contact_phase(wall, entry);
        if (done_) return {};
        if (last_edge_exit_ != EdgeExit::High) {
          FlightStart start;
          start.skip_edge = wall;  // it left the circle tangentially, curving away from it
          return start;
        }
      }
      on_edge = !on_edge;
      entry = state_;
    }
    out_.stalled = true;
    end(Status::Trapped, time_);
    return {};
  }

  /// A sustained contact with a face, from state_ (tangential) to the face's end. `entry` is
  /// the state before the residual normal speed of a collapse was dropped (or state_).
  void face_contact(Wall wall, const State& entry) {
    ++out_.contacts;
    const double lost = energy(entry, mat_.kappa, mat_.radius) - energy(state_, mat_.kappa, mat_.radius);
    out_.energy_loss_events += lost;
    const ContactResult res = slide_to_end(state_, wall, g_, mat_);
    if (sink_ != nullptr) {
      Event e = base_event(EventKind::ContactStart, wall);
      e.velocity_before = entry.v;
      e.omega_before = entry.omega;
      e.regime = res.first_regime;
      e.energy_lost = lost;
      sink_->record(e);
    }
    if (time_ + res.duration > params_.t_max) {
      // The cap falls inside the contact: stop there (rare; observables up to its start).
      end(Status::Trapped, params_.t_max);
      return;
    }
    time_ += res.duration;
    out_.contact_time += res.duration;
    out_.impulse += res.impulse;
    out_.normal_impulse += res.normal_impulse;
    if (wear_ != nullptr) {
      for (int k = 0; k < res.phase_count; ++k) wear_->add_face_phase(wall, res.phases[k], g_.cos_t);
    }
    const State arrived = res.end;
    state_ = res.end;
    double lost_end = res.energy_lost;
    if (g_.closed) {
      // A closed funnel's contact ends at the vertex: the particle rests there (docs/model.md §5).
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

  /// A sustained contact with a wall's edge point, from state_ (on the circle, tangential).
  void edge_contact_phase(Wall wall, const State& entry) {
    ++out_.edge_contacts;
    const double lost = energy(entry, mat_.kappa, mat_.radius) - energy(state_, mat_.kappa, mat_.radius);
    out_.energy_loss_events += lost;
    const bool mirrored = wall == Wall::Right;
    EdgeContactResult res = edge_contact(mirrored ? mirror(state_) : state_, left_arc_, mat_);
    if (mirrored) {
      res.end = mirror(res.end);
      res.tangential_impulse = -res.tangential_impulse;  // t = (n_y, -n_x) mirrors to -t
    }
    if (sink_ != nullptr) {
      Event e = base_event(EventKind::EdgeContactStart, wall);
      e.velocity_before = entry.v;
      e.omega_before = entry.omega;
      e.regime = res.first_regime;
      e.energy_lost = lost;
      sink_->record(e);
    }
    if (time_ + res.duration > params_.t_max) {
      end(Status::Trapped, params_.t_max);
      return;
    }
    time_ += res.duration;
    out_.contact_time += res.duration;
    out_.impulse += res.impulse;
    out_.normal_impulse += res.normal_impulse;
    out_.energy_loss_events += res.energy_lost;
    if (wear_ != nullptr) wear_->add_edge(wall, res.normal_impulse, res.impulse, false);
    state_ = res.end;
    last_edge_exit_ = res.exit;
    if (res.exit == EdgeExit::High) {
      // Back at C*, moving up the face: put it exactly there, tangent to the face.
      const double ws = wall_sign(wall);
      const Vec2 down{-ws * g_.cos_t, -g_.sin_t};
      state_.r = {ws * g_.x_face_end, g_.y_face_end};
      state_.v = dot(res.end.v, down) * down;
    }
    if (sink_ != nullptr) {
      Event e = base_event(EventKind::EdgeContactEnd, wall);
      e.velocity_before = res.end.v;
      e.omega_before = res.end.omega;
      e.regime = res.last_regime;
      e.j_n = res.normal_impulse;
      e.j_t = res.tangential_impulse;
      e.energy_lost = res.energy_lost;
      sink_->record(e);
    }
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
  Wear* wear_;
  State state_;
  EdgeArc left_arc_;
  EdgeExit last_edge_exit_ = EdgeExit::TakeOff;
  double time_ = 0.0;
  double e0_ = 0.0;
  bool done_ = false;
  Trajectory out_;
};

}  // namespace

Trajectory simulate(const Params& params, const Geometry& g, const State& initial, EventSink* sink, Wear* wear) {
  return Run(params, g, initial, sink, wear).finish();
}

State release_state(const Params& params, const Geometry& g, double fraction) {
  State s;
  s.r = release_point(g, fraction);
  s.v = {params.release_u, params.release_v};
  s.omega = params.release_spin;
  return s;
}

Trajectory simulate_release(const Params& params, const Geometry& g, double fraction, EventSink* sink, Wear* wear) {
  return simulate(params, g, release_state(params, g, fraction), sink, wear);
}

}  // namespace funnel
