// Closed funnel long-time states (paper Figs. 11 and 12).
#include "funnel/closed.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

Params elastic_closed(double theta, double mu) {
  Params p = default_params();
  p.theta = theta;
  p.mu = mu;
  p.e = 1.0;
  p.beta0 = 0.0;
  p.gap = 0.0;
  return p;
}

TEST(Closed, SteepFunnelSendsAlmostEveryReleaseToThePeriodicOrbit) {
  const ClosedResult r = run_closed(elastic_closed(70.0, 1.0), {400, ReleaseDist::Line, 0, false}, {});
  EXPECT_GE(r.periodic_fraction, 0.98);
  EXPECT_EQ(r.periodic + r.rest + r.undecided, 400);
}

TEST(Closed, PeriodicFractionAt50DegreesGrowsWithFriction) {
  double previous = -1.0;
  for (const double mu : {0.01, 0.05, 0.1, 1.0}) {
    const ClosedResult r = run_closed(elastic_closed(50.0, mu), {400, ReleaseDist::Line, 0, false}, {});
    EXPECT_GE(r.periodic_fraction, previous) << mu;
    EXPECT_EQ(r.undecided, 0) << mu;
    previous = r.periodic_fraction;
  }
  EXPECT_LT(run_closed(elastic_closed(50.0, 0.01), {400, ReleaseDist::Line, 0, false}, {}).periodic_fraction, 0.6);
  EXPECT_GT(previous, 0.98);
}

TEST(Closed, PeriodicOrbitHasTwoSymmetricCollisionPointsAtEqualHeight) {
  const ClosedSample s = classify_release(elastic_closed(60.0, 1.0), 0.3, {});
  ASSERT_EQ(s.state, FinalState::Periodic);
  EXPECT_TRUE(near(s.x_last, -s.x_prev, 1e-5));
  EXPECT_TRUE(near(s.y_last, s.y_prev, 1e-5));
  // On the centre lines: y = |x| tan(theta).
  EXPECT_TRUE(near(s.y_last, std::fabs(s.x_last) * std::tan(60.0 * 3.14159265358979323846 / 180.0), 1e-12));
}

TEST(Closed, InelasticClosedFunnelAlwaysComesToRest) {
  Params p = elastic_closed(50.0, 1.0);
  p.e = 0.9;
  const ClosedResult r = run_closed(p, {100, ReleaseDist::Line, 0, false}, {});
  EXPECT_EQ(r.rest, 100);
  for (const ClosedSample& s : r.samples) EXPECT_EQ(s.x_last, 0.0);
}

TEST(Closed, ShallowFunnelHasNoPeriodicOrbit) {
  // Below 45 degrees the period-2 orbit is unstable: no release settles on it.
  const ClosedResult r = run_closed(elastic_closed(35.0, 1.0), {200, ReleaseDist::Line, 0, false}, {});
  EXPECT_EQ(r.periodic, 0);
  EXPECT_EQ(r.periodic + r.rest + r.undecided, 200);
  // The same detector does fire where the orbit is stable: the check above can fail.
  const ClosedResult steep = run_closed(elastic_closed(60.0, 1.0), {200, ReleaseDist::Line, 0, false}, {});
  EXPECT_GT(steep.periodic, 150);
}

TEST(Closed, ResultsDoNotDependOnTheThreadCount) {
  const Params p = elastic_closed(55.0, 0.1);
  const ClosedResult a = run_closed(p, {64, ReleaseDist::Line, 1, false}, {});
  const ClosedResult b = run_closed(p, {64, ReleaseDist::Line, 3, false}, {});
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    EXPECT_EQ(a.samples[i].state, b.samples[i].state);
    EXPECT_EQ(a.samples[i].x_last, b.samples[i].x_last);
    EXPECT_EQ(a.samples[i].collisions, b.samples[i].collisions);
  }
}

}  // namespace
}  // namespace funnel
