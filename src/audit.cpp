// Flight-by-flight audit of an event log against the walls, the edges and the exit.
#include "funnel/audit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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
  missed_exits += o.missed_exits;
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

/// The engine's own precision at an edge, relative to a, for a flight of `duration` from s: the
/// flight's quartic |d + v t - (0, t^2/2)|^2 - a^2 (src/flight.cpp edge_time) has terms up to
/// (|d| + |v| t + t^2/2)^2, whose rounding (~eps of it) moves the contact by ~eps of it / (2a).
/// For a tiny particle this exceeds the audit's tolerance (a = 1.2e-5 at the end of a flight of
/// 1.1 time units up and back: 1.9e-7 a, found by the fuzzer); for the paper's funnel (terms
/// below ~1, a = 0.01) it is at most 4e-11, below audit_tolerance.
double edge_conditioning(const State& s, double duration, Vec2 e, double a) {
  const Vec2 d = s.r - e;
  const double reach = std::hypot(d.x, d.y) + std::hypot(s.v.x, s.v.y) * duration + 0.5 * duration * duration;
  const double ratio = reach / a;
  // Capped: an overlap beyond 1e-3 a is a fault whatever the rounding.
  return std::fmin(16.0 * std::numeric_limits<double>::epsilon() * ratio * ratio, 1e-3);
}

/// Deepest position behind a face's centre line (>= 0, in units of the length) while the foot of
/// the perpendicular lies on the face's region. Both the distance to the line and the position
/// along the face are concave (or linear) in time, so the extremes lie at the ends of the part of
/// the flight that is over the region: the ends of the flight or where the position along the
/// face crosses the region's ends. A flight that ends by passing under a higher lower end
/// (`side_exit`, from the funnel) ends on the vertical through that end, below it: outside the
/// funnel, where a level lowest face's region ends (its C* is above the end), so a point on or
/// beyond that vertical, below the end, is not in any wall and is not counted.
double face_depth(const Face& face, const State& s, double duration, double radius, const Funnel* side_exit = nullptr) {
  std::array<double, 6> times{0.0, duration, -1.0, -1.0, -1.0, -1.0};
  // along(t) = c0 + c1 t + c2 t^2, with c2 = -up_y / 2
  const double c1 = dot(face.up, s.v);
  const double c2 = -0.5 * face.up.y;
  int m = 2;
  for (const double end : {0.0, face.length}) {
    if (!std::isfinite(end)) continue;
    const double c0 = along_face(face, s.r) - end;
    if (c2 == 0.0) {
      if (c1 != 0.0) times[m++] = -c0 / c1;
      continue;
    }
    const double disc = c1 * c1 - 4.0 * c2 * c0;
    if (disc < 0.0) continue;
    const double root = std::sqrt(disc);
    times[m++] = (-c1 - root) / (2.0 * c2);
    times[m++] = (-c1 + root) / (2.0 * c2);
  }
  const double slack = 1e-12 * radius;
  double depth = 0.0;
  for (int i = 0; i < m; ++i) {
    const double t = times[i];
    if (!(t >= 0.0 && t <= duration)) continue;
    const Vec2 r = advance(s, t).r;
    const double along = along_face(face, r);
    if (along < -slack || along > face.length + slack) continue;
    if (side_exit != nullptr && side_exit->side_exit * (r.x - side_exit->side_exit_end.x) >= -slack &&
        r.y < side_exit->side_exit_end.y) {
      continue;
    }
    depth = std::max(depth, -face_distance(face, r));
  }
  return depth;
}

/// Whether a flight that ends in `e` left the funnel before it (docs/model.md §2b): its centre
/// fell through the exit level (the height is concave in time: lowest at an end), or crossed the
/// vertical under a higher lower end, outward, below that end; a run must end there.
bool left_funnel_before(const Funnel& f, const State& s, double duration, const Event& e, double tol) {
  if (f.closed || e.kind == EventKind::Exit) return false;
  const double slack = tol * f.radius;
  if (advance(s, duration).r.y < f.y_exit - slack) return true;
  if (f.side_exit == 0 || !(f.side_exit * s.v.x > 0.0)) return false;
  const double t = (f.side_exit_end.x - s.r.x) / s.v.x;
  return t > 0.0 && t < duration && advance(s, t).r.y < f.side_exit_end.y - slack;
}

}  // namespace

double audit_size(const Funnel& f) {
  return std::fmax(f.half_width + std::fabs(f.x_release_mid), std::fmax(std::fabs(f.y_release), std::fabs(f.y_exit)));
}

FlightAudit audit_flights(const Funnel& f, const State& initial, const std::vector<Event>& events) {
  FlightAudit audit;
  audit.trajectories = 1;
  audit.min_edge_distance = never;
  const double a = f.radius;
  const double tol = audit_tolerance_for(a, audit_size(f));
  State s = initial;
  double t_prev = 0.0;
  bool in_contact = false;
  for (const Event& e : events) {
    if (!in_contact) {
      const double duration = std::fmax(e.time - t_prev, 0.0);
      ++audit.flights;
      for (const Side& side : f.sides) {
        for (const Corner& c : side.corners) {
          if (!c.convex) continue;
          const double dist = min_distance(s, duration, c.point) / a;
          audit.min_edge_distance = std::min(audit.min_edge_distance, dist);
          if (dist < 1.0 - std::fmax(tol, edge_conditioning(s, duration, c.point, a))) ++audit.edge_overlaps;
        }
        // An exit that is not through the exit level is under a higher lower end.
        const bool side_exit = e.kind == EventKind::Exit && f.side_exit != 0 && e.position.y > f.y_exit;
        for (const Face& face : side.faces) {
          const double depth = face_depth(face, s, duration, a, side_exit ? &f : nullptr) / a;
          audit.max_face_depth = std::max(audit.max_face_depth, depth);
          if (depth > tol) ++audit.face_crossings;
        }
      }
      if (left_funnel_before(f, s, duration, e, tol)) ++audit.missed_exits;
    }
    switch (e.kind) {
      case EventKind::ContactStart:
      case EventKind::EdgeContactStart: in_contact = true; break;
      case EventKind::ContactEnd:
      case EventKind::EdgeContactEnd: in_contact = false; break;
      case EventKind::Exit:
        // Between the edge circles: at least a from both lower ends.
        for (const Side& side : f.sides) {
          const Vec2 d = e.position - side.corners[0].point;
          if (std::hypot(d.x, d.y) < a * (1.0 - tol)) ++audit.exits_outside;
        }
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
