// Event detection for a free flight in the axisymmetric funnel.
#include "funnel/flight3d.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "batch3d.hpp"
#include "funnel/poly.hpp"
#include "funnel/roots.hpp"
#include "funnel/simd.hpp"

namespace funnel {

namespace {

/// Iterations of the fixed point for the face time before the bracketing fallback.
constexpr int max_face_iterations = 40;

/// Signed distance of r from the centre cone's generator in the half-plane b, n_b . r: the 2D
/// face distance for b = (+-1, 0, 0), with the same operations.
double generator_distance(const Cone& c, Vec3 b, Vec3 r) { return dot(cone_normal(c, b), r); }

/// Distance from the centre cone, cos(theta) y - sin(theta) rho, along the flight.
double cone_distance_at(const Cone& c, const State3& s, double t) {
  const State3 a = advance(s, t);
  return c.g.cos_t * a.r.y - c.g.sin_t * axis_distance(a.r);
}

/// The descending root of the concave distance from the cone on [0, hi], where the distance is
/// <= 0 at hi: bisection from a point where it is positive (t = 0, or its maximum). A fallback
/// for flights on which the fixed point converges slowly (grazing the cone).
double face_time_bracketed(const Cone& c, const State3& s, double hi) {
  auto f = [&](double t) { return cone_distance_at(c, s, t); };
  double lo = 0.0;
  if (!(f(0.0) > 0.0)) {
    // Maximum of the concave function: ternary search.
    double a = 0.0, b = hi;
    for (int it = 0; it < 200 && b - a > 1e-15 * hi; ++it) {
      const double m1 = a + (b - a) / 3.0, m2 = b - (b - a) / 3.0;
      if (f(m1) < f(m2)) a = m1; else b = m2;
    }
    lo = 0.5 * (a + b);
    if (!(f(lo) > 0.0)) return never;
  }
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (f(mid) > 0.0) lo = mid; else hi = mid;
  }
  return hi;
}

/// Intervals of [0, t_end] where a quadratic q0 + q1 t + q2 t^2 is <= bound (inside = true) or
/// >= bound (inside = false); appended to out as (begin, end) pairs. Returns the count.
int quadratic_windows(double q0, double q1, double q2, double bound, bool below, double t_end,
                      std::array<double, 4>& out) {
  // Sign convention: g(t) = q - bound, want g <= 0 (below) or g >= 0.
  const double s = below ? 1.0 : -1.0;
  const double a2 = s * q2, a1 = s * q1, a0 = s * (q0 - bound);  // want a2 t^2 + a1 t + a0 <= 0
  int n = 0;
  auto add = [&](double b, double e) {
    b = std::max(b, 0.0);
    e = std::min(e, t_end);
    if (b <= e) {
      out[static_cast<std::size_t>(n++)] = b;
      out[static_cast<std::size_t>(n++)] = e;
    }
  };
  const double disc = a1 * a1 - 4.0 * a2 * a0;
  if (a2 == 0.0) {
    if (a1 == 0.0) {
      if (a0 <= 0.0) add(0.0, t_end);
    } else {
      const double r = -a0 / a1;
      if (a1 > 0.0) add(0.0, r); else add(r, t_end);
    }
    return n / 2;
  }
  if (disc < 0.0) {
    if (a2 < 0.0) add(0.0, t_end);  // always <= 0
    return n / 2;
  }
  const double root = std::sqrt(disc);
  const double q = -0.5 * (a1 + (a1 < 0.0 ? -root : root));
  double r1 = q / a2, r2 = q != 0.0 ? a0 / q : r1;
  if (r1 > r2) std::swap(r1, r2);
  if (a2 > 0.0) {
    add(r1, r2);  // <= 0 between the roots
  } else {
    add(0.0, r1);  // <= 0 outside them
    add(r2, t_end);
  }
  return n / 2;
}

/// Intersection of two sorted lists of disjoint intervals.
int intersect(const std::array<double, 8>& a, int na, const std::array<double, 4>& b, int nb,
              std::array<double, 8>& out) {
  int n = 0;
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nb; ++j) {
      const double lo = std::max(a[static_cast<std::size_t>(2 * i)], b[static_cast<std::size_t>(2 * j)]);
      const double hi = std::min(a[static_cast<std::size_t>(2 * i + 1)], b[static_cast<std::size_t>(2 * j + 1)]);
      if (lo <= hi && n < 4) {
        out[static_cast<std::size_t>(2 * n)] = lo;
        out[static_cast<std::size_t>(2 * n + 1)] = hi;
        ++n;
      }
    }
  }
  // Sort by start (at most four intervals).
  for (int i = 1; i < n; ++i) {
    for (int j = i; j > 0 && out[static_cast<std::size_t>(2 * j)] < out[static_cast<std::size_t>(2 * j - 2)]; --j) {
      std::swap(out[static_cast<std::size_t>(2 * j)], out[static_cast<std::size_t>(2 * j - 2)]);
      std::swap(out[static_cast<std::size_t>(2 * j + 1)], out[static_cast<std::size_t>(2 * j - 1)]);
    }
  }
  return n;
}

