// Flight-by-flight audit of an event log against the walls, the edges and the exit.
#include "funnel/audit.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "funnel/flight.hpp"
#include "funnel/roots.hpp"

namespace funnel {

void FlightAudit::merge(const FlightAudit& o) {
  if (o.flights > 0 && (flights == 0 || o.min_edge_distance < min_edge_distance)) {
    min_edge_distance = o.min_edge_distance;
  }
  flights += o.flights;
  edge_overlaps += o.edge_overlaps;
  face_crossings += o.face_crossings;
  exits_outside += o.exits_outside;
  trajectories += o.trajectories;
  trajectories_overlapping += o.trajectories_overlapping;
  max_face_depth = std::max(max_face_depth, o.max_face_depth);
}

namespace {

/// Smallest distance from the point `e` of the parabola that starts in `s`, over [0, duration]:
/// at the ends or where d|r - e|^2/dt = 0, a cubic t^3 - 3 v_y t^2 + 2(|v|^2 - d_y) t + 2 d.v.
double min_distance(const State& s, double duration, Vec2 e) {
  const Vec2 d = s.r - e;
  auto dist = [&](double t) {
    const Vec2 r = advance(s, t).r - e;
    return std::hypot(r.x, r.y);
  };
  double best = std::min(dist(0.0), dist(duration));
  std::array<double, 3> roots{};
  const int n = cubic_real_roots(-3.0 * s.v.y, 2.0 * (dot(s.v, s.v) - d.y), 2.0 * dot(d, s.v), roots);
  for (int k = 0; k < n; ++k) {
    if (roots[k] > 0.0 && roots[k] < duration) best = std::min(best, dist(roots[k]));
  }
  return best;
}

/// Deepest position behind a wall's centre line (>= 0, in units of the length) while the foot of
/// the perpendicular lies on the face. Both the distance to the line and the position along the
/// face are concave quadratics in time, so the extremes lie at the ends of the part of the flight
/// that is over the face: the ends of the flight or the roots of the position along the face.
double face_depth(const Geometry& g, const State& s, double duration, Wall wall) {
  const double ws = wall_sign(wall);
  auto along = [&](Vec2 r) { return ws * g.cos_t * (r.x - ws * g.x_face_end) + g.sin_t * (r.y - g.y_face_end); };
  std::array<double, 4> times{0.0, duration, -1.0, -1.0};
  // along(t) = c0 + c1 t - (sin/2) t^2
  const double c0 = along(s.r);
  const double c1 = ws * g.cos_t * s.v.x + g.sin_t * s.v.y;
  const double c2 = -0.5 * g.sin_t;
  const double disc = c1 * c1 - 4.0 * c2 * c0;
  if (disc >= 0.0 && c2 != 0.0) {
    const double root = std::sqrt(disc);
    times[2] = (-c1 - root) / (2.0 * c2);
    times[3] = (-c1 + root) / (2.0 * c2);
  }
  const double slack = 1e-12 * g.radius;
  double depth = 0.0;
  for (const double t : times) {
    if (!(t >= 0.0 && t <= duration)) continue;
    const Vec2 r = advance(s, t).r;
    if (!g.closed && along(r) < -slack) continue;
    depth = std::max(depth, -face_distance(g, wall, r));
  }
  return depth;
}

}  // namespace

FlightAudit audit_flights(const Geometry& g, const State& initial, const std::vector<Event>& events) {
  FlightAudit audit;
  audit.trajectories = 1;
  audit.min_edge_distance = never;
  const double a = g.radius;
  State s = initial;
  double t_prev = 0.0;
  bool in_contact = false;
  for (const Event& e : events) {
    if (!in_contact) {
      const double duration = std::fmax(e.time - t_prev, 0.0);
      ++audit.flights;
      if (!g.closed) {
        for (const Wall wall : {Wall::Left, Wall::Right}) {
          const double dist = min_distance(s, duration, edge_point(g, wall)) / a;
          audit.min_edge_distance = std::min(audit.min_edge_distance, dist);
          if (dist < 1.0 - audit_tolerance) ++audit.edge_overlaps;
        }
      }
      for (const Wall wall : {Wall::Left, Wall::Right}) {
        const double depth = face_depth(g, s, duration, wall) / a;
        audit.max_face_depth = std::max(audit.max_face_depth, depth);
        if (depth > audit_tolerance) ++audit.face_crossings;
      }
    }
    switch (e.kind) {
      case EventKind::ContactStart:
      case EventKind::EdgeContactStart: in_contact = true; break;
      case EventKind::ContactEnd:
      case EventKind::EdgeContactEnd: in_contact = false; break;
      case EventKind::Exit:
        // Between the edge circles: |x| <= d/2 - a at the level of the edges.
        if (std::fabs(e.position.x) > g.half_gap - a * (1.0 - audit_tolerance)) ++audit.exits_outside;
        break;
      default: break;
    }
    s.r = e.position;
    s.v = e.velocity_after;
    s.omega = e.omega_after;
    t_prev = e.time;
  }
  if (!audit.clean()) audit.trajectories_overlapping = 1;
  if (audit.flights == 0) audit.min_edge_distance = 0.0;
  return audit;
}

}  // namespace funnel
