// Event detection in free flight against brute-force searches, and the geometry it relies on.
#include "funnel/flight.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "funnel/roots.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

Params params_at(double theta, double gap = 0.04, double radius = 0.01) {
  Params p = default_params();
  p.theta = theta;
  p.gap = gap;
  p.radius = radius;
  return p;
}

/// Smallest distance of a centre position to the wall segments (the walls themselves, not the
/// centre lines): the particle touches a wall when this equals the radius.
double wall_clearance(const Geometry& g, Vec2 r) {
  double best = 1e300;
  for (const Wall w : {Wall::Left, Wall::Right}) {
    const Vec2 e = edge_point(g, w);
    const Vec2 n = face_normal(g, w);
    const Vec2 up{-n.y, n.x};  // along the wall; pick the direction going up from the edge
    const Vec2 along = up.y > 0 ? up : Vec2{-up.x, -up.y};
    const double s = dot(r - e, along);
    const Vec2 foot = s > 0 ? e + s * along : e;
    const Vec2 d = r - foot;
    best = std::min(best, std::sqrt(dot(d, d)));
  }
  return best;
}

TEST(Geometry, EdgesCentreLinesAndReleaseLineAreConsistent) {
  const Geometry g = make_geometry(params_at(60.0));
  for (const Wall w : {Wall::Left, Wall::Right}) {
    // The edge point lies on the wall surface: a below the centre line.
    EXPECT_TRUE(near(face_distance(g, w, edge_point(g, w)), -g.radius, 1e-14));
    // C* lies on the centre line, a away from the edge.
    const Vec2 c_star{wall_sign(w) * g.x_face_end, g.y_face_end};
    EXPECT_NEAR(face_distance(g, w, c_star), 0.0, 1e-16);
    const Vec2 d = c_star - edge_point(g, w);
    EXPECT_TRUE(near(std::sqrt(dot(d, d)), g.radius, 1e-14));
  }
  EXPECT_TRUE(near(g.y_release - g.y_bottom, 1.0, 1e-15));
  // The release line ends on the centre lines.
  EXPECT_NEAR(face_distance(g, Wall::Right, release_point(g, 1.0)), 0.0, 1e-15);
  EXPECT_NEAR(face_distance(g, Wall::Left, release_point(g, -1.0)), 0.0, 1e-15);
}

TEST(Flight, SameFaceReturnTimeIsTwoPOverCosTheta) {
  const Geometry g = make_geometry(params_at(50.0));
  State s;
  s.r = {-0.6, 0.6 * g.tan_t};  // on the left centre line, high enough to return above C*
  const Vec2 n = face_normal(g, Wall::Left);
  const double p = 0.37;
  s.v = p * n + 0.1 * Vec2{n.y, -n.x};
  FlightStart start;
  start.on_face = WallPart{Wall::Left, 0};
  EXPECT_EQ(face_time(make_funnel(params_at(50.0)), s, {Wall::Left, 0}, start), 2.0 * p / g.cos_t);
}

