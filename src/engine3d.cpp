// The event loop of one 3D trajectory in the axisymmetric funnel.
#include "funnel/engine3d.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include "funnel/roots.hpp"
#include "funnel/walton3d.hpp"

namespace funnel {

std::string_view to_string(Contact3End end) {
  switch (end) {
    case Contact3End::FaceEnd: return "face_end";
    case Contact3End::RimTop: return "rim_top";
    case Contact3End::TakeOff: return "take_off";
    case Contact3End::Exit: return "exit";
    case Contact3End::Rest: return "rest";
    case Contact3End::TimeCap: return "time_cap";
    case Contact3End::Periodic: return "periodic";
  }
  return "?";
}

namespace {

/// Consecutive hand-overs between the face and the rim without time advancing after which the run
/// is stopped as trapped (a Zeno guard no physical contact reaches).
constexpr int max_hand_overs = 1000;

class Run3 {
 public:
  Run3(const Params& params, const Cone& cone, const State3& initial, EventSink3* sink,
       const std::atomic<bool>* cancel = nullptr)
      : params_(params), cone_(cone), g_(cone.g), mat_(material(params)), law_(collision_constants(mat_)),
        sink_(sink), events_(sink != nullptr && sink->records() ? sink : nullptr), state_(initial) {
    e0_ = energy(initial, mat_.kappa, mat_.radius);
    opt_.eps_rest = params.eps_rest;
    opt_.max_steps = params.max_ode_steps;
    opt_.cancel = cancel;
  }

  Trajectory3 finish() {
    while (!done_) step(cone_face_time(cone_, state_, start_));
    return result();
  }

  /// True once the run has ended (result() is then its trajectory).
  bool done() const { return done_; }

  /// The flight that the next step() starts: cone_face_time(cone, state(), start()) is its face time.
  const State3& state() const { return state_; }
  const FlightStart3& start() const { return start_; }

  /// One turn of the event loop: the flight from state() to its next event, whose face time
  /// face_time (cone_face_time of state() and start()) is given, and that event.
  void step(double face_time) {
    const NextEvent3 ev = next_event(cone_, state_, start_, face_time);
    if (!(time_ + ev.dt <= params_.t_max)) {  // also catches dt = never
      fly(std::fmin(params_.t_max - time_, 1e300));
      end(Status::Trapped, params_.t_max);
      return;
    }
    const double before = time_;
    fly(ev.dt);
    time_ += ev.dt;
    stalled_ = time_ > before ? 0 : stalled_ + 1;
    if (stalled_ > max_stalled_events) {
      out_.stalled = !g_.closed;
      end(g_.closed ? Status::Rest : Status::Trapped, time_);
      return;
    }
    switch (ev.kind) {
      case EventKind::Exit:
        state_.r.y = g_.y_bottom;
        exit_here();
        return;
      case EventKind::Face: start_ = face_collision(); break;
      case EventKind::Edge: start_ = rim_collision(); break;
      default: break;
    }
    if (done_) return;
    if (sink_ != nullptr && sink_->finished()) {
      out_.stopped = true;
      end(Status::Trapped, time_);
      return;
    }
    if (out_.collisions >= params_.max_collisions) {
      out_.capped = true;
      end(Status::Trapped, time_);
      return;
    }
    if (g_.closed && energy(state_, mat_.kappa, mat_.radius) < params_.eps_rest) {
      end(Status::Rest, time_);
      return;
    }
  }

  /// The trajectory of a run that has ended.
  Trajectory3 result() {
    out_.final_state = state_;
    out_.energy_loss = reported_energy_loss(e0_, energy(state_, mat_.kappa, mat_.radius));
    out_.orbits = swept_ / (2.0 * std::numbers::pi);
    return out_;
  }

 private:
  /// A free flight of duration dt, with the azimuth it sweeps.
  void fly(double dt) {
    const State3 next = advance(state_, dt);
    swept_ += azimuth_swept(state_.r, next.r);
    state_ = next;
  }

