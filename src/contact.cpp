// Closed-form sliding and rolling along a face (docs/model.md §5).
#include "funnel/contact.hpp"

#include <cmath>
#include <limits>

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

Phase sliding_phase(double slip_sign, const Face& g, const Material& m) {
  Phase ph;
  ph.force = -m.mu * g.cos_a * slip_sign;
  ph.accel = g.sin_a + ph.force;
  ph.slip_rate = g.sin_a + ph.force * (1.0 + 1.0 / m.kappa);
  ph.regime = Regime::Sliding;
  return ph;
}

/// The phase that follows zero slip: rolling if static friction can hold it, else sliding forward.
Phase zero_slip_phase(const Face& g, const Material& m) {
  if (g.sin_a * m.kappa <= m.mu * g.cos_a * (1.0 + m.kappa)) {  // tan(angle) <= mu (1 + kappa)/kappa
    Phase ph;
    ph.force = -g.sin_a * m.kappa / (1.0 + m.kappa);
    ph.accel = g.sin_a / (1.0 + m.kappa);
    ph.slip_rate = 0.0;
    ph.regime = Regime::Rolling;
    return ph;
  }
  return sliding_phase(1.0, g, m);
}

}  // namespace

ContactResult slide_on_face(const State& start, const Face& face, double ws, const Material& m) {
  // Down-slope unit vector along the face, and the spin measured in the same sense:
  // s_hat = w + a Omega is the down-slope velocity of the contact point.
  const Vec2 down = face.down;
  const double spin_sign = -ws;
  double w = dot(start.v, down);
  double spin = spin_sign * start.omega;
  double slip = w + m.radius * spin;
  // Distance up the face from the lower end of its region (C*, a corner, or the vertex of a
  // closed funnel); by height where the face slopes, along it on a ledge.
  double remaining = face.sin_a > 0.0 ? (start.r.y - face.low.y) / face.sin_a : along_face(face, start.r);
  const bool bounded = face.length < std::numeric_limits<double>::infinity();

  ContactResult res;
  const double c_cos = face.cos_a;
  auto run_phase = [&](const Phase& ph, double t_limit) {
    // First time the lower end is reached in this phase: w t + accel t^2/2 = remaining. At the
    // end already: done if moving down, or still and not driven up; moving up (handed over by an
    // edge), or still and driven up (a spin that drives a ball up the face out of a concave
    // corner, found by a review: it ended at once, back in the corner, a thousand times), it
    // comes back later, if at all.
    const double t_low = remaining > 0.0                           ? first_positive_root(0.5 * ph.accel, w, -remaining)
                         : w > 0.0 || (w == 0.0 && ph.accel >= 0.0) ? 0.0
                                                                    : first_positive_root(0.5 * ph.accel, w, 0.0);
    // ... and the upper end of a bounded region: w t + accel t^2/2 = remaining - length. At or
    // past it already (by rounding) it is taken as at the end, as the lower end is: moving up,
    // or still and driven up, done; moving down, it is back when driven up again. A contact
    // that starts in the concave corner at a ledge's end and is driven into it by a spin slid on
    // through the wall, moving up (found by an audit's random profiles) or moving down at
    // 2e-9 while its past-the-end rounding (1e-16) hid the turn (the next audit's).
    const double t_high = !bounded                          ? never
                          : remaining < face.length         ? first_positive_root(0.5 * ph.accel, w, face.length - remaining)
                          : w < 0.0 || (w == 0.0 && ph.accel < 0.0) ? 0.0
                                                            : first_positive_root(0.5 * ph.accel, w, 0.0);
    const double t_end = std::fmin(t_low, t_high);
    if (t_end == never && t_limit == never) {
      // No end is ever reached (only on a ledge, at rest): the contact ends here, at rest.
      res.at_rest = true;
      res.last_regime = ph.regime;
      return true;
    }
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
    res.at_high_end = dt >= t_high && t_high < t_low;
    return dt >= t_end || remaining <= 0.0;
  };

  bool done = false;
  if (slip != 0.0) {
    const Phase first = sliding_phase(slip > 0.0 ? 1.0 : -1.0, face, m);
    res.first_regime = first.regime;
    res.slid = true;
    // The slip reaches zero only if it decreases in magnitude.
    const double t_stop = slip * first.slip_rate < 0.0 ? -slip / first.slip_rate : never;
    done = run_phase(first, t_stop);
    if (!done) slip = 0.0;  // exactly: the phase ended because the slip vanished
  }
  if (!done) {
    const Phase second = zero_slip_phase(face, m);
    if (res.duration == 0.0) res.first_regime = second.regime;
    if (second.regime == Regime::Sliding) res.slid = true;
    run_phase(second, never);  // the end is reached: accel > 0 down a slope; on a ledge it rolls on
  }

  res.end.v = w * down;
  res.end.omega = spin_sign * spin;
  if (res.at_rest) {
    res.end.r = face.low + (-remaining) * face.down;  // where it stopped, `remaining` up from the lower end
    return res;
  }
  // Place the centre exactly at the end of the region, so no drift accumulates.
  res.end.r = res.at_high_end ? face.high : face.low;
  return res;
}

}  // namespace funnel
