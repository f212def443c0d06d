// 3D ensembles: the 2D cone statistics for releases at rest, determinism, seeded releases.
#include "funnel/ensemble3d.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "funnel/random.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

void expect_same(const Summary& a, const Summary& b) {
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.std, b.std);
  EXPECT_EQ(a.min, b.min);
  EXPECT_EQ(a.max, b.max);
}

TEST(Ensemble3d, ReleasesAtRestGiveTheTwoDimensionalConeStatisticsBitForBit) {
  // A ball released at rest stays in its meridian plane: the 3D disk ensemble is the 2D one.
  for (const double theta : {30.0, 46.0, 60.0}) {
    Params p = default_params();
    p.theta = theta;
    EnsembleOptions o2;
    o2.samples = 200;
    o2.dist = ReleaseDist::Disk;
    o2.threads = 2;
    Ensemble3Options o3;
    o3.samples = 200;
    o3.threads = 2;
    const EnsembleResult a = run_ensemble(p, o2);
    const Ensemble3Result b = run_ensemble_3d(p, o3);
    expect_same(b[Observable::Duration], a[Observable::Duration]);
    expect_same(b[Observable::Impulse], a[Observable::Impulse]);
    expect_same(b[Observable::NormalImpulse], a[Observable::NormalImpulse]);
    expect_same(b[Observable::EnergyLoss], a[Observable::EnergyLoss]);
    expect_same(b[Observable::Collisions], a[Observable::Collisions]);
    expect_same(b[Observable::EdgeCollisions], a[Observable::EdgeCollisions]);
    expect_same(b[Observable::ContactTime], a[Observable::ContactTime]);
    EXPECT_EQ(b.exited, a.exited);
    EXPECT_EQ(b.trapped, a.trapped);
    EXPECT_EQ(b.total_collisions, a.total_collisions);
    EXPECT_EQ(b[Observable::Orbits].max, 0.0);
    EXPECT_EQ(b.ode_steps, 0);  // every contact in closed form
  }
}

TEST(Ensemble3d, LineReleasesGiveTheTwoDimensionalFunnelStatistics) {
  Params p = default_params();
  p.theta = 50.0;
  EnsembleOptions o2;
  o2.samples = 101;
  Ensemble3Options o3;
  o3.samples = 101;
  o3.dist = ReleaseDist::Line;
  const EnsembleResult a = run_ensemble(p, o2);
  const Ensemble3Result b = run_ensemble_3d(p, o3);
  // The 2D engine simulates half the line and counts each mirror twice: the sums are the same up
  // to their order.
  EXPECT_TRUE(near(b[Observable::Duration].mean, a[Observable::Duration].mean, 1e-12));
  EXPECT_TRUE(near(b[Observable::Impulse].mean, a[Observable::Impulse].mean, 1e-12));
  EXPECT_TRUE(near(b[Observable::EnergyLoss].mean, a[Observable::EnergyLoss].mean, 1e-12));
  EXPECT_EQ(b.total_collisions, a.total_collisions);
}

TEST(Ensemble3d, ResultsAreBitIdenticalForAnyThreadCount) {
  Params p = default_params();
  p.theta = 60.0;
  p.t_max = 2000.0;
  Ensemble3Options o;
  o.samples = 48;
  o.velocity_sd = 0.05;
  o.seed = 17;
  o.threads = 1;
  const Ensemble3Result a = run_ensemble_3d(p, o);
  o.threads = 2;
  const Ensemble3Result b = run_ensemble_3d(p, o);
  expect_same(a[Observable::Duration], b[Observable::Duration]);
  expect_same(a[Observable::Impulse], b[Observable::Impulse]);
  expect_same(a[Observable::EnergyLoss], b[Observable::EnergyLoss]);
  expect_same(a[Observable::Orbits], b[Observable::Orbits]);
  EXPECT_EQ(a.trapped, b.trapped);
  EXPECT_EQ(a.ode_steps, b.ode_steps);
  EXPECT_GT(a.ode_steps, 0);  // integrated contacts are part of it
}

TEST(Ensemble3d, RunsEndedByTheCollisionCapAreCountedAmongTheTrapped) {
  Params p = default_params();
  p.theta = 60.0;
  p.max_collisions = 40;
  Ensemble3Options o;
  o.samples = 48;
  o.velocity_sd = 0.05;
  o.seed = 17;
  o.threads = 2;
  o.keep_samples = true;
  const Ensemble3Result r = run_ensemble_3d(p, o);
  std::int64_t capped = 0;
  for (const Sample3& s : r.per_sample) {
    if (!s.trajectory.capped) continue;
    ++capped;
    EXPECT_EQ(s.trajectory.status, Status::Trapped);
    EXPECT_EQ(s.trajectory.collisions, 40);
  }
  EXPECT_EQ(r.capped, capped);
  EXPECT_GT(capped, 24);
  EXPECT_LE(r.capped, r.trapped);
  p.max_collisions = default_params().max_collisions;
  EXPECT_EQ(run_ensemble_3d(p, o).capped, 0);
}

