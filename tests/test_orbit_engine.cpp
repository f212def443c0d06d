// The period-2 orbit theory (orbit.hpp) against the simulation engine.
#include <gtest/gtest.h>

#include <cmath>

#include "funnel/engine.hpp"
#include "funnel/orbit.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

/// Elastic, always-sticking particle in a closed funnel: the setting of the paper's Sec. IV.
Params orbit_params(double theta, double beta0, double mu = 1e12) {
  Params p = default_params();
  p.theta = theta;
  p.beta0 = beta0;
  p.mu = mu;
  p.e = 1.0;
  p.gap = 0.0;
  return p;
}

orbit::OrbitParams theory(const Params& p) { return {p.theta, p.beta0, p.inertia, p.radius}; }

/// Engine state just after a left-wall collision described by P = (y, u', v', omega').
State on_left_wall(const orbit::State& P, const Geometry& g) {
  State s;
  s.r = {-P[0] / g.tan_t, P[0]};
  s.v = {P[1], P[2]};
  s.omega = P[3];
  return s;
}

/// The collisions of a run, as theory states.
class CollisionLog final : public EventSink {
 public:
  void record(const Event& e) override {
    if (e.kind == EventKind::Face) events.push_back(e);
  }
  std::vector<Event> events;
};

TEST(OrbitEngine, OnePeriodOfTheMapEqualsTwoCollisionsOfTheEngine) {
  for (const double theta : {40.0, 50.0, 60.0, 75.0}) {
    for (const double beta0 : {0.0, 0.31, -0.31}) {
      const Params p = orbit_params(theta, beta0);
      const Geometry g = make_geometry(p);
      const double y_star = 0.4;
      orbit::State P1 = orbit::fixed_point(y_star, theory(p));
      // Off the orbit: every component perturbed, so the maps are checked in general.
      P1[0] *= 1.01;
      P1[1] *= 0.99;
      P1[2] *= 1.02;
      P1[3] = 0.5;
      const orbit::State P3 = orbit::period_map(P1, theory(p));
      Params two = p;
      two.max_collisions = 2;
      CollisionLog log;
      simulate(two, g, on_left_wall(P1, g), &log);
      ASSERT_EQ(log.events.size(), 2u);
      EXPECT_EQ(*log.events[0].wall, Wall::Right);
      EXPECT_EQ(*log.events[1].wall, Wall::Left);
      const Event& e = log.events[1];
      EXPECT_TRUE(near(e.position.y, P3[0], 1e-12)) << theta << " " << beta0;
      EXPECT_TRUE(near(e.velocity_after.x, P3[1], 1e-12, 1e-14)) << theta << " " << beta0;
      EXPECT_TRUE(near(e.velocity_after.y, P3[2], 1e-12, 1e-14)) << theta << " " << beta0;
      EXPECT_TRUE(near(e.omega_after, P3[3], 1e-12, 1e-12)) << theta << " " << beta0;
    }
  }
}

TEST(OrbitEngine, ParticleStartedOnTheOrbitStaysOnItFor10000Collisions) {
  const Params base = orbit_params(60.0, 0.0, 1.0);  // mu = 1: sticking is automatic with zero slip
  Params p = base;
  p.max_collisions = 10000;
  const Geometry g = make_geometry(p);
  const double y_star = 0.3;
  CollisionLog log;
  simulate(p, g, on_left_wall(orbit::fixed_point(y_star, theory(p)), g), &log);
  ASSERT_EQ(log.events.size(), 10000u);
  for (std::size_t i = 0; i < log.events.size(); ++i) {
    const Event& e = log.events[i];
    ASSERT_EQ(*e.wall, i % 2 == 0 ? Wall::Right : Wall::Left) << i;
    ASSERT_TRUE(near(e.position.y, y_star, 1e-9)) << i;
    ASSERT_LT(std::fabs(e.slip_before), 1e-9) << i;
  }
}

/// Deviation from a period-2 orbit: the difference of consecutive heights and the slip.
double deviation(const Event& a, const Event& b) {
  return std::fabs(a.position.y - b.position.y) + std::fabs(b.slip_before);
}

TEST(OrbitEngine, PerturbationDecaysAbove45DegreesAndGrowsBelow) {
  for (const double theta : {60.0, 30.0}) {
    const Params base = orbit_params(theta, 0.0, 1.0);
    Params p = base;
    p.max_collisions = 400;
    const Geometry g = make_geometry(p);
    orbit::State P = orbit::fixed_point(0.3, theory(p));
    P[1] *= 1.0 + 1e-6;
    CollisionLog log;
    simulate(p, g, on_left_wall(P, g), &log);
    ASSERT_GE(log.events.size(), 40u);
    const double early = deviation(log.events[1], log.events[2]);
    const std::size_t n = log.events.size();
    if (theta > 45.0) {
      ASSERT_EQ(n, 400u);
      EXPECT_LT(deviation(log.events[n - 2], log.events[n - 1]), 1e-3 * early);
    } else {
      // Unstable: the deviation grows until the alternating pattern breaks down.
      double late = 0.0;
      for (std::size_t i = 2; i + 1 < n; ++i) late = std::max(late, deviation(log.events[i], log.events[i + 1]));
      EXPECT_GT(late, 1e3 * early);
    }
  }
}

}  // namespace
}  // namespace funnel