  void end(Status status, double time) {
    out_.status = status;
    out_.duration = time;
    done_ = true;
  }

  void exit_here() {
    out_.exit_state = state_;
    log(base_event(EventKind::Exit));
    end(Status::Exited, time_);
  }

  Collision3 apply_collision(EventKind kind, Vec3 n, Vec3 across) {
    const Collision3 c = collide(state_, n, across, law_);
    ++out_.collisions;
    out_.impulse += std::sqrt(c.j_n * c.j_n + dot(c.j_t, c.j_t));
    out_.normal_impulse += c.j_n;
    out_.energy_loss_events += c.energy_lost;
    if (events_ != nullptr) {
      Event3 e = base_event(kind);
      e.velocity_after = c.after.v;
      e.omega_after = c.after.omega;
      e.normal = n;
      e.slip_before = c.slip;
      e.regime = c.regime;
      e.j_n = c.j_n;
      e.j_t = c.j_t;
      e.energy_lost = c.energy_lost;
      events_->record(e);
    }
    state_ = c.after;
    return c;
  }

  /// The half-plane of the face the centre meets: its own, or on the axis (a closed cone's vertex,
  /// where it touches every generator at once) the one it moves towards. The position alone would
  /// name the same generator for every bounce in the vertex, undoing each bounce with the next
  /// (docs/robustness.md, finding 26).
  Vec3 face_side() const {
    if (state_.r.x != 0.0 || state_.r.z != 0.0) return meridian_direction(state_.r);
    return meridian_direction({state_.v.x, 0.0, state_.v.z});
  }

  FlightStart3 face_collision() {
    const Vec3 b = face_side();
    const Vec3 n = cone_normal(cone_, b);
    // Put the centre exactly on the centre cone, so that the next flight starts at distance 0.
    const double delta = dot(n, state_.r);
    state_.r = state_.r - delta * n;
    // Next to a closed cone's vertex the generator's line goes on past the apex, to the far side
    // of the axis: a centre projected there is at the apex (finding 26).
    if (g_.closed && b.x * state_.r.x + b.z * state_.r.z < 0.0) state_.r = {};
    const Collision3 c = apply_collision(EventKind::Face, n, azimuthal_direction(b));
    if (c.p_after >= params_.p_c) {
      FlightStart3 start;
      start.on_face = true;
      return start;
    }
    // Inelastic collapse: drop the residual normal speed and go on in sustained contact (on this
    // generator, also when the centre is at a closed cone's vertex).
    const State3 before = state_;
    state_.v = state_.v - c.p_after * n;
    opt_.axis_side = b;
    return sustained_contact(false, before);
  }

  FlightStart3 rim_collision() {
    const Vec3 b = meridian_direction(state_.r);
    const Vec3 point = rim_point(cone_, b);
    const Vec3 d = state_.r - point;
    const Vec3 n = (1.0 / norm(d)) * d;
    state_.r = point + g_.radius * n;  // exactly at distance a from the rim circle
    ++out_.edge_collisions;
    const Collision3 c = apply_collision(EventKind::Edge, n, azimuthal_direction(b));
    FlightStart3 start;
    start.on_rim = true;
    if (c.p_after >= params_.p_c) return start;
    // The chatter on the rim has collapsed: without its residual normal speed the particle
    // stays on the rim (positive normal force needed) or flies off curving away from it.
    State3 tangential = state_;
    tangential.v = state_.v - c.p_after * n;
    if (rim_normal_force(cone_, tangential) > 0.0) return sustained_contact(true, state_);
    start.slow_rim = true;
    return start;
  }

