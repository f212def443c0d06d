// Self-retracing orbits of the elastic frictionless particle (retrace.hpp) against closed forms and the engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "funnel/geometry.hpp"
#include "funnel/retrace.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

Params closed_funnel(double theta) {
  Params p = retrace::frictionless(default_params());
  p.theta = theta;
  p.gap = 0.0;
  return p;
}

retrace::Options with_rest_turns() {
  retrace::Options o;
  o.rest_turns = true;
  return o;
}

const retrace::Orbit* find_sequence(const std::vector<retrace::Orbit>& orbits, const std::string& sequence,
                                    retrace::Turn turn = retrace::Turn::Wall) {
  for (const auto& o : orbits) {
    if (o.sequence == sequence && o.turn == turn) return &o;
  }
  return nullptr;
}

// Fall from rest onto the left wall at height y1, bounce to v = V (sin 2θ, cos 2θ), hit the right wall
// perpendicularly after t = V c with c = 4cos²θ - 1 (needs θ < 60°): y1/y0 = c(4 - c)/(2 + c(4 - c)),
// V = sqrt(2(y0 - y1)), period 2V(1 + c).
TEST(Retrace, SimplestOrbitLRMatchesItsClosedForm) {
  for (const double theta : {45.5, 48.0, 52.0, 57.0}) {
    const Params p = closed_funnel(theta);
    const auto orbits = retrace::find_orbits(p);
    const retrace::Orbit* lr = find_sequence(orbits, "LR");
    ASSERT_NE(lr, nullptr) << theta;
    const double th = theta * std::numbers::pi / 180.0;
    const double c = 4.0 * std::cos(th) * std::cos(th) - 1.0;
    const double ratio = c * (4.0 - c) / (2.0 + c * (4.0 - c));
    const double y0 = make_geometry(p).y_release;
    const double v = std::sqrt(2.0 * y0 * (1.0 - ratio));
    EXPECT_TRUE(near(lr->release, -ratio, 1e-14)) << theta;
    EXPECT_TRUE(near(lr->period, 2.0 * v * (1.0 + c), 1e-13)) << theta;
    EXPECT_EQ(lr->collisions_per_period, 3);
  }
  // Beyond 60° the bounce off the left wall goes up too steeply to meet the right wall head-on.
  EXPECT_EQ(find_sequence(retrace::find_orbits(closed_funnel(62.0)), "LR"), nullptr);
}

