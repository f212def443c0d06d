// Event detection for a free flight (docs/model.md §3).
#include "funnel/flight.hpp"

#include <array>
#include <cmath>

#include "funnel/roots.hpp"

namespace funnel {

namespace {

/// How far up the face from C* the foot of the perpendicular from r lies (>= 0: on the wall).
/// Measured along the face, not by height: for nearly flat walls C* is within rounding of the
/// vertex's height (y_face_end = 2e-22 at theta = 1.7e-14 degrees), and a height test took
/// contacts over the gap for face contacts and let the particle fall through the faces
/// (found by fuzz/fuzz_physics). On the centre line it equals the height test.
double up_face(const Geometry& g, Wall wall, Vec2 r) {
  const double ws = wall_sign(wall);
  return ws * g.cos_t * (r.x - ws * g.x_face_end) + g.sin_t * (r.y - g.y_face_end);
}

}  // namespace

double face_time(const Geometry& g, const State& s, Wall wall, const FlightStart& start) {
  if (start.skip_face == wall) return never;  // tangent at C*: a zero-time hit otherwise (Zeno)
  const Vec2 n = face_normal(g, wall);
  const double p = dot(s.v, n);
  // Right after a collision with this face the distance is exactly 0 and the return time 2p/cos.
  double delta0 = start.on_face == wall ? 0.0 : face_distance(g, wall, s.r);
  // Up the face from C*, or anywhere in a closed funnel, a centre behind the centre line would
  // be inside the wall: a negative distance there is rounding, and the contact is now. Without
  // this a release within ~1e-16 of the wall (|x0/L| = 1 - 2^-53) fell through it (found by
  // fuzz/fuzz_physics).
  if (delta0 < 0.0 && (g.closed || up_face(g, wall, s.r) >= 0.0)) delta0 = 0.0;
  const double t = line_arrival_time(delta0, p, g.cos_t);
  if (t == never || g.closed) return t;
  // A face contact needs the foot of the perpendicular on the wall: up the face from C*.
  return up_face(g, wall, advance(s, t).r) >= 0.0 ? t : never;
}

double edge_time(const Geometry& g, const State& s, Wall wall, const FlightStart& start, double t_limit) {
  if (g.closed || start.skip_edge == wall) return never;
  // The edge arc lies at or below C*; the height is concave in time, so a flight that is above
  // C* at both ends of the window cannot touch it.
  const double y_end = s.r.y + s.v.y * t_limit - 0.5 * t_limit * t_limit;
  if (s.r.y > g.y_face_end && y_end > g.y_face_end) return never;
  const Vec2 e = edge_point(g, wall);
  // Nor can a flight whose x stays farther than a from the edge point (x is linear in time).
  const double x_end = s.r.x + s.v.x * t_limit;
  if (std::fmin(s.r.x, x_end) > e.x + g.radius || std::fmax(s.r.x, x_end) < e.x - g.radius) return never;
  const Vec2 d = s.r - e;
  // |d + v t - (0, t^2/2)|^2 - a^2 as a quartic in t.
  std::array<double, 5> c{};
  c[0] = start.on_edge == wall ? 0.0 : dot(d, d) - g.radius * g.radius;
  // After an edge collision that left a normal speed below p_c (e = 0, or the end of a chatter
  // of ever smaller bounces) the rate d.v is rounding noise, and a positive noise made the same
  // edge be found again at t = 0+, time after time, until the Zeno guard (found by
  // fuzz/fuzz_physics). It is taken as 0, as a face collapse drops its residual normal speed;
  // the engine starts such a flight only when it curves away from the circle (docs/model.md §5b).
  c[1] = start.slow_edge == wall ? 0.0 : 2.0 * dot(d, s.v);
  c[2] = dot(s.v, s.v) - d.y;
  c[3] = -s.v.y;
  c[4] = 0.25;
  const double t = first_descending_root(c, t_limit);
  if (t == never) return never;
  // Valid only on the edge side of C* (not up the face from it). A first approach from the
  // other side would come from behind the wall, which the particle cannot reach; a hit within
  // rounding of C* is the same contact as the face's and is accepted.
  return up_face(g, wall, advance(s, t).r) <= 1e-9 * g.radius ? t : never;
}

double exit_time(const Geometry& g, const State& s) {
  if (g.closed) return never;
  const double h = std::fmax(s.r.y - g.y_bottom, 0.0);
  const double v = s.v.y;
  const double root = std::sqrt(v * v + 2.0 * h);
  return v >= 0.0 ? v + root : 2.0 * h / (root - v);
}

NextEvent next_event(const Geometry& g, const State& s, const FlightStart& start) {
  NextEvent ev{EventKind::Face, Wall::Left, never};
  for (const Wall wall : {Wall::Left, Wall::Right}) {
    const double t = face_time(g, s, wall, start);
    if (t < ev.dt) ev = {EventKind::Face, wall, t};
  }
  // Fast path: a face contact is valid only at or above C*, and the height is concave in time,
  // so a flight that starts above C* stays above it until that contact: no edge can be touched
  // and the exit level (below C*) cannot be crossed first.
  if (ev.dt != never && (g.closed || s.r.y > g.y_face_end)) return ev;
  const double t_exit = exit_time(g, s);
  if (t_exit <= ev.dt) ev = {EventKind::Exit, Wall::Left, t_exit};
  // Edges are searched only up to the earliest face or exit event, both over that same window:
  // the last bits of a refined root depend on the window's end, and a mirror-image state must
  // give the mirror-image event (found by fuzz/fuzz_physics: with both edges in reach, the
  // right edge's window used to end at the left edge's time).
  const double window = ev.dt;
  for (const Wall wall : {Wall::Left, Wall::Right}) {
    const double t = edge_time(g, s, wall, start, window);
    if (t < ev.dt) ev = {EventKind::Edge, wall, t};
  }
  return ev;
}

}  // namespace funnel
