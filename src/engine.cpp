// The event loop of one trajectory (docs/model.md §3-7).
#include "funnel/engine.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include "batch.hpp"
#include "funnel/contact.hpp"
#include "funnel/edge_contact.hpp"
#include "funnel/wear.hpp"
#include "funnel/roots.hpp"
#include "funnel/simd.hpp"
#include "funnel/watch.hpp"

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

/// Hand-overs between faces and edges within one sustained contact after which the run is
/// stopped as trapped: a guard that no physical contact reaches (each hand-over back up needs
/// friction to reverse the motion, which dissipates energy).
constexpr int max_hand_overs = 1000;
/// Nested hand-overs between two faces at a concave corner before the particle counts as settled
/// in that pocket (each is a call deeper).
constexpr int max_pocket_hand_overs = 256;

int index_of(Wall w) { return w == Wall::Left ? 0 : 1; }

/// The running trajectory: state, clock, observables and the optional log.
class Run {
 public:
  Run(const Params& params, const Funnel& f, const State& initial, EventSink* sink, Wear* wear)
      : params_(params), f_(f), kappa_(params.inertia), radius_(params.radius), sink_(sink),
        events_(sink != nullptr && sink->records() ? sink : nullptr), wear_(wear),
        state_(initial) {
    e0_ = energy(initial, kappa_, radius_);
  }

  Trajectory finish() {
    while (!step()) {
    }
    return result();
  }

  /// The observables once the run has ended (step() returned true).
  Trajectory result() {
    out_.final_state = state_;
    out_.energy_loss = reported_energy_loss(e0_, energy(state_, kappa_, radius_));
    return out_;
  }

  /// One event of the loop: the next event found, the flight to it and what it does. Returns
  /// true once the run has ended.
  bool step() {
    const NextEvent ev = next_event(f_, state_, start_);
    if (!(time_ + ev.dt <= params_.t_max)) {  // also catches dt = never (a closed funnel at rest)
      state_ = advance(state_, std::fmin(params_.t_max - time_, 1e300));
      end(Status::Trapped, params_.t_max);
      return true;
    }
    const double before = time_;
    state_ = advance(state_, ev.dt);
    time_ += ev.dt;
    stalled_ = time_ > before ? 0 : stalled_ + 1;
    if (stalled_ > max_stalled_events) {
      // In a closed funnel collisions pile up in no time only where the faces meet: they have
      // collapsed onto the vertex (a wedge collapse; beta0 = 1 keeps the spin's energy above
      // eps_rest), which is rest (found by fuzz/fuzz_physics). Elsewhere it is the Zeno guard.
      out_.stalled = !f_.closed;
      end(f_.closed ? Status::Rest : Status::Trapped, time_);
      return true;
    }
    switch (ev.kind) {
      case EventKind::Exit:
        if (ev.sideways) {
          state_.r.x = f_.side_exit_end.x;
        } else {
          state_.r.y = f_.y_exit;
        }
        out_.exit_state = state_;
        log_simple(EventKind::Exit, std::nullopt);
        end(Status::Exited, time_);
        return true;
      case EventKind::Face:
        start_ = face_collision(ev.part);
        break;
      case EventKind::Edge:
        start_ = edge_collision(ev.part);
        break;
      default:
        break;
    }
    if (done_) return true;
    if (sink_ != nullptr && sink_->finished()) {
      out_.stopped = true;
      end(Status::Trapped, time_);
      return true;
    }
    if (out_.collisions >= params_.max_collisions) {
      out_.capped = true;
      end(Status::Trapped, time_);
      return true;
    }
    if (f_.closed && energy(state_, kappa_, radius_) - f_.y_vertex < params_.eps_rest) {
      end(Status::Rest, time_);  // the energy above the bottom has run out
      return true;
    }
    return false;
  }

  /// The batched path's view of a run between its events (run_many below copies the lanes'
  /// common steps in and out through it).
  struct Lane {
    State* state;
    double* time;
    Trajectory* out;
    FlightStart* start;
    int* stalled;
  };
  Lane lane() { return {&state_, &time_, &out_, &start_, &stalled_}; }

 private:
  const Side& side(Wall w) const { return f_.sides[index_of(w)]; }
  const Face& face(WallPart p) const { return side(p.wall).faces[p.index]; }
  const Corner& corner(WallPart p) const { return side(p.wall).corners[p.index]; }

  void end(Status status, double time) {
    out_.status = status;
    out_.duration = time;
    done_ = true;
  }

