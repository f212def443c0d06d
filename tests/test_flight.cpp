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

}  // namespace
}  // namespace funnel