/// The rim octic in the flight's time from the state s:
/// (rho^2 + R^2 + h^2 - a^2)^2 - 4 R^2 rho^2 = (D^2 - a^2)((rho + R)^2 + h^2 - a^2), D the
/// distance from the rim circle; the second factor is positive (R > a), so the octic has the
/// sign of D - a.
Poly rim_octic(const Cone& c, const State3& s) {
  const double R = c.rim_radius, a = c.g.radius;
  const double h0 = s.r.y - c.g.y_bottom;
  Poly rho2;  // rho^2 = A + B t + C t^2
  rho2.degree = 2;
  rho2.c[0] = s.r.x * s.r.x + s.r.z * s.r.z;
  rho2.c[1] = 2.0 * (s.r.x * s.v.x + s.r.z * s.v.z);
  rho2.c[2] = s.v.x * s.v.x + s.v.z * s.v.z;
  Poly h;  // h = h0 + v t - t^2/2
  h.degree = 2;
  h.c[0] = h0;
  h.c[1] = s.v.y;
  h.c[2] = -0.5;
  Poly S = h * h;
  S.c[0] += rho2.c[0] + (R - a) * (R + a);
  S.c[1] += rho2.c[1];
  S.c[2] += rho2.c[2];
  Poly P = S * S;
  const double four_r2 = 4.0 * R * R;
  for (int k = 0; k <= 2; ++k) P.c[static_cast<std::size_t>(k)] -= four_r2 * rho2.c[static_cast<std::size_t>(k)];
  return P;
}

}  // namespace

namespace {

/// One flight's fixed point for the face time (cone_face_time): the half-plane of the current
/// iterate, the one the flight starts in, the best time so far and the iterations done.
struct FaceIterate {
  Vec3 b, b_start;
  double t_best = never;
  int it = 0;
  bool fallback = false;  ///< max_face_iterations reached: the bracketing fallback decides
};

FaceIterate face_start(const State3& s) {
  FaceIterate f;
  f.b = meridian_direction(s.r);
  f.b_start = f.b;
  return f;
}

/// One iteration of the fixed point; false once it has ended (f.t_best is then its result,
/// before the fallback and the check that the hit is on the face).
///
/// The distance from the cone is the minimum over the face's generators (half-planes b) of the
/// distance from the generator's line, each a concave quadratic in t with the 2D face roots.
/// Each is >= the cone's, so each root is >= the cone's; the root for the half-plane of the
/// previous root's position is the next, smaller iterate (a Newton-like step: the two functions
/// touch to first order there). In a meridian plane the first or second iterate is exact.
[[gnu::always_inline]] inline bool face_step(const Cone& c, const State3& s, const FlightStart3& start, int max_iterations, FaceIterate& f) {
  const Geometry& g = c.g;
  const Vec3 n = cone_normal(c, f.b);
  const double p = dot(s.v, n);
  double delta0 = start.on_face && f.b.x == f.b_start.x && f.b.z == f.b_start.z ? 0.0 : generator_distance(c, f.b, s.r);
  // Up the face from C* (anywhere, if closed) a negative distance is rounding: the centre is on
  // the cone (as in 2D, measured along this generator).
  if (delta0 < 0.0 && (g.closed || up_face(c, f.b.x * s.r.x + f.b.z * s.r.z, s.r.y) >= 0.0)) delta0 = 0.0;
  const double t = line_arrival_time(delta0, p, g.cos_t);
  if (t == never) return false;        // this generator is never reached, so neither is the cone
  if (!(t < f.t_best)) return false;   // no progress: converged to the last bits
  f.t_best = t;
  const Vec3 b_next = meridian_direction(advance(s, t).r);
  if (b_next.x == f.b.x && b_next.z == f.b.z) return false;  // a fixed point
  f.b = b_next;
  if (++f.it == max_iterations) {
    f.fallback = true;
    return false;
  }
  return true;
}

/// The face time from the fixed point's end: the fallback if it did not converge, and `never`
/// for a hit below C* (an open funnel's face ends there).
double face_finish(const Cone& c, const State3& s, const FaceIterate& f) {
  const double t_best = f.fallback ? face_time_bracketed(c, s, f.t_best) : f.t_best;
  if (t_best == never || c.g.closed) return t_best;
  const State3 at = advance(s, t_best);
  return up_face(c, axis_distance(at.r), at.r.y) >= 0.0 ? t_best : never;
}

}  // namespace