  /// Book-keeping shared by face and edge collisions; returns the collision.
  Collision apply_collision(EventKind kind, WallPart part, Vec2 n) {
    const Collision c = collide(state_, n, side(part.wall).law);
    ++out_.collisions;
    if (c.regime == Regime::Sliding) out_.slid = true;
    const double j = std::sqrt(c.j_n * c.j_n + c.j_t * c.j_t);
    out_.impulse += j;
    out_.normal_impulse += c.j_n;
    out_.energy_loss_events += c.energy_lost;
    if (wear_ != nullptr) {
      if (kind == EventKind::Edge) {
        wear_->add_edge(part.wall, c.j_n, j, true);
      } else {
        const Face& fc = face(part);
        wear_->add_collision(part.wall, fc.surface_offset + along_face(fc, state_.r), c.j_n, j);
      }
    }
    if (events_ != nullptr) {
      Event e = base_event(kind, part.wall);
      e.velocity_after = c.after.v;
      e.omega_after = c.after.omega;
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

  FlightStart face_collision(WallPart part) {
    const Vec2 n = face(part).n;
    // Put the centre exactly on the centre line, so that the next flight starts at distance 0.
    const double delta = face_distance(face(part), state_.r);
    state_.r = state_.r - delta * n;
    return collide_with_face(part);
  }

  /// A collision with a face (the centre on its centre line): a flight from it, or a collapse
  /// into sustained contact.
  FlightStart collide_with_face(WallPart part) {
    const Vec2 n = face(part).n;
    const Collision c = apply_collision(EventKind::Face, part, n);
    if (stalled_ != 0) [[unlikely]] note_pile_up(part);
    if (c.p_after >= params_.p_c && !at_vertex(part)) {
      if (const int lower = slow_at_corner(part); lower >= 0) return from_corner({part.wall, lower});
      FlightStart start;
      start.on_face = part;
      return start;
    }
    // Inelastic collapse: drop the residual normal speed and go on in sustained contact.
    const State before = state_;
    state_.v = state_.v - c.p_after * n;
    return sustained_contact(part, false, before);
  }

  /// A collision on face `part` in no time (stalled_ > 0): at a concave corner, with less kinetic
  /// energy than the one before it (if that one was too), a collision of a collapse into the
  /// corner. It counts as progress, not towards the Zeno guard, up to max_corner_pile_up of them
  /// in a row. Out of line, and step() untouched: the common collision takes time, and a test of
  /// this in step()'s guard slowed the scalar engine by 15%.
  [[gnu::noinline, gnu::cold]] void note_pile_up(WallPart part) {
    const double k = dot(state_.v, state_.v) + kappa_ * radius_ * radius_ * state_.omega * state_.omega;
    if (concave_corner_at(part) < 0 || !(k < (pile_up_ == 0 ? HUGE_VAL : pile_up_energy_)) ||
        pile_up_ >= max_corner_pile_up) {
      pile_up_ = 0;
      return;
    }
    // A collapse's progress, not a stall.
    ++pile_up_;
    pile_up_energy_ = k;
    stalled_ = 0;
  }

  /// A collision on a closed funnel's lowest face with the centre at the vertex to the rounding
  /// of its coordinates (Funnel::vertex_tolerance): the bounces between the two faces have
  /// collapsed onto it, whatever normal speed is left. Closer than that, a flight moves the
  /// centre by less than the rounding of its height while gravity still speeds it up: the
  /// bounces of a frictionless spinning ball (whose spin keeps energy above eps_rest) froze in a
  /// cycle, 10^5 collisions in 10^-4 of time, at a vertex 0.277 H below the origin. At a vertex
  /// at the origin (the V's) the coordinates resolve the collapse to its end.
  bool at_vertex(WallPart part) const {
    return f_.vertex_tolerance > 0.0 && part.index == 0 && state_.r.y - f_.y_vertex < f_.vertex_tolerance;
  }

  /// A particle at a concave corner is still there if its speed is below p_c (a collision with
  /// the next face would collapse at once) or too small to rise 1e-9 a above the corner. (A
  /// spinning ball on a sloping ledge with e = 0 went round contact, corner and collision at
  /// 4e-6 of speed until the pocket guard called it at rest, still spinning at 1244: a review.)
  bool still_at_corner() const {
    const double v2 = dot(state_.v, state_.v);
    return v2 < 2e-9 * radius_ || std::sqrt(v2) < params_.p_c;
  }

  /// After a collision on face `part`: if the centre sits at a concave corner of that face of one
  /// wall, within 1e-9 a of it, and is too slow to rise 1e-9 a above it, the lower of the
  /// corner's two faces; else -1. Such a ball touches both faces: it is still in the corner
  /// (corner_contact). A ball spinning at 10^2-10^3 in a corner bounced there between the faces
  /// at 1e-8 of speed and time, never below p_c (each sliding collision turns spin into speed),
  /// until the collision cap (a directed scan of the held corner).
  int slow_at_corner(WallPart part) const { return still_at_corner() ? concave_corner_at(part) : -1; }

  /// If the centre sits within 1e-9 a of a concave corner of face `part` of one wall (touching
  /// both faces), the lower of the corner's two faces; else -1. Collisions that pile up there in
  /// no time, each losing energy, are a collapse into the corner: a "superball" (beta0 = 1 and
  /// a large mu, so that each collision sticks and reverses the slip) loses only about 1% of its
  /// speed and spin at each, and the Zeno guard stopped it after 1 000 of them, still at 0.03
  /// (the random-profile campaign, tests/test_random_profile.cpp); about 1 100 in all leave it
  /// still there (slow_at_corner).
  int concave_corner_at(WallPart part) const {
    const double tol = 1e-9 * radius_;
    const Side& sd = side(part.wall);
    const Face& fc = face(part);
    const auto near = [&](Vec2 p) {
      const Vec2 d = state_.r - p;
      return dot(d, d) <= tol * tol;
    };
    if (static_cast<std::size_t>(part.index) + 1 < sd.faces.size() && !fc.high_convex && near(fc.high)) return part.index;
    if (part.index > 0 && !fc.low_convex && near(fc.low)) return part.index - 1;
    return -1;
  }

  /// A ball still at the concave corner above face `lower` (slow_at_corner): held there, or on
  /// along one of its faces in sustained contact.
  FlightStart from_corner(WallPart lower) {
    State entry = state_;
    const CornerExit exit = corner_contact(lower, entry);
    if (exit == CornerExit::Done) return {};
    if (exit == CornerExit::Flight) {
      FlightStart start;
      start.on_face = lower;
      return start;
    }
    return sustained_contact(face_from_corner(lower, exit), false, entry);
  }

  FlightStart edge_collision(WallPart part) {
    const Vec2 e = corner(part).point;
    const Vec2 d = state_.r - e;
    const double dist = std::sqrt(dot(d, d));
    const Vec2 n = (1.0 / dist) * d;
    state_.r = e + radius_ * n;  // exactly on the edge circle
    ++out_.edge_collisions;
    const Collision c = apply_collision(EventKind::Edge, part, n);
    FlightStart start;
    if (c.p_after >= params_.p_c) {
      start.on_edge = part;
      return start;
    }
    // The edge chatter has collapsed. Without its residual normal speed the particle either
    // stays on the edge (the normal force it needs is positive) or flies off curving away from
    // the edge circle, whose quartic then has no root at t = 0+ (its linear term taken as 0).
    State tangential = state_;
    tangential.v = state_.v - c.p_after * n;
    if (edge_normal_force(tangential, e, radius_) > 0.0) return sustained_contact(part, true, state_);
    start.on_edge = part;
    start.slow_edge = part;
    return start;
  }

  /// Sustained contact after a collapse on a face (on_edge false) or on a corner's edge, through
  /// every hand-over between faces and edges, until the particle flies off, rests, or the time
  /// cap falls inside it. `before` is the state before the residual normal speed was dropped
  /// (the particle is already tangential in state_ for a face).
  FlightStart sustained_contact(WallPart part, bool on_edge, const State& before) {
    State entry = before;
    if (on_edge) {
      const Vec2 n = (1.0 / radius_) * (state_.r - corner(part).point);
      state_.v = state_.v - dot(state_.v, n) * n;
    }
    for (int hop = 0; hop < max_hand_overs; ++hop) {
      if (!on_edge) {
        const bool high = face_contact(part, entry);
        if (done_) return {};
        const WallPart end_corner{part.wall, high ? part.index + 1 : part.index};
        const Corner& c = corner(end_corner);
        if (!c.convex) {
          // Where two faces meet: the particle runs into the neighbouring face.
          const WallPart next{part.wall, high ? part.index + 1 : part.index - 1};
          if (still_at_corner()) {
            // Still in the corner: held there by both faces, or on along one of them.
            entry = state_;
            const WallPart lower{part.wall, high ? part.index : part.index - 1};
            const CornerExit exit = corner_contact(lower, entry);
            if (exit == CornerExit::Done) return {};
            if (exit != CornerExit::Flight) {
              part = face_from_corner(lower, exit);
              continue;  // from state_, booking the drop from `entry`
            }
            FlightStart start;
            start.on_face = part;
            return start;
          }
          if (!(dot(state_.v, face(next).n) < 0.0)) {
            FlightStart start;
            start.on_face = part;
            return start;
          }
          // A pocket where two faces meet can pass the particle from one to the other and back
          // without end (each collapse a call deeper: a stack overflow, found by an audit's
          // random profiles); that many hand-overs there is the particle settled in it: rest,
          // as in a closed funnel's wedge.
          if (pocket_ >= max_pocket_hand_overs) {
            end(Status::Rest, time_);
            return {};
          }
          ++pocket_;
          const FlightStart start = collide_with_face(next);
          --pocket_;
          return start;
        }
        // At a convex corner: the edge holds the particle if the normal force it needs is
        // positive (v^2 < a cos(angle) at the end of a face); otherwise it flies on, tangent to
        // the face and the edge circle.
        if (!(edge_normal_force(state_, c.point, radius_) > 0.0)) {
          FlightStart start;
          start.skip_face = part;
          if (high) {
            // Up over the corner: the flight rises and falls back, and only the edge stands
            // between it and the wall below the corner (it stays behind the face's line): the
            // edge is searched, from exactly on its circle with no normal speed (an audit's
            // ball slid up a steep face, flew and fell back through it).
            start.on_edge = end_corner;
            start.slow_edge = end_corner;
          } else {
            start.skip_edge = end_corner;
          }
          return start;
        }
        part = end_corner;
      } else {
        const EdgeExit exit = edge_contact_phase(part, entry);
        if (done_) return {};
        if (exit == EdgeExit::TakeOff || (exit == EdgeExit::Low && part.index == 0)) {
          FlightStart start;
          start.skip_edge = part;  // it left the circle tangentially, curving away from it
          return start;
        }
        // Back onto a face: the one above at the lower end of its region, or the one below at
        // its upper end; put the centre exactly there, tangent to the face.
        part = exit == EdgeExit::High ? part : WallPart{part.wall, part.index - 1};
        const Face& fc = face(part);
        const State arrived = state_;
        state_.r = exit == EdgeExit::High ? fc.low : fc.high;
        state_.v = dot(arrived.v, fc.down) * fc.down;
      }
      on_edge = !on_edge;
      entry = state_;
    }
    out_.stalled = true;
    end(Status::Trapped, time_);
    return {};
  }

  enum class CornerExit { Lower, Upper, Flight, Done };

  /// The face a particle goes on along from the corner above face `lower` (exit Lower or Upper).
  static WallPart face_from_corner(WallPart lower, CornerExit exit) {
    return {lower.wall, exit == CornerExit::Lower ? lower.index : lower.index + 1};
  }

  /// A particle still (still_at_corner) at a concave corner of one wall, between face `lower`
  /// and the face above it, with spin w. Sliding on both faces (each slip is a w, the centre
  /// being still), it is held there if the normal forces that balance gravity and the two
  /// frictions, N_A n_A + N_B n_B - mu sgn(w) (N_A t_A + N_B t_B) = (0, 1), are both >= 0; the
  /// frictions then stop the spin at the constant rate mu (N_A + N_B)/(kappa a) (docs/model.md
  /// §2b). Without spin (or friction) a particle held there rests, in a pocket. Otherwise it goes
  /// on along the face that still pushes, the other's force being negative (returned: the lower
  /// or upper face, the centre placed at the corner, still), or flies (no force is a number). A
  /// spinning ball driven into such a corner was passed from face to face in no time until the
  /// Zeno guard stopped it (the random-profile audit's last stalls). Done: the run ended (rest,
  /// or the time cap inside the phase). `entry` is the state on arrival; on return, the state
  /// from which the next contact books its start (the residual speed dropped here).
  CornerExit corner_contact(WallPart lower, State& entry) {
    const Side& sd = side(lower.wall);
    const Face& fa = sd.faces[lower.index];
    const Face& fb = sd.faces[lower.index + 1];
    const double mu = sd.material.mu;
    const double sigma = mu == 0.0 ? 0.0 : entry.omega > 0.0 ? 1.0 : entry.omega < 0.0 ? -1.0 : 0.0;
    // Cramer's rule for the two normal forces. Each face pushes n - mu sgn(w) t per unit normal
    // force (t = (n_y, -n_x)), and the system's determinant is det(n_A, n_B)(1 + mu^2); past
    // mu = 1 numerator and determinant are divided by mu^2 (mu up to 1e308 without overflow).
    const double det = fa.n.x * fb.n.y - fa.n.y * fb.n.x;
    const auto forces = [&](double sgn) -> std::array<double, 2> {
      if (sgn == 0.0) return {-fb.n.x / det, fa.n.x / det};
      if (mu <= 1.0) {
        const double d = det * (1.0 + mu * mu);
        return {-(fb.n.x - mu * sgn * fb.n.y) / d, (fa.n.x - mu * sgn * fa.n.y) / d};
      }
      const double d = mu * det * (1.0 / (mu * mu) + 1.0);
      return {-(fb.n.x / mu - sgn * fb.n.y) / d, (fa.n.x / mu - sgn * fa.n.y) / d};
    };
    std::array<double, 2> n = forces(sigma);
    const auto held = [&] { return n[0] >= 0.0 && n[1] >= 0.0 && std::isfinite(n[0]) && std::isfinite(n[1]); };
    state_.r = fa.high;
    state_.v = {0.0, 0.0};
    // The residual speed (below p_c) is dropped, as after a collapse.
    const double dropped = energy(entry, kappa_, radius_) - energy(state_, kappa_, radius_);
    if (sigma != 0.0 && held()) {
      // Held while the spin runs down: a contact with both faces, logged on the lower one.
      ++out_.contacts;
      out_.energy_loss_events += dropped;
      log_contact_start(EventKind::ContactStart, lower.wall, entry, Regime::Sliding, dropped);
      const double rate = mu * (n[0] + n[1]);  // of the spin, times kappa a
      const double duration = std::fabs(entry.omega) * kappa_ * radius_ / rate;
      if (!(time_ + duration <= params_.t_max)) {
        end(Status::Trapped, params_.t_max);  // the cap falls inside it (observables up to its start)
        return CornerExit::Done;
      }
      const double f_a = -mu * sigma * n[0], f_b = -mu * sigma * n[1];
      time_ += duration;
      out_.slid = true;
      out_.contact_time += duration;
      out_.impulse += (std::hypot(n[0], f_a) + std::hypot(n[1], f_b)) * duration;
      out_.normal_impulse += (n[0] + n[1]) * duration;
      if (wear_ != nullptr) {
        wear_->add_face_phase(lower.wall, {fa.length, 0.0, 0.0, f_a, duration}, n[0], fa.surface_offset);
        wear_->add_face_phase(lower.wall, {0.0, 0.0, 0.0, f_b, duration}, n[1], fb.surface_offset);
      }
      const State spinning = state_;
      state_.omega = 0.0;
      const double lost = energy(spinning, kappa_, radius_) - energy(state_, kappa_, radius_);
      out_.energy_loss_events += lost;
      if (events_ != nullptr) {
        Event e = base_event(EventKind::ContactEnd, lower.wall);  // still, the spin stopped
        e.regime = Regime::Sliding;
        e.j_n = (n[0] + n[1]) * duration;
        e.j_t = (f_a + f_b) * duration;
        e.energy_lost = lost;
        events_->record(e);
      }
      entry = state_;
      n = forces(0.0);
      if (held()) {  // stopped, and gravity alone holds it there
        end(Status::Rest, time_);
        return CornerExit::Done;
      }
      return n[1] < 0.0 ? CornerExit::Lower : CornerExit::Upper;
    }
    if (held()) {  // without spin or friction, gravity alone holds it there
      out_.energy_loss_events += dropped;
      end(Status::Rest, time_);
      return CornerExit::Done;
    }
    if (n[1] < 0.0) return CornerExit::Lower;  // booked by that face's contact, from `entry`
    if (n[0] < 0.0) return CornerExit::Upper;
    out_.energy_loss_events += dropped;
    return CornerExit::Flight;
  }

  /// A sustained contact with a face, from state_ (tangential) to an end of its region; returns
  /// true at the upper end. `entry` is the state before the residual normal speed of a collapse
  /// was dropped (or state_).
  bool face_contact(WallPart part, const State& entry) {
    ++out_.contacts;
    const Side& sd = side(part.wall);
    const Face& fc = face(part);
    const double lost = energy(entry, kappa_, radius_) - energy(state_, kappa_, radius_);
    out_.energy_loss_events += lost;
    const ContactResult res = slide_on_face(state_, fc, sd.ws, sd.material);
    if (res.slid) out_.slid = true;
    log_contact_start(EventKind::ContactStart, part.wall, entry, res.first_regime, lost);
    if (!(time_ + res.duration <= params_.t_max)) {
      // The cap falls inside the contact: stop there (observables up to its start).
      end(Status::Trapped, params_.t_max);
      return false;
    }
    time_ += res.duration;
    out_.contact_time += res.duration;
    out_.impulse += res.impulse;
    out_.normal_impulse += res.normal_impulse;
    if (wear_ != nullptr) {
      for (int k = 0; k < res.phase_count; ++k) wear_->add_face_phase(part.wall, res.phases[k], fc.cos_a, fc.surface_offset);
    }
    const State arrived = res.end;
    state_ = res.end;
    double lost_end = res.energy_lost;
    // At rest at a closed funnel's bottom, or on a ledge.
    const bool rest = res.at_rest || (!res.at_high_end && sd.corners[part.index].bottom);
    if (rest) {
      // A closed funnel's contact ends at its bottom: the particle rests there (docs/model.md §5);
      // on a ledge it stopped where it is.
      lost_end += energy(arrived, kappa_, radius_) - (res.at_rest ? arrived.r.y : f_.y_vertex);
      state_.v = {0.0, 0.0};
      state_.omega = 0.0;
    }
    out_.energy_loss_events += lost_end;
    if (events_ != nullptr) {
      Event e = base_event(EventKind::ContactEnd, part.wall);
      e.position = arrived.r;
      e.velocity_before = arrived.v;
      e.omega_before = arrived.omega;
      e.velocity_after = state_.v;
      e.omega_after = state_.omega;
      e.regime = res.last_regime;
      e.j_n = res.normal_impulse;
      e.j_t = res.tangential_impulse;
      e.energy_lost = lost_end;
      events_->record(e);
    }
    if (rest) end(Status::Rest, time_);
    return res.at_high_end;
  }

  /// A sustained contact with a corner's edge point, from state_ (on the circle, tangential).
  EdgeExit edge_contact_phase(WallPart part, const State& entry) {
    ++out_.edge_contacts;
    // Rolling over an edge reads mu beyond a monotone test (its quadrature's error floor, the
    // search for the loss of rolling): any edge contact counts as depending on mu.
    out_.slid = true;
    const Side& sd = side(part.wall);
    const double lost = energy(entry, kappa_, radius_) - energy(state_, kappa_, radius_);
    out_.energy_loss_events += lost;
    // Arcs are kept in each wall's own left-facing frame: the right wall's contacts are solved in
    // the mirror image, which keeps the engine exactly mirror symmetric.
    const bool mirrored = part.wall == Wall::Right;
    EdgeContactResult res = edge_contact(mirrored ? mirror(state_) : state_, corner(part).arc, sd.material);
    if (mirrored) {
      res.end = mirror(res.end);
      res.tangential_impulse = -res.tangential_impulse;  // t = (n_y, -n_x) mirrors to -t
    }
    log_contact_start(EventKind::EdgeContactStart, part.wall, entry, res.first_regime, lost);
    if (time_ + res.duration > params_.t_max) {
      end(Status::Trapped, params_.t_max);
      return res.exit;
    }
    time_ += res.duration;
    out_.contact_time += res.duration;
    out_.impulse += res.impulse;
    out_.normal_impulse += res.normal_impulse;
    out_.energy_loss_events += res.energy_lost;
    if (wear_ != nullptr) wear_->add_edge(part.wall, res.normal_impulse, res.impulse, false);
    state_ = res.end;
    if (events_ != nullptr) {
      Event e = base_event(EventKind::EdgeContactEnd, part.wall);
      e.regime = res.last_regime;
      e.j_n = res.normal_impulse;
      e.j_t = res.tangential_impulse;
      e.energy_lost = res.energy_lost;
      events_->record(e);
    }
    return res.exit;
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

  /// The start of a sustained contact (face, edge or corner), from `entry` (the state before a
  /// residual speed was dropped, `lost`).
  void log_contact_start(EventKind kind, Wall wall, const State& entry, Regime regime, double lost) {
    if (events_ == nullptr) return;
    Event e = base_event(kind, wall);
    e.velocity_before = entry.v;
    e.omega_before = entry.omega;
    e.regime = regime;
    e.energy_lost = lost;
    events_->record(e);
  }

  void log_simple(EventKind kind, std::optional<Wall> wall) {
    if (events_ != nullptr) events_->record(base_event(kind, wall));
  }

  const Params& params_;
  const Funnel& f_;
  const double kappa_, radius_;
  EventSink* sink_;
  EventSink* events_;  ///< sink_ if it records events (EventSink::records), else null
  Wear* wear_;
  State state_;
  double time_ = 0.0;
  double e0_ = 0.0;
  bool done_ = false;
  Trajectory out_;
  FlightStart start_;  // how the current flight began
  int stalled_ = 0;    // consecutive events without an advance of time
  int pile_up_ = 0;                    // collisions in a row of a collapse into a concave corner (note_pile_up)
  double pile_up_energy_ = HUGE_VAL;   // the kinetic energy (twice, with the spin's) after the last, to compare with
  int pocket_ = 0;     // nested hand-overs at a concave corner (sustained_contact)
};

}  // namespace

Trajectory simulate(const Params& params, const Funnel& f, const State& initial, EventSink* sink, Wear* wear) {
  return Run(params, f, initial, sink, wear).finish();
}

Trajectory simulate(const Params& params, const Geometry&, const State& initial, EventSink* sink, Wear* wear) {
  const Funnel f = make_funnel(params);
  return simulate(params, f, initial, sink, wear);
}

namespace {

/// The batched path runs the flights between the two walls' top faces above every edge arc (the
/// lanes' fast path: src/flight.cpp's search, which then finds no edge and no exit). A funnel
/// qualifies when each wall's top face is straight and rises towards the funnel (n_y > 0) with
/// nothing above it, and either
///  - it is a closed V: the two faces meet at the vertex (the lanes then check no region); or
///  - it is open, every corner of its walls is an edge (convex), and every lower face lies
///    wholly below the highest edge arc (skip_height): a V, a V with a spout, a profile that
///    steepens towards its outlet. A flight that starts above skip_height and lands on a top
///    face's region at or above it stays strictly above skip_height in between (its height is
///    concave in time), so it cannot reach a lower face first: the earlier of the top faces is
///    the event the scalar search finds, in the same operations.
bool batchable(const Funnel& f) {
  for (const Side& s : f.sides) {
    const Face& top = s.faces.back();
    if (top.high_convex || !(top.n.y > 0.0)) return false;
    if (top.low_convex == f.closed) return false;
  }
  if (f.closed) return f.one_face;
  for (const Side& s : f.sides) {
    for (const Corner& c : s.corners) {
      if (!c.convex) return false;
    }
    for (std::size_t k = 0; k + 1 < s.faces.size(); ++k) {
      const Face& fc = s.faces[k];
      if (!(std::fmax(fc.low.y, fc.high.y) < f.skip_height)) return false;
    }
  }
  return true;
}

/// The index of a wall's top face: the lanes' faces.
int top_face(const Funnel& f, Wall w) { return static_cast<int>(f.sides[w == Wall::Left ? 0 : 1].faces.size()) - 1; }

batch::Constants batch_constants(const Params& params, const Funnel& f) {
  batch::Constants k{};
  for (int i = 0; i < 2; ++i) {
    const Face& fc = f.sides[i].faces.back();
    const CollisionConstants& law = f.sides[i].law;
    k.side[i] = {fc.n.x,  fc.n.y,  fc.ref.x, fc.ref.y, fc.low.x, fc.low.y, fc.up.x, fc.up.y,
                 fc.low.y >= f.skip_height ? 1.0 : 0.0,
                 law.e, law.mu, law.one_plus_e, law.slide_factor, law.one_plus_beta0, law.reduced, law.kappa_a,
                 law.half_1_minus_e2, law.half_reduced, law.radius};
  }
  k.skip_height = f.skip_height;
  k.low_landing = k.side[0].low_ok == 0.0 || k.side[1].low_ok == 0.0 ? 1.0 : 0.0;
  k.y_exit = f.y_exit;
  k.t_max = params.t_max;
  k.p_c = params.p_c;
  k.max_collisions = static_cast<double>(params.max_collisions);
  k.closed = f.closed ? 1.0 : 0.0;
  k.y_rest = f.y_vertex;  // as Run's rest test
  k.vertex_tolerance = f.vertex_tolerance;
  k.eps_rest = params.eps_rest;
  k.spin_energy = 0.5 * params.inertia * params.radius * params.radius;
  return k;
}

/// The lanes' code of how a run's flight began.
double start_code(const Funnel& f, const FlightStart& s) {
  if (s.on_edge.has_value() || s.slow_edge.has_value() || s.skip_face.has_value() || s.skip_edge.has_value()) {
    return batch::start_other;
  }
  if (!s.on_face.has_value()) return batch::start_fresh;
  if (s.on_face == WallPart{Wall::Left, top_face(f, Wall::Left)}) return batch::start_left;
  if (s.on_face == WallPart{Wall::Right, top_face(f, Wall::Right)}) return batch::start_right;
  return batch::start_other;
}

void to_lane(const Funnel& f, Run::Lane r, batch::Lanes& l, int i, OrbitWatch* w) {
  l.rx[i] = r.state->r.x;
  l.ry[i] = r.state->r.y;
  l.vx[i] = r.state->v.x;
  l.vy[i] = r.state->v.y;
  l.omega[i] = r.state->omega;
  l.time[i] = *r.time;
  l.impulse[i] = r.out->impulse;
  l.normal_impulse[i] = r.out->normal_impulse;
  l.energy_loss[i] = r.out->energy_loss_events;
  l.collisions[i] = static_cast<double>(r.out->collisions);
  l.start[i] = start_code(f, *r.start);
  l.slid[i] = r.out->slid ? 1.0 : 0.0;
  if (w != nullptr) {
    const OrbitWatch::Memory& m = w->memory();
    l.streak[i] = m.streak;
    l.have_last[i] = m.have_last ? 1.0 : 0.0;
    l.last_wall[i] = m.last_wall == Wall::Left ? 0.0 : 1.0;
    l.last_x[i] = m.last.x;
    l.last_y[i] = m.last.y;
    l.prev_x[i] = m.prev.x;
    l.prev_y[i] = m.prev.y;
  }
}

/// Copies lane i back into its run; returns the collisions the lane computed since it was filled.
std::int64_t from_lane(const Funnel& f, const batch::Lanes& l, int i, Run::Lane r, OrbitWatch* w) {
  const auto collisions = static_cast<std::int64_t>(l.collisions[i]);
  const std::int64_t stepped = collisions - r.out->collisions;
  if (stepped == 0) return 0;  // not stepped in the lanes since it left them
  r.state->r = {l.rx[i], l.ry[i]};
  r.state->v = {l.vx[i], l.vy[i]};
  r.state->omega = l.omega[i];
  *r.time = l.time[i];
  r.out->impulse = l.impulse[i];
  r.out->normal_impulse = l.normal_impulse[i];
  r.out->energy_loss_events = l.energy_loss[i];
  r.out->collisions = collisions;
  r.out->slid = l.slid[i] != 0.0;
  *r.start = FlightStart{};
  if (l.start[i] == batch::start_left) r.start->on_face = WallPart{Wall::Left, top_face(f, Wall::Left)};
  if (l.start[i] == batch::start_right) r.start->on_face = WallPart{Wall::Right, top_face(f, Wall::Right)};
  *r.stalled = 0;  // every step in the lanes advanced time
  if (w != nullptr) {
    OrbitWatch::Memory& m = w->memory();
    m.streak = static_cast<int>(l.streak[i]);
    m.have_last = l.have_last[i] != 0.0;
    m.have_prev = collisions >= 2;  // the watch sees every collision (not carried in the lanes)
    m.last_wall = l.last_wall[i] == 0.0 ? Wall::Left : Wall::Right;
    m.last = {l.last_x[i], l.last_y[i]};
    m.prev = {l.prev_x[i], l.prev_y[i]};
  }
  return stepped;
}

/// simulate_many with or without watches (empty span: none).
std::int64_t run_many(const Params& params, const Funnel& f, std::span<const State> initial, std::span<Trajectory> out,
                      std::span<OrbitWatch> watches, const std::atomic<bool>* cancel = nullptr) {
  const int width = simd_lanes() <= 1 ? 1 : batch::width();
  auto watch_of = [&](std::size_t k) { return watches.empty() ? nullptr : &watches[k]; };
  const auto cancelled = [cancel] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); };
  // (The lanes run the paper's test of the orbit watch, not the two_back one; every watch of a
  // call has the same test, run_closed's.)
  const bool two_back = !watches.empty() && watches[0].test().two_back;
  if (width <= 1 || !batchable(f) || initial.size() < 2 || two_back) {
    for (std::size_t k = 0; k < initial.size() && !cancelled(); ++k) out[k] = simulate(params, f, initial[k], watch_of(k));
    return 0;
  }
  std::int64_t in_lanes = 0;
  batch::Constants constants = batch_constants(params, f);
  if (!watches.empty()) {
    const OrbitTest& test = watches[0].test();
    constants.watch = 1.0;
    constants.window = test.window;
    constants.slip_tol = test.slip_tol;
    constants.height_tol = test.height_tol;
  }
  batch::Lanes lanes{};
  std::array<std::optional<Run>, batch::max_lanes> runs;
  std::array<std::size_t, batch::max_lanes> sample{};
  std::size_t next = 0;
  // A lane takes the next trajectory, or goes idle.
  auto fill = [&](int i) {
    if (next == initial.size()) {
      runs[i].reset();
      lanes.start[i] = batch::start_idle;
      return;
    }
    sample[i] = next;
    runs[i].emplace(params, f, initial[next], watch_of(next), nullptr);
    ++next;
    to_lane(f, runs[i]->lane(), lanes, i, watch_of(sample[i]));
  };
  for (int i = 0; i < batch::max_lanes; ++i) lanes.start[i] = batch::start_idle;
  for (int i = 0; i < width; ++i) fill(i);
  for (;;) {
    if (cancelled()) return in_lanes;  // out is incomplete; the caller discards it
    std::uint32_t need = batch::face_steps(constants, lanes);
    if (need == 0) return in_lanes;  // every lane idle
    // The scalar engine takes each lane's uncommon event, then the lanes go on.
    while (need != 0) {
      const int i = std::countr_zero(need);
      need &= need - 1;
      Run& run = *runs[i];
      in_lanes += from_lane(f, lanes, i, run.lane(), watch_of(sample[i]));
      if (run.step()) {
        out[sample[i]] = run.result();
        fill(i);
      } else {
        to_lane(f, run.lane(), lanes, i, watch_of(sample[i]));
      }
    }
  }
}

}  // namespace

std::int64_t simulate_many(const Params& params, const Funnel& f, std::span<const State> initial,
                           std::span<Trajectory> out, const std::atomic<bool>* cancel) {
  return run_many(params, f, initial, out, {}, cancel);
}

std::int64_t simulate_many(const Params& params, const Funnel& f, std::span<const State> initial,
                           std::span<Trajectory> out, std::span<OrbitWatch> watches) {
  return run_many(params, f, initial, out, watches);
}

State release_state(const Params& params, const Funnel& f, double fraction) {
  State s;
  s.r = release_point(f, fraction);
  s.v = {params.release_u, params.release_v};
  s.omega = params.release_spin;
  return s;
}

State release_state(const Params& params, const Geometry&, double fraction) {
  return release_state(params, make_funnel(params), fraction);
}

Trajectory simulate_release(const Params& params, const Funnel& f, double fraction, EventSink* sink, Wear* wear) {
  return simulate(params, f, release_state(params, f, fraction), sink, wear);
}

Trajectory simulate_release(const Params& params, const Geometry&, double fraction, EventSink* sink, Wear* wear) {
  const Funnel f = make_funnel(params);
  return simulate_release(params, f, fraction, sink, wear);
}

}  // namespace funnel