  /// Sustained contact on the face (on_rim false) or the rim, through every hand-over between
  /// them, until the particle flies off, exits, rests or the time cap falls inside it. `before`
  /// is the state before the residual normal speed was dropped.
  FlightStart3 sustained_contact(bool on_rim, const State3& before) {
    State3 entry = before;
    crossing_ = {};
    if (on_rim) {
      const Vec3 d = state_.r - rim_point(cone_, meridian_direction(state_.r));
      const Vec3 n = (1.0 / norm(d)) * d;
      state_.v = state_.v - dot(state_.v, n) * n;
    }
    // Hand-overs go on while time advances (a slowly dissipating orbit about the throat may cross
    // C* many times); many in a row without any time passing are a Zeno loop.
    for (int idle = 0; idle < max_hand_overs;) {
      // A cancelled run (Ctrl-C) stops here too: contacts shorter than the integrator's check
      // interval (1024 steps) never look at the flag, and a ball orbiting across C* hands over
      // between the face and the rim thousands of times (a Python ensemble at 46 degrees went on
      // for a minute after Ctrl-C). Its results are discarded.
      if (opt_.cancel != nullptr && opt_.cancel->load(std::memory_order_relaxed)) {
        end(Status::Trapped, time_);
        return {};
      }
      const double before_phase = time_;
      const Contact3End how = contact_phase(on_rim, entry);
      idle = time_ > before_phase ? 0 : idle + 1;
      if (done_) return {};
      FlightStart3 start;
      if (!on_rim) {
        // At C*: the rim holds the particle if the normal force it needs is positive; otherwise it
        // flies on, tangent to the face and to the rim torus.
        if (!(rim_normal_force(cone_, state_) > 0.0)) {
          start.skip_face = true;
          start.on_rim = true;
          start.slow_rim = true;
          return start;
        }
        if (repeats_cycle()) return {};
      } else if (how != Contact3End::RimTop) {
        start.on_rim = true;  // took off tangentially, curving away from the rim torus
        start.slow_rim = true;
        return start;
      }
      on_rim = !on_rim;
      entry = state_;
    }
    out_.stalled = true;
    end(Status::Trapped, time_);
    return {};
  }

  /// The state of a contact crossing C* down the face onto the rim, up to the symmetry about the
  /// axis: velocity and spin in the local frame (down-slope, azimuthal, normal) and the energy.
  struct Crossing {
    bool valid = false;
    std::array<double, 5> local{};
    double energy = 0.0, time = 0.0, impulse = 0.0, normal_impulse = 0.0, swept = 0.0;
  };

  /// Called at each crossing of C* from the face onto the rim. A contact that crosses C* again in
  /// the same local state with the same energy (a conservative cycle between the face and the
  /// rim: rolling, or frictionless sliding) repeats it forever, since the motion depends on the
  /// local state only (the funnel is axisymmetric): the run is extrapolated to the time cap and
  /// ends trapped. Returns true when it did so.
  bool repeats_cycle() {
    const Vec3 b = meridian_direction(state_.r);
    const Vec3 n = cone_normal(cone_, b);
    const Vec3 down{-g_.cos_t * b.x, -g_.sin_t, -g_.cos_t * b.z};
    const Vec3 across = azimuthal_direction(b);
    Crossing now;
    now.valid = true;
    now.local = {dot(state_.v, down), dot(state_.v, across), dot(state_.omega, n), dot(state_.omega, down),
                 dot(state_.omega, across)};
    now.energy = energy(state_, mat_.kappa, mat_.radius);
    now.time = time_;
    now.impulse = out_.impulse;
    now.normal_impulse = out_.normal_impulse;
    now.swept = swept_;
    const double scale = norm(state_.v) + mat_.radius * norm(state_.omega);
    // Tolerances well above the integrator's error over a cycle (~1e-11) and far below any
    // dissipation that matters over the time cap.
    bool same = crossing_.valid && std::fabs(now.energy - crossing_.energy) <= 1e-9 * std::fmax(now.energy, 1.0);
    for (int i = 0; i < 5 && same; ++i) {
      const double unit = i < 2 ? scale : scale / mat_.radius;
      same = std::fabs(now.local[i] - crossing_.local[i]) <= 1e-7 * unit;
    }
    if (!same || !(now.time > crossing_.time)) {
      crossing_ = now;
      return false;
    }
    const double periods = (params_.t_max - time_) / (now.time - crossing_.time);
    out_.impulse += periods * (now.impulse - crossing_.impulse);
    out_.normal_impulse += periods * (now.normal_impulse - crossing_.normal_impulse);
    out_.contact_time += params_.t_max - time_;
    swept_ += periods * (now.swept - crossing_.swept);
    out_.periodic = true;
    end(Status::Trapped, params_.t_max);
    return true;
  }