TEST(Ensemble3d, OnePoolOverSeveralVelocitySpreadsGivesEachEnsembleBitForBit) {
  Params p = default_params();
  p.theta = 46.0;
  p.t_max = 300.0;
  Ensemble3Options o;
  o.samples = 32;
  o.seed = 3;
  o.threads = 2;
  const std::vector<double> sds{0.0, 0.03, 0.1};
  const std::vector<Ensemble3Result> pooled = run_sweep_3d({p, p, p}, sds, o);
  for (std::size_t i = 0; i < sds.size(); ++i) {
    o.velocity_sd = sds[i];
    const Ensemble3Result alone = run_ensemble_3d(p, o);
    expect_same(pooled[i][Observable::Duration], alone[Observable::Duration]);
    expect_same(pooled[i][Observable::Orbits], alone[Observable::Orbits]);
    EXPECT_EQ(pooled[i].total_collisions, alone.total_collisions);
  }
  EXPECT_NE(pooled[0][Observable::Duration].mean, pooled[2][Observable::Duration].mean);
}

TEST(Ensemble3d, ReleaseVelocitiesAreSeededNormalDraws) {
  Params p = default_params();
  p.release_u = 0.01;
  const Cone c = make_cone(p);
  Ensemble3Options o;
  o.samples = 4000;
  o.velocity_sd = 0.03;
  o.seed = 99;
  p.release_w = -0.02;
  double su = 0.0, sw = 0.0, su2 = 0.0, sw2 = 0.0;
  for (std::int64_t k = 0; k < o.samples; ++k) {
    const State3 s = ensemble_release_3d(p, c, o, k);
    const auto index = static_cast<std::uint64_t>(k);
    EXPECT_EQ(s.v.x, 0.01 + 0.03 * standard_normal(99, release_velocity_u_stream, index));
    EXPECT_EQ(s.v.z, -0.02 + 0.03 * standard_normal(99, release_velocity_w_stream, index));
    EXPECT_EQ(s.v.y, 0.0);
    EXPECT_EQ(s.r.z, 0.0);
    su += s.v.x - 0.01;
    sw += s.v.z + 0.02;
    su2 += (s.v.x - 0.01) * (s.v.x - 0.01);
    sw2 += (s.v.z + 0.02) * (s.v.z + 0.02);
  }
  const double n = static_cast<double>(o.samples), var = 0.03 * 0.03;
  EXPECT_NEAR(su / n, 0.0, 5.0 * 0.03 / std::sqrt(n));
  EXPECT_NEAR(sw / n, 0.0, 5.0 * 0.03 / std::sqrt(n));
  EXPECT_NEAR(su2 / n, var, 5.0 * var * std::sqrt(2.0 / n));
  EXPECT_NEAR(sw2 / n, var, 5.0 * var * std::sqrt(2.0 / n));
  Ensemble3Options other = o;
  other.seed = 100;
  EXPECT_NE(ensemble_release_3d(p, c, other, 5).v.x, ensemble_release_3d(p, c, o, 5).v.x);
}

TEST(Ensemble3d, KeptSamplesAgreeWithTheStatistics) {
  Params p = default_params();
  p.theta = 45.0;
  p.t_max = 1000.0;
  Ensemble3Options o;
  o.samples = 40;
  o.velocity_sd = 0.03;
  o.keep_samples = true;
  const Ensemble3Result r = run_ensemble_3d(p, o);
  ASSERT_EQ(r.per_sample.size(), 40u);
  double sum = 0.0, sum_exited = 0.0;
  std::int64_t exited = 0;
  for (const Sample3& s : r.per_sample) {
    sum += s.trajectory.duration;
    if (s.trajectory.status == Status::Exited) {
      sum_exited += value(s.trajectory, Observable::ExitSpeed);
      ++exited;
    }
  }
  EXPECT_TRUE(near(r[Observable::Duration].mean, sum / 40.0, 1e-12));
  EXPECT_EQ(r.exited, exited);
  ASSERT_GT(exited, 0);
  EXPECT_TRUE(near(r[Observable::ExitSpeed].mean, sum_exited / static_cast<double>(exited), 1e-12));
}

}  // namespace
}  // namespace funnel