TEST(Flight, EventTimesMatchBruteForceSearch) {
  // Random flights inside the funnel: the first time the clearance to the walls falls to the
  // radius (fine scan plus bisection) must be the engine's next event time.
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0, edges = 0;
  for (const double theta : {20.0, 45.0, 70.0}) {
    const Params p = params_at(theta, 0.1, 0.03);
    const Geometry g = make_geometry(p);
    const Funnel fn = make_funnel(p);
    for (int i = 0; i < 150; ++i) {
      State s;
      // Start low in the funnel so that edges are often hit.
      const double y = g.y_bottom + 0.01 + 0.3 * u(rng);
      const double half = std::max((y - g.y_face_end) / g.tan_t + g.x_face_end, g.half_gap - g.radius);
      s.r = {(2.0 * u(rng) - 1.0) * half * 0.95, y};
      if (wall_clearance(g, s.r) <= g.radius * 1.01) continue;
      if (face_distance(g, Wall::Left, s.r) < 0 && s.r.y > g.y_face_end) continue;
      if (face_distance(g, Wall::Right, s.r) < 0 && s.r.y > g.y_face_end) continue;
      s.v = {2.0 * u(rng) - 1.0, 2.0 * u(rng) - 1.0};
      const NextEvent ev = next_event(fn, s, FlightStart{});
      ASSERT_NE(ev.dt, never);
      // Brute force over [0, exit] on the clearance function.
      const double t_exit = exit_time(fn, s);
      double t_hit = never;
      const int steps = 20000;
      for (int k = 1; k <= steps && t_hit == never; ++k) {
        const double tk = t_exit * k / steps;
        if (wall_clearance(g, advance(s, tk).r) < g.radius) {
          double lo = t_exit * (k - 1) / steps, hi = tk;
          for (int it = 0; it < 80; ++it) {
            const double mid = 0.5 * (lo + hi);
            (wall_clearance(g, advance(s, mid).r) < g.radius ? hi : lo) = mid;
          }
          t_hit = hi;
        }
      }
      if (t_hit == never) {
        EXPECT_EQ(ev.kind, EventKind::Exit);
        EXPECT_TRUE(near(ev.dt, t_exit, 1e-15));
      } else {
        EXPECT_NE(ev.kind, EventKind::Exit);
        EXPECT_TRUE(near(ev.dt, t_hit, 1e-9, 1e-12)) << "theta " << theta << " case " << i;
        edges += ev.kind == EventKind::Edge;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
  EXPECT_GT(edges, 10);  // the sample really exercises the edge quartic
}

TEST(Flight, LeavingAContactAtTheFaceEndFindsNoZeroTimeEvent) {
  // A particle leaving C* along the face is tangent to the centre line and the edge circle.
  const Geometry g = make_geometry(params_at(60.0));
  for (const double speed : {1e-6, 0.01, 0.5, 3.0}) {
    State s;
    s.r = {-g.x_face_end, g.y_face_end};
    s.v = speed * Vec2{g.cos_t, -g.sin_t};  // down the left face
    FlightStart start;
    start.skip_face = WallPart{Wall::Left, 0};
    start.skip_edge = WallPart{Wall::Left, 0};
    const NextEvent ev = next_event(make_funnel(params_at(60.0)), s, start);
    EXPECT_GT(ev.dt, 1e-6) << speed;
  }
}

/// The edge quartic exactly as edge_time builds it, for a flight d + v t - (0, t^2/2) relative
/// to the edge point (on_edge: the flight starts on the circle, c[0] = 0).
std::array<double, 5> edge_quartic(Vec2 d, Vec2 v, double a, bool on_edge) {
  return {on_edge ? 0.0 : dot(d, d) - a * a, 2.0 * dot(d, v), dot(v, v) - d.y, -v.y, 0.25};
}

TEST(Flight, EdgeQuarticShortcutsNeverSkipARoot) {
  // Flights that pass the edge point at a distance a (1 + delta), from 1e-15 (where rounding
  // decides) to a few a, inside and outside, in every direction, and flights that leave the
  // circle. Wherever a shortcut says "no root", first_descending_root must find none; and the
  // shortcuts must say it for most flights that miss by more than rounding (or they are no use).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double deltas[] = {-1e-3, -1e-9, -1e-13, -1e-15, 0.0, 1e-15, 1e-13, 1e-11, 1e-9, 1e-6, 1e-3, 0.1, 1.0, 5.0};
  long clear = 0, away = 0, roots = 0, misses = 0, missed_by_much = 0, caught = 0;
  for (const double a : {0.01, 1e-4, 0.3}) {
    for (int n = 0; n < 40000; ++n) {
      const double delta = deltas[n % std::size(deltas)];
      // Every seventh flight passes straight beside, above or below the point (exact axes).
      const double phi = n % 7 == 0 ? 0.5 * M_PI * ((n / 7) % 4) : 2.0 * M_PI * unit(rng);
      const Vec2 radial{std::cos(phi), std::sin(phi)};
      const Vec2 p = a * (1.0 + delta) * radial;  // the closest approach, relative to the edge
      const double speed = 2.0 * unit(rng);
      const Vec2 vp = speed * Vec2{-radial.y, radial.x};  // tangent there
      const double t1 = unit(rng) * (n % 3 == 0 ? 1e-3 : 1.0), t2 = unit(rng);
      const Vec2 v{vp.x, vp.y + t1};  // the velocity and position t1 before the approach
      const Vec2 d = p - t1 * v + Vec2{0.0, 0.5 * t1 * t1};
      const double T = t1 + t2;
      const std::array<double, 5> c = edge_quartic(d, v, a, false);
      const bool root = first_descending_root(c, T) != never;
      roots += root;
      const bool is_clear = detail::clears_circle(d, v, T, a), moves_away = detail::moves_away_for_good(c, T);
      ASSERT_FALSE(root && is_clear) << a << " " << delta << " " << phi << " " << t1 << " " << t2;
      ASSERT_FALSE(root && moves_away) << a << " " << delta << " " << phi << " " << t1 << " " << t2;
      clear += is_clear;
      away += moves_away;
      // The closest approach over [0, T]: at an end or where the squared distance's derivative,
      // the cubic t^3 + 3 c3 t^2 + 2 c2 t + c1, vanishes.
      const auto distance_at = [&](double t) {
        const Vec2 r = d + t * v - Vec2{0.0, 0.5 * t * t};
        return std::sqrt(dot(r, r));
      };
      double closest = std::min(distance_at(0.0), distance_at(T));
      std::array<double, 3> crit{};
      const int n_crit = cubic_real_roots(3.0 * c[3], 2.0 * c[2], c[1], crit);
      for (int k = 0; k < n_crit; ++k) {
        if (crit[k] > 0.0 && crit[k] < T) closest = std::min(closest, distance_at(crit[k]));
      }
      misses += !root;
      // A flight that never comes within a sqrt(2) of the point never enters the square of side
      // 2a around it, and clears_circle must always say so.
      if (closest > 1.42 * a) {
        ++missed_by_much;
        caught += is_clear;
      }
      // Leaving the circle from a point on it (after an edge collision): outward, at any angle.
      const Vec2 out = radial;
      const double s = 0.01 + 2.0 * unit(rng), tilt = (unit(rng) - 0.5) * 3.0;
      const Vec2 v_out = s * Vec2{out.x * std::cos(tilt) - out.y * std::sin(tilt), out.x * std::sin(tilt) + out.y * std::cos(tilt)};
      const Vec2 d_on = a * radial;
      const std::array<double, 5> c_on = edge_quartic(d_on, v_out, a, true);
      if (c_on[1] > 0.0) {
        const double T_on = 3.0 * unit(rng);
        const bool back = first_descending_root(c_on, T_on) != never;
        const bool proved = detail::moves_away_for_good(c_on, T_on);
        ASSERT_FALSE(back && proved) << a << " " << phi << " " << s << " " << tilt << " " << T_on;
        away += proved;
        roots += back;
      }
    }
  }
  EXPECT_GT(roots, 10000);
  EXPECT_GT(misses, 10000);
  EXPECT_GT(clear, 10000);
  EXPECT_GT(away, 10000);
  EXPECT_GT(missed_by_much, 10000);
  EXPECT_EQ(caught, missed_by_much);
}

TEST(Flight, EdgeQuarticShortcutsDeclineWhatTheyCannotProve) {
  const double a = 0.01;
  // A flight through the circle, one that grazes it within rounding, one that starts inside it.
  // (Each flight from (-0.5, y0) with v = (1, 0.5) is at the top of its arc, y0, at x = 0.)
  const Vec2 v{1.0, 0.5};
  const double y0 = -0.125;
  EXPECT_FALSE(detail::clears_circle({-0.5, y0}, v, 1.0, a));
  EXPECT_FALSE(detail::clears_circle({-0.5, y0 + a * (1.0 + 1e-14)}, v, 1.0, a));
  EXPECT_FALSE(detail::clears_circle({0.0, 0.5 * a}, v, 1.0, a));
  // Clear by a: yes, above or below; before it gets there: yes; a window of infinite or NaN
  // length: no.
  EXPECT_TRUE(detail::clears_circle({-0.5, y0 + 2.0 * a}, v, 1.0, a));
  EXPECT_TRUE(detail::clears_circle({-0.5, y0 - 2.0 * a}, v, 1.0, a));
  EXPECT_TRUE(detail::clears_circle({-0.5, y0}, v, 0.4, a));
  EXPECT_FALSE(detail::clears_circle({-0.5, y0 + 2.0 * a}, v, never, a));
  EXPECT_FALSE(detail::clears_circle({-0.5, y0 + 2.0 * a}, v, std::nan(""), a));
  // Moving away only with c[0] >= 0 and c[1] > 0, and not when gravity brings it back in time.
  EXPECT_TRUE(detail::moves_away_for_good(edge_quartic({a, 0.0}, {1.0, 0.0}, a, true), 0.1));
  EXPECT_FALSE(detail::moves_away_for_good(edge_quartic({a, 0.0}, {-1.0, 0.0}, a, true), 0.1));
  EXPECT_FALSE(detail::moves_away_for_good(edge_quartic({0.0, 0.9 * a}, {0.0, 1.0}, a, false), 0.1));
  // Thrown straight up from the top of the circle: back on it at t = 2 v.
  const std::array<double, 5> up = edge_quartic({0.0, a}, {0.0, 0.5}, a, true);
  EXPECT_TRUE(detail::moves_away_for_good(up, 0.9));
  EXPECT_FALSE(detail::moves_away_for_good(up, 1.1));
  EXPECT_NE(first_descending_root(up, 1.1), never);
}

}  // namespace
}  // namespace funnel