  /// One sustained contact on the face or the rim from state_ (tangential). `entry` is the state
  /// before the residual normal speed of a collapse was dropped (or state_).
  Contact3End contact_phase(bool on_rim, const State3& entry) {
    ++(on_rim ? out_.edge_contacts : out_.contacts);
    const double lost = energy(entry, mat_.kappa, mat_.radius) - energy(state_, mat_.kappa, mat_.radius);
    out_.energy_loss_events += lost;
    opt_.t_budget = params_.t_max - time_;
    const Contact3Result res =
        on_rim ? rim_contact(state_, cone_, mat_, opt_) : face_contact(state_, cone_, mat_, opt_);
    out_.ode_steps += res.steps;
    if (events_ != nullptr) {
      Event3 e = base_event(on_rim ? EventKind::EdgeContactStart : EventKind::ContactStart);
      e.velocity_before = entry.v;
      e.omega_before = entry.omega;
      e.regime = res.first_regime;
      e.energy_lost = lost;
      events_->record(e);
    }
    if (res.closed_form && time_ + res.duration > params_.t_max) {
      end(Status::Trapped, params_.t_max);  // the cap falls inside the contact (as in 2D)
      return Contact3End::TimeCap;
    }
    time_ += res.duration;
    out_.contact_time += res.duration;
    out_.impulse += res.impulse;
    out_.normal_impulse += res.normal_impulse;
    swept_ += res.swept;
    const State3 arrived = res.end;
    state_ = res.end;
    double lost_end = res.energy_lost;
    const Vec3 b = meridian_direction(state_.r);
    if (res.how == Contact3End::RimTop || (!res.closed_form && res.how == Contact3End::FaceEnd)) {
      // Exactly at C*, tangent to the face: no drift accumulates over hand-overs (the closed form
      // of the face already ends there; the rim's is snapped as in 2D).
      state_.r = {g_.x_face_end * b.x, g_.y_face_end, g_.x_face_end * b.z};
      if (res.closed_form) {
        const Vec3 down{-g_.cos_t * b.x, -g_.sin_t, -g_.cos_t * b.z};
        state_.v = dot(state_.v, down) * down;
      } else {
        const Vec3 n = cone_normal(cone_, b);
        state_.v = state_.v - dot(state_.v, n) * n;
      }
    } else if (res.how == Contact3End::Exit) {
      state_.r.y = g_.y_bottom;
    } else if (res.how == Contact3End::Rest) {
      // A closed funnel's contact ends at rest: the kinetic energy left is booked as lost.
      lost_end += energy(arrived, mat_.kappa, mat_.radius) - arrived.r.y;
      state_.v = {};
      state_.omega = {};
    }
    out_.energy_loss_events += lost_end;
    if (events_ != nullptr) {
      Event3 e = base_event(on_rim ? EventKind::EdgeContactEnd : EventKind::ContactEnd);
      e.position = arrived.r;
      e.velocity_before = arrived.v;
      e.omega_before = arrived.omega;
      e.regime = res.last_regime;
      e.j_n = res.normal_impulse;
      e.contact_impulse = res.contact_impulse;
      e.energy_lost = lost_end;
      events_->record(e);
    }
    switch (res.how) {
      case Contact3End::Exit: exit_here(); break;
      case Contact3End::Rest: end(Status::Rest, time_); break;
      case Contact3End::Periodic: out_.periodic = true; end(Status::Trapped, params_.t_max); break;
      case Contact3End::TimeCap:
        // A guard of the integrator fired, not the cap: the contact ended before its budget (the
        // cap less the time before it; time_ + budget can round 1 ulp below t_max).
        out_.stalled = res.duration < opt_.t_budget;
        end(Status::Trapped, time_);
        break;
      default: break;
    }
    return res.how;
  }