double cone_face_time(const Cone& c, const State3& s, const FlightStart3& start) {
  return detail::cone_face_time(c, s, start, max_face_iterations);
}

void cone_face_times(const Cone& c, std::span<const State3> s, std::span<const FlightStart3> start,
                     std::span<double> out) {
  detail::cone_face_times(c, s, start, out, max_face_iterations);
}

namespace detail {

double cone_face_time(const Cone& c, const State3& s, const FlightStart3& start, int max_iterations) {
  if (start.skip_face) return never;  // tangent at C*: a zero-time hit otherwise (Zeno)
  FaceIterate f = face_start(s);
  while (face_step(c, s, start, max_iterations, f)) {
  }
  return face_finish(c, s, f);
}

void cone_face_times(const Cone& c, std::span<const State3> s, std::span<const FlightStart3> start,
                     std::span<double> out, int max_iterations) {
  const std::size_t n = std::min(s.size(), max_face_lanes);
  std::array<FaceIterate, max_face_lanes> f;
  if (simd_lanes() > 1) {
    // The fixed points in SIMD lanes (src/batch3d.cpp), each lane the scalar iteration's
    // operations; the fallback and the final check below, one flight at a time.
    static_assert(max_face_lanes <= batch::max_flights);
    batch::FaceFlights lanes;
    const batch::FaceConstants k{c.g.sin_t, c.g.cos_t, c.g.x_face_end, c.g.y_face_end, c.g.closed, max_iterations};
    lanes.n = n;
    for (std::size_t i = 0; i < batch::max_flights; ++i) {
      const bool used = i < n && !start[i].skip_face;
      lanes.active[i] = used ? 1.0 : 0.0;
      if (!used) {
        lanes.rx[i] = lanes.ry[i] = lanes.rz[i] = lanes.vx[i] = lanes.vy[i] = lanes.vz[i] = 0.0;
        lanes.bx[i] = 1.0;
        lanes.bz[i] = lanes.on_face[i] = 0.0;
        continue;
      }
      f[i] = face_start(s[i]);
      lanes.rx[i] = s[i].r.x;
      lanes.ry[i] = s[i].r.y;
      lanes.rz[i] = s[i].r.z;
      lanes.vx[i] = s[i].v.x;
      lanes.vy[i] = s[i].v.y;
      lanes.vz[i] = s[i].v.z;
      lanes.bx[i] = f[i].b.x;
      lanes.bz[i] = f[i].b.z;
      lanes.on_face[i] = start[i].on_face ? 1.0 : 0.0;
    }
    batch::face_times(k, lanes);
    for (std::size_t i = 0; i < n; ++i) {
      f[i].t_best = lanes.t_best[i];
      f[i].fallback = lanes.fallback[i] != 0.0;
    }
  } else {
    // The scalar engine: the flights' fixed points advance together, one iteration of each in
    // turn; each is a chain of dependent square roots and divisions, and the processor overlaps
    // the independent chains.
    std::array<std::size_t, max_face_lanes> active{};
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (start[i].skip_face) continue;
      f[i] = face_start(s[i]);
      active[m++] = i;
    }
    while (m > 0) {
      std::size_t kept = 0;
      for (std::size_t j = 0; j < m; ++j) {
        const std::size_t i = active[j];
        if (face_step(c, s[i], start[i], max_iterations, f[i])) active[kept++] = i;
      }
      m = kept;
    }
  }
  for (std::size_t i = 0; i < n; ++i) out[i] = start[i].skip_face ? never : face_finish(c, s[i], f[i]);
}

}  // namespace detail