TEST(Retrace, EngineStartedOnAnOrbitReturnsToRestAtTheReleaseAfterOnePeriod) {
  int checked = 0;
  for (const double theta : {48.0, 61.0, 68.0, 72.3}) {
    const Params p = closed_funnel(theta);
    for (const auto& o : retrace::find_orbits(p, with_rest_turns())) {
      const retrace::ReturnCheck r = retrace::check_return(p, o);
      EXPECT_FALSE(r.left) << o.sequence;
      EXPECT_EQ(r.collisions, o.collisions_per_period) << o.sequence;
      EXPECT_LE(r.position_error, 1e-12) << theta << " " << o.sequence << " " << retrace::to_string(o.turn);
      EXPECT_LE(r.speed, 1e-12) << theta << " " << o.sequence << " " << retrace::to_string(o.turn);
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(Retrace, RestTurnRisesExactlyToTheReleaseHeight) {
  const Params p = closed_funnel(61.0);
  const double y0 = make_geometry(p).y_release;
  int rest = 0;
  for (const auto& o : retrace::find_orbits(p, with_rest_turns())) {
    if (o.turn != retrace::Turn::Rest) continue;
    const auto c = retrace::period_collisions(p, o);
    const Event& turn = c[static_cast<std::size_t>(o.bounces - 1)];
    EXPECT_LE(std::fabs(turn.velocity_after.x), 1e-14);
    EXPECT_TRUE(near(turn.position.y + 0.5 * turn.velocity_after.y * turn.velocity_after.y, y0, 1e-14));
    // The orbit comes back through the same collision point, once down and once up again.
    EXPECT_EQ(c[static_cast<std::size_t>(o.bounces)].wall, turn.wall);
    EXPECT_TRUE(near(c[static_cast<std::size_t>(o.bounces)].position.x, turn.position.x, 1e-13));
    ++rest;
  }
  EXPECT_GE(rest, 2);  // LRLR and its mirror at least
}

TEST(Retrace, EachCollisionMapIsAreaPreservingInBirkhoffCoordinates) {
  for (const double theta : {40.0, 55.0, 68.0}) {
    const Params p = closed_funnel(theta);
    for (const auto& o : retrace::find_orbits(p, with_rest_turns())) {
      const auto c = retrace::period_collisions(p, o);
      for (std::size_t i = 0; i + 1 < c.size(); ++i) {
        EXPECT_TRUE(near(retrace::collision_map_jacobian(p, c[i], c[i + 1]).determinant(), 1.0, 1e-11));
      }
      const Eigen::Matrix2d m = retrace::monodromy(p, o);
      EXPECT_TRUE(near(m.determinant(), 1.0, 1e-12 * m.squaredNorm() + 1e-12));
    }
  }
}

TEST(Retrace, MonodromyMatchesFiniteDifferencesOfTheEngine) {
  for (const double theta : {47.0, 60.0, 70.0}) {
    const Params p = closed_funnel(theta);
    for (const auto& o : retrace::find_orbits(p, with_rest_turns())) {
      const Eigen::Matrix2d exact = retrace::monodromy(p, o);
      const Eigen::Matrix2d fd = retrace::monodromy_fd(p, o);
      EXPECT_LE((exact - fd).norm(), 1e-6 * exact.norm()) << theta << " " << o.sequence;
    }
  }
}

// The monodromy of the flow over one period in (x, y, u, v) has the eigenvalues 1, 1 (along the flow
// and across the energy surface) and those of the reduced map: its trace is 2 + trace of the reduced one.
TEST(Retrace, FlowMonodromyTraceIsTwoPlusTheReducedTrace) {
  for (const double theta : {50.0, 61.0, 68.0}) {
    const Params p = closed_funnel(theta);
    const Geometry g = make_geometry(p);
    for (const auto& o : retrace::find_orbits(p)) {
      if (o.release > 0.0) continue;
      Params run = p;
      run.t_max = o.period;
      const Vec2 r0 = release_point(g, o.release);
      auto flow = [&](const Eigen::Vector4d& x) {
        State s;
        s.r = {x(0), x(1)};
        s.v = {x(2), x(3)};
        const State end = simulate(run, g, s).final_state;
        return Eigen::Vector4d(end.r.x, end.r.y, end.v.x, end.v.y);
      };
      const Eigen::Vector4d x0(r0.x, r0.y, 0.0, 0.0);
      const double h = 1e-7;
      double trace = 0.0;
      for (int j = 0; j < 4; ++j) {
        Eigen::Vector4d d = Eigen::Vector4d::Zero();
        d(j) = h;
        trace += (flow(x0 + d)(j) - flow(x0 - d)(j)) / (2.0 * h);
      }
      EXPECT_TRUE(near(trace, 2.0 + o.trace, 1e-5, 1e-6)) << theta << " " << o.sequence;
    }
  }
}

TEST(Retrace, MirrorReleaseIsTheMirrorOrbit) {
  const auto orbits = retrace::find_orbits(closed_funnel(60.0), with_rest_turns());
  for (const auto& o : orbits) {
    std::string mirrored = o.sequence;
    for (char& c : mirrored) c = c == 'L' ? 'R' : 'L';
    const auto twin = std::find_if(orbits.begin(), orbits.end(), [&](const retrace::Orbit& x) {
      return x.release == -o.release && x.sequence == mirrored && x.turn == o.turn;
    });
    ASSERT_NE(twin, orbits.end()) << o.sequence;
    EXPECT_EQ(twin->period, o.period);
    EXPECT_EQ(twin->trace, o.trace);
    EXPECT_EQ(o.sequence[0], o.release < 0.0 ? 'L' : 'R');  // released above the left wall: falls on it
  }
}

TEST(Retrace, RepetitionsOfAShorterOrbitAreNotListed) {
  // The LR orbit at 48° hits the right wall head-on again at its 5th collision (LR, back L, L, R).
  const auto orbits = retrace::find_orbits(closed_funnel(48.0));
  ASSERT_NE(find_sequence(orbits, "LR"), nullptr);
  EXPECT_EQ(find_sequence(orbits, "LRLLR"), nullptr);
  for (const auto& o : orbits) EXPECT_EQ(o.collisions_per_period, 2 * o.bounces - 1);
}

// Below 45° the wedge billiard is hyperbolic (Wojtkowski): no periodic orbit can be elliptic.
TEST(Retrace, NoOrbitIsStableBelow45Degrees) {
  int count = 0;
  for (const double theta : {30.0, 36.0, 41.0, 44.5}) {
    for (const auto& o : retrace::find_orbits(closed_funnel(theta), with_rest_turns())) {
      EXPECT_FALSE(o.stable) << theta << " " << o.sequence << " trace " << o.trace;
      EXPECT_GT(std::fabs(o.trace), 2.0);
      ++count;
    }
  }
  EXPECT_GT(count, 20);
}

TEST(Retrace, FinerReleaseGridFindsNoMoreOrbits) {
  retrace::Options coarse = with_rest_turns(), fine = with_rest_turns();
  coarse.scan_points = 300;
  fine.scan_points = 6000;
  for (const double theta : {46.0, 63.0, 77.0}) {
    const auto a = retrace::find_orbits(closed_funnel(theta), coarse);
    const auto b = retrace::find_orbits(closed_funnel(theta), fine);
    ASSERT_EQ(a.size(), b.size()) << theta;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].sequence, b[i].sequence);
      EXPECT_TRUE(near(a[i].release, b[i].release, 1e-13, 1e-15));
    }
  }
}