  Event3 base_event(EventKind kind) const {
    Event3 e;
    e.time = time_;
    e.kind = kind;
    e.position = state_.r;
    e.velocity_before = state_.v;
    e.omega_before = state_.omega;
    e.velocity_after = state_.v;
    e.omega_after = state_.omega;
    return e;
  }

  void log(const Event3& e) {
    if (events_ != nullptr) events_->record(e);
  }

  const Params& params_;
  const Cone& cone_;
  const Geometry& g_;
  const Material mat_;
  const CollisionConstants law_;
  EventSink3* sink_;
  EventSink3* events_;  ///< sink_ if it records events (EventSink::records), else null
  State3 state_;
  FlightStart3 start_;
  int stalled_ = 0;  ///< events in a row without time advancing
  Contact3Options opt_;
  double time_ = 0.0;
  double e0_ = 0.0;
  double swept_ = 0.0;
  Crossing crossing_;
  bool done_ = false;
  Trajectory3 out_;
};

}  // namespace

Trajectory3 simulate_3d(const Params& params, const Cone& cone, const State3& initial, EventSink3* sink) {
  return Run3(params, cone, initial, sink).finish();
}

void simulate_3d_many(const Params& params, const Cone& cone, std::span<const State3> initial,
                      std::span<Trajectory3> out, const std::atomic<bool>* cancel) {
  // Up to max_face_lanes runs at once, each a Run3 as simulate_3d's; at every turn the face times
  // of all their flights are found together (cone_face_times, the same bits), then each run
  // takes its step. A run that ends hands its lane to the next trajectory.
  constexpr std::size_t lanes = max_face_lanes;
  std::array<std::optional<Run3>, lanes> run;
  std::array<std::size_t, lanes> index{};
  std::array<State3, lanes> states;
  std::array<FlightStart3, lanes> starts;
  std::array<double, lanes> face_times{};
  std::size_t next = 0;
  const auto stopped = [&] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); };
  const auto launch = [&](std::size_t lane) {
    run[lane].reset();
    if (next < initial.size() && !stopped()) {
      index[lane] = next;
      run[lane].emplace(params, cone, initial[next], nullptr, cancel);
      ++next;
    }
  };
  for (std::size_t lane = 0; lane < lanes; ++lane) launch(lane);
  for (;;) {
    std::size_t n = 0;
    for (std::size_t lane = 0; lane < lanes; ++lane) {
      if (!run[lane]) continue;
      states[n] = run[lane]->state();
      starts[n] = run[lane]->start();
      ++n;
    }
    if (n == 0 || stopped()) return;
    cone_face_times(cone, {states.data(), n}, {starts.data(), n}, {face_times.data(), n});
    std::size_t k = 0;
    for (std::size_t lane = 0; lane < lanes; ++lane) {
      if (!run[lane]) continue;
      Run3& r = *run[lane];
      r.step(face_times[k++]);
      if (r.done()) {
        out[index[lane]] = r.result();
        launch(lane);
      }
    }
  }
}

State3 release_state_3d(const Params& params, const Cone& cone, double fraction) {
  State3 s;
  s.r = {fraction * cone.g.half_width, cone.g.y_release, 0.0};
  s.v = {params.release_u, params.release_v, params.release_w};
  s.omega = {params.release_spin_x, params.release_spin_y, params.release_spin};
  return s;
}

Trajectory3 simulate_release_3d(const Params& params, const Cone& cone, double fraction, EventSink3* sink) {
  return simulate_3d(params, cone, release_state_3d(params, cone, fraction), sink);
}

}  // namespace funnel