double rim_time(const Cone& c, const State3& s, const FlightStart3& start, double t_limit) {
  const Geometry& g = c.g;
  if (g.closed || !(t_limit > 0.0)) return never;
  const double a = g.radius, R = c.rim_radius;
  // The rim's arc lies at or below C*: a flight above the slab h <= a (height concave in time)
  // at both ends of the window cannot touch it.
  const double slab = g.y_bottom + a * (1.0 + 1e-6);
  const double y_end = s.r.y + s.v.y * t_limit - 0.5 * t_limit * t_limit;
  if (s.r.y > slab && y_end > slab) return never;
  // Windows where the centre is in the slab and in the annulus (R - a)^2 <= rho^2 <= (R + a)^2,
  // slightly enlarged so that rounding of their ends cannot hide a root.
  const double pad = 1.0 + 1e-6;
  std::array<double, 4> w1{}, w2{}, w3{};
  const int n1 = quadratic_windows(s.r.y, s.v.y, -0.5, slab, true, t_limit, w1);
  const double A = s.r.x * s.r.x + s.r.z * s.r.z, B = 2.0 * (s.r.x * s.v.x + s.r.z * s.v.z),
               C = s.v.x * s.v.x + s.v.z * s.v.z;
  const int n2 = quadratic_windows(A, B, C, (R + a * pad) * (R + a * pad), true, t_limit, w2);
  // In a ring less than 1e-6 a wider than the ball the enlarged inner radius R - a pad is below
  // 0: then there is no inner bound (squaring it would exclude the centres within |R - a pad| of
  // the axis, where such a ring's far side is hit: docs/robustness.md, finding 24).
  const double inner = std::fmax(0.0, R - a * pad);
  int n3 = 1;
  w3[0] = 0.0;
  w3[1] = t_limit;
  if (inner > 0.0) n3 = quadratic_windows(A, B, C, inner * inner, false, t_limit, w3);
  std::array<double, 8> cur{}, next{};
  int n = 0;
  for (int i = 0; i < n1; ++i) {
    cur[static_cast<std::size_t>(2 * i)] = w1[static_cast<std::size_t>(2 * i)];
    cur[static_cast<std::size_t>(2 * i + 1)] = w1[static_cast<std::size_t>(2 * i + 1)];
  }
  n = intersect(cur, n1, w2, n2, next);
  n = intersect(next, n, w3, n3, cur);
  for (int i = 0; i < n; ++i) {
    const double t0 = cur[static_cast<std::size_t>(2 * i)], t1 = cur[static_cast<std::size_t>(2 * i + 1)];
    // Expand about the window's start, so that the octic's coefficients are well conditioned.
    const State3 at = advance(s, t0);
    Poly P = rim_octic(c, at);
    if (t0 == 0.0 && start.on_rim) {
      P.c[0] = 0.0;  // exactly on the rim: the root at t = 0 is not found again
      if (start.slow_rim) P.c[1] = 0.0;  // tangential departure: a double root at 0
    }
    const double tau = first_descending_root(P, t1 - t0);
    if (tau == never) continue;
    double t = t0 + tau;
    // Polish on the distance from the rim's point in the half-plane of the hit, P_b, a quartic
    // in t as in 2D (and the same one, bit for bit, for a flight in a meridian plane). It is >= the
    // distance from the circle and touches it at the hit, so its first root is the same time.
    const Vec3 b_hit = meridian_direction(advance(s, t).r), b_start = meridian_direction(s.r);
    const bool same_point = b_hit.x == b_start.x && b_hit.z == b_start.z;  // the flight starts on P_b
    const Vec3 point = rim_point(c, b_hit);
    const Vec3 d = s.r - point;
    std::array<double, 5> q{};
    q[0] = start.on_rim && same_point ? 0.0 : dot(d, d) - a * a;
    q[1] = start.slow_rim && same_point ? 0.0 : 2.0 * dot(d, s.v);
    q[2] = dot(s.v, s.v) - d.y;
    q[3] = -s.v.y;
    q[4] = 0.25;
    const double polished = first_descending_root(q, t_limit);
    if (std::fabs(polished - t) <= 1e-9 * (t + a)) t = polished;
    // Valid only on the rim's side of C*: an approach from the face's side is the face contact.
    const State3 hit = advance(s, t);
    return up_face(c, axis_distance(hit.r), hit.r.y) <= 1e-9 * a ? t : never;
  }
  return never;
}

double exit_time(const Cone& c, const State3& s) {
  if (c.g.closed) return never;
  const double h = std::fmax(s.r.y - c.g.y_bottom, 0.0);
  const double v = s.v.y;
  const double root = std::sqrt(v * v + 2.0 * h);
  return v >= 0.0 ? v + root : 2.0 * h / (root - v);
}

NextEvent3 next_event(const Cone& c, const State3& s, const FlightStart3& start) {
  return next_event(c, s, start, cone_face_time(c, s, start));
}

NextEvent3 next_event(const Cone& c, const State3& s, const FlightStart3& start, double face_time) {
  NextEvent3 ev{EventKind::Face, face_time};
  // A face contact is valid only at or above C* and the height is concave in time: a flight that
  // starts above C* stays above it until that contact (no rim, no exit first).
  if (ev.dt != never && (c.g.closed || s.r.y > c.g.y_face_end)) return ev;
  const double t_exit = exit_time(c, s);
  if (t_exit <= ev.dt) ev = {EventKind::Exit, t_exit};
  const double t_rim = rim_time(c, s, start, ev.dt);
  if (t_rim < ev.dt) ev = {EventKind::Edge, t_rim};
  return ev;
}

}  // namespace funnel
