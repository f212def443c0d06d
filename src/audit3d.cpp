// Flight-by-flight audit of a 3D event log against the cone face, the rim and the outlet.
#include "funnel/audit3d.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "funnel/flight3d.hpp"
#include "funnel/poly.hpp"
#include "funnel/roots.hpp"

namespace funnel {

void FlightAudit3::merge(const FlightAudit3& o) {
  if (o.flights > 0 && (flights == 0 || o.min_rim_distance < min_rim_distance)) min_rim_distance = o.min_rim_distance;
  flights += o.flights;
  rim_overlaps += o.rim_overlaps;
  face_crossings += o.face_crossings;
  exits_outside += o.exits_outside;
  trajectories += o.trajectories;
  trajectories_overlapping += o.trajectories_overlapping;
  max_face_depth = std::max(max_face_depth, o.max_face_depth);
}

namespace {

/// Length of the pieces a flight is cut into for the rim check, units sqrt(H/g): short enough
/// that the octic of each piece, expanded about its start, is well conditioned.
constexpr double piece_length = 0.02;
/// Samples of the part of a flight behind the centre cone, checked for lying on the face.
constexpr int face_samples = 256;

double rim_distance(const Cone& c, Vec3 r) {
  const double rho = std::hypot(r.x, r.z);
  return std::hypot(rho - c.rim_radius, r.y - c.g.y_bottom);
}

/// Smallest distance from the rim circle over a flight of the given duration: at the ends of
/// its pieces and at the critical points of the rim octic (which has the sign of D - a and is
/// stationary within rounding where D is, near D = a).
double min_rim_distance(const Cone& c, const State3& s, double duration) {
  const double a = c.g.radius, R = c.rim_radius;
  double best = std::min(rim_distance(c, s.r), rim_distance(c, advance(s, duration).r));
  const int pieces = static_cast<int>(std::min(1e5, std::ceil(duration / piece_length)));
  for (int k = 0; k < pieces; ++k) {
    const double t0 = duration * k / pieces, t1 = duration * (k + 1) / pieces;
    const State3 at = advance(s, t0);
    const State3 end = advance(s, t1);
    // The piece is far from the rim if it stays above its slab or outside its annulus.
    if (std::min(at.r.y, end.r.y) > c.g.y_bottom + 2.0 * a) continue;
    const double rho0 = std::hypot(at.r.x, at.r.z), rho1 = std::hypot(end.r.x, end.r.z);
    const double speed = std::hypot(at.v.x, at.v.z);
    if (std::min(rho0, rho1) - speed * (t1 - t0) > R + 2.0 * a || std::max(rho0, rho1) < R - 2.0 * a) continue;
    // (rho^2 + R^2 + h^2 - a^2)^2 - 4 R^2 rho^2 in the piece's time.
    const double h0 = at.r.y - c.g.y_bottom;
    Poly rho2, h;
    rho2.degree = 2;
    rho2.c = {at.r.x * at.r.x + at.r.z * at.r.z, 2.0 * (at.r.x * at.v.x + at.r.z * at.v.z), at.v.x * at.v.x + at.v.z * at.v.z};
    h.degree = 2;
    h.c = {h0, at.v.y, -0.5};
    Poly S = h * h;
    for (int i = 0; i < 3; ++i) S.c[static_cast<std::size_t>(i)] += rho2.c[static_cast<std::size_t>(i)];
    S.c[0] += (R - a) * (R + a);
    Poly P = S * S;
    for (int i = 0; i < 3; ++i) P.c[static_cast<std::size_t>(i)] -= 4.0 * R * R * rho2.c[static_cast<std::size_t>(i)];
    std::array<double, 8> crit{};
    const int n = real_roots(P.derivative(), 0.0, t1 - t0, crit);
    for (int i = 0; i < n; ++i) best = std::min(best, rim_distance(c, advance(at, crit[static_cast<std::size_t>(i)]).r));
    best = std::min(best, rim_distance(c, end.r));
  }
  return best;
}

/// Deepest position behind the centre cone while the foot of the perpendicular lies on the face
/// (>= 0, units of length). The distance from the cone is concave along a flight, so it is
/// negative on at most two intervals at the ends of the flight; those are sampled for lying on the face.
double face_depth(const Cone& c, const State3& s, double duration) {
  auto depth_at = [&](double t) {
    const State3 a = advance(s, t);
    const double rho = std::hypot(a.r.x, a.r.z);
    const bool on_face = c.g.closed || up_face(c, rho, a.r.y) >= -1e-12 * c.g.radius;
    return on_face ? std::max(0.0, -(c.g.cos_t * a.r.y - c.g.sin_t * rho)) : 0.0;
  };
  double depth = std::max(depth_at(0.0), depth_at(duration));
  for (int k = 1; k < face_samples; ++k) depth = std::max(depth, depth_at(duration * k / face_samples));
  return depth;
}

}  // namespace

FlightAudit3 audit_flights_3d(const Cone& c, const State3& initial, const std::vector<Event3>& events) {
  FlightAudit3 audit;
  audit.trajectories = 1;
  audit.min_rim_distance = never;
  const double a = c.g.radius;
  State3 s = initial;
  double t_prev = 0.0;
  bool in_contact = false;
  for (const Event3& e : events) {
    if (!in_contact) {
      const double duration = std::fmax(e.time - t_prev, 0.0);
      ++audit.flights;
      if (!c.g.closed) {
        const double dist = min_rim_distance(c, s, duration) / a;
        audit.min_rim_distance = std::min(audit.min_rim_distance, dist);
        if (dist < 1.0 - audit_tolerance) ++audit.rim_overlaps;
      }
      const double depth = face_depth(c, s, duration) / a;
      audit.max_face_depth = std::max(audit.max_face_depth, depth);
      if (depth > audit_tolerance) ++audit.face_crossings;
    }
    switch (e.kind) {
      case EventKind::ContactStart:
      case EventKind::EdgeContactStart: in_contact = true; break;
      case EventKind::ContactEnd:
      case EventKind::EdgeContactEnd: in_contact = false; break;
      case EventKind::Exit:
        if (std::hypot(e.position.x, e.position.z) > c.rim_radius - a * (1.0 - audit_tolerance)) ++audit.exits_outside;
        break;
      default: break;
    }
    s.r = e.position;
    s.v = e.velocity_after;
    s.omega = e.omega_after;
    t_prev = e.time;
  }
  if (!audit.clean()) audit.trajectories_overlapping = 1;
  if (audit.flights == 0) audit.min_rim_distance = 0.0;
  return audit;
}

}  // namespace funnel