TEST(Retrace, ScanIsBitIdenticalForAnyThreadCount) {
  retrace::Options one = with_rest_turns(), two = with_rest_turns();
  one.threads = 1;
  two.threads = 2;
  one.scan_points = two.scan_points = 300;
  const std::vector<double> thetas{46.0, 52.5, 61.0, 68.0, 75.0};
  const auto a = retrace::scan(closed_funnel(60.0), thetas, one);
  const auto b = retrace::scan(closed_funnel(60.0), thetas, two);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].theta, b[i].theta);
    EXPECT_EQ(a[i].release, b[i].release);
    EXPECT_EQ(a[i].period, b[i].period);
    EXPECT_EQ(a[i].trace, b[i].trace);
  }
}

// The flow in the wedge is scale invariant: an orbit that stays above the faces' lower ends exists in
// the open funnel at the same x0/L, with its period scaled by sqrt(y0 ratio); the others do not.
TEST(Retrace, OpenFunnelKeepsTheOrbitsThatStayAboveTheFaceEnds) {
  Params open = closed_funnel(48.0);
  open.gap = 0.04;
  const Geometry go = make_geometry(open), gc = make_geometry(closed_funnel(48.0));
  const double scale = go.y_release / gc.y_release;
  int kept = 0, dropped = 0;
  for (const auto& o : retrace::find_orbits(closed_funnel(48.0), with_rest_turns())) {
    const auto t = retrace::transfer(o, open, with_rest_turns());
    if (o.min_height * scale > go.y_face_end) {
      ASSERT_TRUE(t.has_value()) << o.sequence;
      EXPECT_TRUE(near(t->release, o.release, 1e-13));
      EXPECT_TRUE(near(t->period, o.period * std::sqrt(scale), 1e-12));
      EXPECT_TRUE(near(t->trace, o.trace, 1e-8, 1e-9));
      const retrace::ReturnCheck r = retrace::check_return(open, *t);
      EXPECT_FALSE(r.left);
      EXPECT_LE(r.position_error, 1e-12);
      ++kept;
    } else {
      EXPECT_FALSE(t.has_value()) << o.sequence;
      ++dropped;
    }
  }
  EXPECT_GT(kept, 4);
  EXPECT_GT(dropped, 0);
}

TEST(Retrace, WindowsAreMaximalRunsOfGridAngles) {
  auto orbit = [](double theta, const char* seq, bool stable) {
    retrace::Orbit o;
    o.theta = theta;
    o.sequence = seq;
    o.bounces = static_cast<int>(std::string(seq).size());
    o.stable = stable;
    return o;
  };
  const std::vector<double> thetas{50, 51, 52, 53, 54};
  // The mirror sequence RL is the same family as LR.
  const std::vector<retrace::Orbit> orbits{orbit(50, "LR", false), orbit(51, "RL", true), orbit(52, "LR", true),
                                           orbit(54, "LR", true), orbit(52, "LRL", false)};
  const auto w = retrace::windows(orbits, thetas);
  ASSERT_EQ(w.size(), 5u);
  EXPECT_EQ(w[0].sequence, "LR");
  EXPECT_FALSE(w[0].stable);
  EXPECT_EQ(w[0].theta_from, 50);
  EXPECT_EQ(w[0].theta_to, 52);
  EXPECT_EQ(w[0].points, 3);
  EXPECT_EQ(w[1].theta_from, 54);
  EXPECT_TRUE(w[2].stable);
  EXPECT_EQ(w[2].theta_from, 51);
  EXPECT_EQ(w[2].theta_to, 52);
  EXPECT_TRUE(w[3].stable);
  EXPECT_EQ(w[3].theta_from, 54);
  EXPECT_EQ(w[4].sequence, "LRL");
}

TEST(Retrace, SignOfATurnAngleIsTheSignOfItsAtan2) {
  // The scan compares turn angles by sign without atan2 where it can: the same answer everywhere,
  // signed zeros, angles that underflow, infinities and NaN included.
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> values{0.0, -0.0, 1.0, -1.0, 0x1p-1074, -0x1p-1074, 0x1p-1022, -0x1p-1022, 1e-300, -1e-300,
                             1e300, -1e300, 0x1p-900, -0x1p-900, inf, -inf, nan, 0.3, -2.5};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-1100.0, 1100.0);
  for (int i = 0; i < 2000; ++i) values.push_back(std::ldexp(u(rng), static_cast<int>(e(rng))));
  int checked = 0;
  for (const double y : values) {
    for (const double x : values) {
      ASSERT_EQ(retrace::detail::atan2_negative(y, x), std::atan2(y, x) < 0.0) << y << " " << x;
      ++checked;
    }
  }
  EXPECT_GT(checked, 4000000);
}

}  // namespace
}  // namespace funnel
