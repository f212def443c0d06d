// Closed-form sliding and rolling along a face (docs/model.md §5).
#include "funnel/contact.hpp"

#include <cmath>

#include "funnel/roots.hpp"

namespace funnel {

namespace {

/// One phase of constant acceleration in down-slope coordinates.
struct Phase {
  double force = 0.0;      // friction force along the down-slope direction
  double accel = 0.0;      // d w / dt
  double slip_rate = 0.0;  // d s_hat / dt
  Regime regime = Regime::Sliding;
};

Phase sliding_phase(double slip_sign, const Geometry& g, const Material& m) {
  Phase ph;
  ph.force = -m.mu * g.cos_t * slip_sign;
  ph.accel = g.sin_t + ph.force;
  ph.slip_rate = g.sin_t + ph.force * (1.0 + 1.0 / m.kappa);
  ph.regime = Regime::Sliding;
  return ph;
}

/// The phase that follows zero slip: rolling if static friction can hold it, else sliding forward.
Phase zero_slip_phase(const Geometry& g, const Material& m) {
  if (g.sin_t * m.kappa <= m.mu * g.cos_t * (1.0 + m.kappa)) {  // tan(theta) <= mu (1 + kappa)/kappa
    Phase ph;
    ph.force = -g.sin_t * m.kappa / (1.0 + m.kappa);
    ph.accel = g.sin_t / (1.0 + m.kappa);
    ph.slip_rate = 0.0;
    ph.regime = Regime::Rolling;
    return ph;
  }
  return sliding_phase(1.0, g, m);
}

}  // namespace

ContactResult slide_to_end(const State& start, Wall wall, const Geometry& g, const Material& m) {
  const double ws = wall_sign(wall);
  // Down-slope unit vector along the face, and the spin measured in the same sense:
  // s_hat = w + a Omega is the down-slope velocity of the contact point.
  const Vec2 down{-ws * g.cos_t, -g.sin_t};
  const double spin_sign = -ws;
  double w = dot(start.v, down);
  double spin = spin_sign * start.omega;
  double slip = w + m.radius * spin;
  // Distance left along the face to its end (C*, or the vertex when closed).
  double remaining = (start.r.y - g.y_face_end) / g.sin_t;

  ContactResult res;
  const double c_cos = g.cos_t;
  auto run_phase = [&](const Phase& ph, double t_limit) {
    // First time the end is reached in this phase: w t + accel t^2/2 = remaining. At the end
    // already: done if moving down; moving up (handed over by the edge), it comes back later.
    const double t_end = remaining > 0.0 ? first_positive_root(0.5 * ph.accel, w, -remaining)
                         : w >= 0.0      ? 0.0
                                         : first_positive_root(0.5 * ph.accel, w, 0.0);
    const double dt = std::fmin(t_end, t_limit);
    res.phases[res.phase_count++] = {remaining, w, ph.accel, ph.force, dt};
    const double ds = w * dt + 0.5 * ph.accel * dt * dt;
    res.duration += dt;
    res.normal_impulse += c_cos * dt;
    res.impulse += std::hypot(c_cos, ph.force) * dt;
    res.tangential_impulse += -ws * ph.force * dt;  // down-slope is -ws times the wall tangent t
    res.energy_lost += -ph.force * (slip * dt + 0.5 * ph.slip_rate * dt * dt);
    remaining -= ds;
    w += ph.accel * dt;
    spin += ph.force / (m.kappa * m.radius) * dt;
    slip += ph.slip_rate * dt;
    res.last_regime = ph.regime;
    return dt >= t_end || remaining <= 0.0;
  };

  bool done = false;
  if (slip != 0.0) {
    const Phase first = sliding_phase(slip > 0.0 ? 1.0 : -1.0, g, m);
    res.first_regime = first.regime;
    // The slip reaches zero only if it decreases in magnitude.
    const double t_stop = slip * first.slip_rate < 0.0 ? -slip / first.slip_rate : never;
    done = run_phase(first, t_stop);
    if (!done) slip = 0.0;  // exactly: the phase ended because the slip vanished
  }
  if (!done) {
    const Phase second = zero_slip_phase(g, m);
    if (res.duration == 0.0) res.first_regime = second.regime;
    run_phase(second, never);  // accel > 0 here, so the end is always reached
  }

  res.end.v = w * down;
  res.end.omega = spin_sign * spin;
  // Place the centre exactly at the end of the face, so no drift accumulates.
  res.end.r = g.closed ? Vec2{0.0, 0.0} : Vec2{ws * g.x_face_end, g.y_face_end};
  return res;
}

}  // namespace funnel
