// Event detection for a free flight (docs/model.md §3), over any funnel's faces and corners.
#include "funnel/flight.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "funnel/roots.hpp"

namespace funnel {

namespace {

const Face& face_of(const Funnel& f, WallPart p) { return f.sides[p.wall == Wall::Left ? 0 : 1].faces[p.index]; }
const Side& side_of(const Funnel& f, Wall w) { return f.sides[w == Wall::Left ? 0 : 1]; }

/// How far beyond a concave end a face's hit still counts (on_region): rounding, far below a.
double concave_slack(const Funnel& f) { return 1e-9 * f.radius; }

/// The foot of r lies on the face's region. Measured along the face, not by height: for nearly
/// flat walls C* is within rounding of the vertex's height, and a height test took contacts over
/// the gap for face contacts and let the particle fall through the faces (found by
/// fuzz/fuzz_physics). At a concave end (where two faces' centre lines meet, or a closed
/// funnel's bottom) within `slack` beyond it: the neighbouring face bounds the region there, and
/// a flight into the corner meets both lines at once. Beyond it the line is no face: where the
/// neighbour ends at a convex corner, the line continued past the meeting point runs into the
/// funnel again (an audit's spout under a shoulder: a ball collided with it in mid-air).
bool on_region(const Face& face, Vec2 r, double slack) {
  const double s = along_face(face, r);
  return s >= (face.low_convex ? 0.0 : -slack) && s <= (face.high_convex ? face.length : face.length + slack);
}

/// When the centre reaches a face's centre line, before the check that it does so on the
/// face's region (face_time without that check).
double line_time(const Funnel& f, const State& s, WallPart part, const FlightStart& start) {
  if (start.skip_face == part) return never;  // tangent at the region's end: a zero-time hit otherwise (Zeno)
  const Face& face = face_of(f, part);
  const double p = dot(s.v, face.n);
  // Right after a collision with this face the distance is exactly 0 and the return time 2p/c.
  double delta0 = start.on_face == part ? 0.0 : face_distance(face, s.r);
  // On the face's region a centre behind the centre line would be inside the wall: a negative
  // distance there is rounding, and the contact is now. Without this a release within ~1e-16
  // of the wall (|x0/L| = 1 - 2^-53) fell through it (found by fuzz/fuzz_physics).
  if (delta0 < 0.0 && on_region(face, s.r, concave_slack(f))) delta0 = 0.0;
  // The distance is delta0 + p t - n_y t^2/2 (gravity's component along the normal is -n_y). A
  // vertical face (n_y = 0) is reached only by moving towards it.
  return face.n.y > 0.0 ? line_arrival_time(delta0, p, face.n.y)
         : p < 0.0      ? (delta0 > 0.0 ? -delta0 / p : 0.0)
                        : never;
}

/// The line is reached at time t (not never) on the face's region.
bool reached_on_region(const Funnel& f, const State& s, WallPart part, double t) {
  // A closed V's faces end at the vertex, where the other face bounds them: nothing to check.
  return (f.closed && f.one_face) || on_region(face_of(f, part), advance(s, t).r, concave_slack(f));
}

}  // namespace

namespace detail {

// Both proofs below show that fl(f) (eval_quartic's value) never goes from > 0 to <= 0 over
// (0, T] for the edge quartic that edge_time builds, so that first_descending_root finds no
// bracket and answers `never`: the same answer edge_time would give, at a fraction of the cost.
// (An independent review searched 4 M near-grazing inputs for a counterexample, 2026-11-24.)

bool clears_circle(Vec2 d, Vec2 v, double T, double a) {
  // R bounds every term: |d|^2 + 2|d||v| t + (|v|^2 + |d_y|) t^2 + |v_y| t^3 + t^4/4 <= R^2 for
  // t <= T (1-norms). The coefficients' rounding moves f by at most gamma_3 (R^2 + a^2), Horner's
  // by gamma_8 times that again; a distance of a + m/2 or more keeps f >= a m, well above both.
  const double R = std::fabs(d.x) + std::fabs(d.y) + (std::fabs(v.x) + std::fabs(v.y)) * T + 0.5 * T * T;
  if (!(R < 0x1p300) || !(a > 0x1p-300) || !(T >= 0.0)) return false;  // scales of normal numbers only
  constexpr double u = 0x1p-53;
  // m also covers this test's own rounding (a few u R on each x or y below) twice over.
  const double m = 32.0 * u * ((R * R + a * a) / a + R);
  const double w = a + m;
  // [ta, tb]: the times of [0, T] when |x| <= w (x is linear in t); elsewhere |x| > a + m/2.
  // (Where t1 or t2 is subnormal their relative error is no longer u, but rounding is monotone:
  // every double t with |x(t)| <= w still lies in the computed [ta, tb].)
  double ta = 0.0, tb = T;
  if (v.x != 0.0) {
    double t1 = (-w - d.x) / v.x, t2 = (w - d.x) / v.x;
    if (t1 > t2) std::swap(t1, t2);
    ta = std::fmax(ta, t1);
    tb = std::fmin(tb, t2);
    if (!(ta <= tb)) return true;
  } else if (std::fabs(d.x) > w) {
    return true;
  }
  // There y = d_y + v_y t - t^2/2 must stay above w (concave: its least value is at an end) or
  // below -w (its greatest value: at t = v_y, or at an end).
  const double ya = d.y + v.y * ta - 0.5 * ta * ta, yb = d.y + v.y * tb - 0.5 * tb * tb;
  if (std::fmin(ya, yb) > w) return true;
  const double y_top = v.y > ta && v.y < tb ? d.y + 0.5 * v.y * v.y : std::fmax(ya, yb);
  return y_top < -w;
}

bool moves_away_for_good(const std::array<double, 5>& c, double T) {
  // f = c0 + t g with g(t) = c1 + c2 t + c3 t^2 + c4 t^3, and fl(f(t)) = fl(fl(y t) + c0) with
  // y = g's Horner value: fl(f(t)) > 0 for t > 0 when y > 0 and c0 >= 0, unless y t underflows
  // to 0. That happens only with c0 = 0 and t below 2^-726, where y is c1 exactly (the bounds
  // below), so fl(c1 t) is 0 up to some t and positive beyond: never > 0 then <= 0. On [0, T], g
  // is at least the least of its Bernstein coefficients b_j, and |y - g| <= gamma_6 G(T) with
  // G(T) = |c1| + |c2| T + |c3| T^2 + c4 T^3; each b_j's own rounding is below 6u G(T).
  if (!(c[0] >= 0.0 && c[4] == 0.25 && c[1] >= 0x1p-300 && T >= 0x1p-300 && T <= 0x1p100)) return false;
  if (!(std::fabs(c[2]) <= 0x1p100 && std::fabs(c[3]) <= 0x1p100)) return false;
  // (These bounds keep the absolute error of any underflow, 2^-1075 per operation, far below
  // the margin, which is at least about 2^-348.)
  constexpr double u = 0x1p-53;
  const double T2 = T * T, T3 = T2 * T;
  const double G = c[1] + std::fabs(c[2]) * T + std::fabs(c[3]) * T2 + c[4] * T3;
  const double margin = 32.0 * u * G;
  const double b1 = c[1] + c[2] * T / 3.0;
  const double b2 = c[1] + 2.0 * c[2] * T / 3.0 + c[3] * T2 / 3.0;
  const double b3 = c[1] + c[2] * T + c[3] * T2 + c[4] * T3;
  return c[1] > margin && b1 > margin && b2 > margin && b3 > margin;
}

}  // namespace detail

double face_time(const Funnel& f, const State& s, WallPart part, const FlightStart& start) {
  const double t = line_time(f, s, part, start);
  return t == never || reached_on_region(f, s, part, t) ? t : never;
}

double edge_time(const Funnel& f, const State& s, WallPart part, const FlightStart& start, double t_limit) {
  if (start.skip_edge == part) return never;
  const Side& side = side_of(f, part.wall);
  const Corner& corner = side.corners[part.index];
  // The edge arc lies at or below its top; the height is concave in time, so a flight that is
  // above the top at both ends of the window cannot touch it.
  const double y_end = s.r.y + s.v.y * t_limit - 0.5 * t_limit * t_limit;
  if (s.r.y > corner.top && y_end > corner.top) return never;
  const Vec2 e = corner.point;
  // Nor can a flight whose x stays farther than a from the edge point (x is linear in time).
  const double x_end = s.r.x + s.v.x * t_limit;
  if (std::fmin(s.r.x, x_end) > e.x + f.radius || std::fmax(s.r.x, x_end) < e.x - f.radius) return never;
  // The quartic's terms reach (|d| + |v| T + T^2/2)^2 over the window T, and their rounding, eps
  // of that, moves the contact by eps (|d| + |v| T + T^2/2)^2 / (2a). For a long flight onto a
  // tiny particle's edge (a fall of 10 H onto a = 1e-6: 2% of a, found by the fuzzer) the flight
  // is expanded instead from where it comes down into the edge's reach (y = top), which it
  // cannot touch before. Only where that bound exceeds 1e-4 a (a reach of 1.7e5 a: 1700 H for
  // the paper's a = 0.01, 17 H for a = 1e-4), so that ordinary runs keep every bit.
  double t0 = 0.0;
  State from = s;
  if (s.r.y > corner.top && start.on_edge != part && start.slow_edge != part) {
    // (With 1-norms, at most sqrt(2) times the 2-norms: cheap on this hot path.)
    const double reach = std::fabs(s.r.x - e.x) + std::fabs(s.r.y - e.y) + (std::fabs(s.v.x) + std::fabs(s.v.y)) * t_limit +
                         0.5 * t_limit * t_limit;
    const double ratio = reach / f.radius;
    if (16.0 * std::numeric_limits<double>::epsilon() * ratio * ratio > 1e-4) {
      // y(t) = top on the way down: t = v + sqrt(v^2 + 2 (y - top)), y > top.
      const double drop = s.r.y - corner.top;
      const double root = std::sqrt(s.v.y * s.v.y + 2.0 * drop);
      t0 = s.v.y >= 0.0 ? s.v.y + root : 2.0 * drop / (root - s.v.y);
      if (!(t0 < t_limit)) return never;
      from = advance(s, t0);
    }
  }
  const Vec2 d = from.r - e;
  // A flight that stays clear of the circle has no root: said without the quartic's cubic
  // (docs/performance.md, "Fifth round"; the same answer, so the same bits).
  if (start.on_edge != part && start.slow_edge != part && detail::clears_circle(d, from.v, t_limit - t0, f.radius)) return never;
  // |d + v t - (0, t^2/2)|^2 - a^2 as a quartic in t.
  std::array<double, 5> c{};
  c[0] = start.on_edge == part ? 0.0 : dot(d, d) - f.radius * f.radius;
  // After an edge collision that left a normal speed below p_c (e = 0, or the end of a chatter
  // of ever smaller bounces) the rate d.v is rounding noise, and a positive noise made the same
  // edge be found again at t = 0+, time after time, until the Zeno guard (found by
  // fuzz/fuzz_physics). It is taken as 0, as a face collapse drops its residual normal speed;
  // the engine starts such a flight only when it curves away from the circle (docs/model.md §5b).
  c[1] = start.slow_edge == part ? 0.0 : 2.0 * dot(d, from.v);
  c[2] = dot(from.v, from.v) - d.y;
  c[3] = -from.v.y;
  c[4] = 0.25;
  // Leaving the circle (after an edge collision, or from beside it) and not coming back to it
  // in the window: the most common flight without a root that is not clear of the circle.
  if (start.slow_edge != part && detail::moves_away_for_good(c, t_limit - t0)) return never;
  const double tau = first_descending_root(c, t_limit - t0);
  if (tau == never) return never;
  const double t = t0 + tau;
  // Valid only on the edge's arc, not on the faces beside it. A first approach from the other
  // side would come from behind the wall, which the particle cannot reach; a hit within rounding
  // of the arc's ends is the same contact as the face's and is accepted.
  const Vec2 hit = advance(s, t).r;
  const double slack = 1e-9 * f.radius;
  if (along_face(side.faces[part.index], hit) > slack) return never;
  if (part.index > 0) {
    const Face& below = side.faces[part.index - 1];
    if (along_face(below, hit) < below.length - slack) return never;
  }
  return t;
}

double exit_time(const Funnel& f, const State& s) {
  if (f.closed) return never;
  const double h = std::fmax(s.r.y - f.y_exit, 0.0);
  const double v = s.v.y;
  const double root = std::sqrt(v * v + 2.0 * h);
  return v >= 0.0 ? v + root : 2.0 * h / (root - v);
}

double side_exit_time(const Funnel& f, const State& s) {
  if (f.side_exit == 0) return never;
  const double gap = f.side_exit_end.x - s.r.x;  // outward: the same sign as side_exit
  if (!(f.side_exit * s.v.x > 0.0) || f.side_exit * gap < 0.0) return never;
  const double t = gap / s.v.x;
  return advance(s, t).r.y < f.side_exit_end.y ? t : never;
}

namespace {

/// The event search. `OneFace`: each wall is one straight face over its outlet edge (the V):
/// the loops then have a known trip count of one (the same arithmetic in the same order).
template <bool OneFace>
[[gnu::always_inline]] inline NextEvent search(const Funnel& f, const State& s, const FlightStart& start) {
  NextEvent ev{EventKind::Face, {}, false, never};
  const Face* hit_face = nullptr;
  if constexpr (OneFace) {
    // The two faces' lines first, the region checked for the earlier one only (and for the
    // other if it fails): the same event as checking both, the left face first on a tie.
    const WallPart left{Wall::Left, 0}, right{Wall::Right, 0};
    const double tl = line_time(f, s, left, start), tr = line_time(f, s, right, start);
    const bool left_first = tl <= tr;
    const WallPart first = left_first ? left : right, second = left_first ? right : left;
    const double t1 = left_first ? tl : tr, t2 = left_first ? tr : tl;
    if (t1 != never && reached_on_region(f, s, first, t1)) {
      ev = {EventKind::Face, first, false, t1};
    } else if (t2 != never && reached_on_region(f, s, second, t2)) {
      ev = {EventKind::Face, second, false, t2};
    }
    if (ev.dt != never) hit_face = &face_of(f, ev.part);
  } else {
    for (const Wall wall : {Wall::Left, Wall::Right}) {
      const Side& side = side_of(f, wall);
      for (int k = 0; k < static_cast<int>(side.faces.size()); ++k) {
        const double t = face_time(f, s, {wall, k}, start);
        if (t < ev.dt) {
          ev = {EventKind::Face, {wall, k}, false, t};
          hit_face = &side.faces[k];
        }
      }
    }
  }
  // Fast path: a face contact is valid only on its region (at a concave end too: on_region),
  // and the height is concave in time, so a flight that starts above every edge arc and ends on
  // a face whose region lies above them too stays above them: no edge can be touched and the
  // exit (below) cannot be crossed. A closed V has no edge (nor exit) at all; a closed
  // profile's convex corners are edges as anywhere.
  if (ev.dt != never &&
      ((f.closed && f.one_face) || (s.r.y > f.skip_height && hit_face->low.y >= f.skip_height))) {
    return ev;
  }
  const double t_exit = exit_time(f, s);
  if (t_exit <= ev.dt) ev = {EventKind::Exit, {}, false, t_exit};
  if (f.side_exit != 0) {
    const double t_side = side_exit_time(f, s);
    if (t_side < ev.dt) ev = {EventKind::Exit, {}, true, t_side};
  }
  // Edges are searched only up to the earliest face or exit event, all over that same window:
  // the last bits of a refined root depend on the window's end, and a mirror-image state must
  // give the mirror-image event (found by fuzz/fuzz_physics: with both edges in reach, the
  // right edge's window used to end at the left edge's time).
  const double window = ev.dt;
  for (const Wall wall : {Wall::Left, Wall::Right}) {
    const Side& side = side_of(f, wall);
    const int corners = OneFace ? 1 : static_cast<int>(side.corners.size());
    for (int k = 0; k < corners; ++k) {
      if (!side.corners[k].convex) continue;
      const double t = edge_time(f, s, {wall, k}, start, window);
      if (t < ev.dt) ev = {EventKind::Edge, {wall, k}, false, t};
    }
  }
  return ev;
}

}  // namespace

// Inlined into the event loop by link-time optimisation: measured 4-7% of the reference
// ensemble's time (docs/performance.md, item 9). GCC warns that an out-of-line function may not
// be inlinable; across files only LTO can, which is the point.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wattributes"
[[gnu::always_inline]] NextEvent next_event(const Funnel& f, const State& s, const FlightStart& start) {
  return f.one_face ? search<true>(f, s, start) : search<false>(f, s, start);
}
#pragma GCC diagnostic pop

}  // namespace funnel
