// Ensembles: release distributions, statistics, determinism and the paper's headline result.
#include "funnel/ensemble.hpp"
#include "funnel/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_identical(const Summary& a, const Summary& b) {
  EXPECT_TRUE(same_bits(a.mean, b.mean));
  EXPECT_TRUE(same_bits(a.std, b.std));
  EXPECT_TRUE(same_bits(a.min, b.min));
  EXPECT_TRUE(same_bits(a.max, b.max));
}

TEST(Ensemble, ReleasePositionsFollowModelSection8) {
  EXPECT_DOUBLE_EQ(release_fraction(ReleaseDist::Line, 0, 4), -0.75);
  EXPECT_DOUBLE_EQ(release_fraction(ReleaseDist::Line, 3, 4), 0.75);
  EXPECT_DOUBLE_EQ(release_fraction(ReleaseDist::Disk, 0, 2), 0.5);
  EXPECT_DOUBLE_EQ(release_fraction(ReleaseDist::Disk, 1, 2), std::sqrt(0.75));
  // The line distribution is symmetric about the axis.
  for (int k = 0; k < 10; ++k) {
    EXPECT_EQ(release_fraction(ReleaseDist::Line, k, 10), -release_fraction(ReleaseDist::Line, 9 - k, 10));
  }
}

TEST(Stats, WelfordMergeMatchesTwoPassStatistics) {
  Accumulator a, b, all;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < 1000; ++i) {
    const double x = std::sin(i * 0.37) * 10 + i * 0.01;
    (i < 377 ? a : b).add(x);
    all.add(x);
    sum += x;
  }
  const double mean = sum / 1000;
  for (int i = 0; i < 1000; ++i) {
    const double x = std::sin(i * 0.37) * 10 + i * 0.01;
    sum2 += (x - mean) * (x - mean);
  }
  a.merge(b);
  const Summary s = summarize(a);
  EXPECT_TRUE(near(s.mean, mean, 1e-13));
  EXPECT_TRUE(near(s.std, std::sqrt(sum2 / 999), 1e-12));
  EXPECT_TRUE(near(s.sem, s.std / std::sqrt(1000.0), 1e-15));
  EXPECT_EQ(s.min, summarize(all).min);
  EXPECT_EQ(s.max, summarize(all).max);
}

TEST(Ensemble, ResultsAreBitIdenticalForOneAndManyThreads) {
  Params p = default_params();
  p.theta = 47.0;
  EnsembleOptions one{1000, ReleaseDist::Line, 1, false};
  EnsembleOptions many = one;
  many.threads = 4;
  const EnsembleResult a = run_ensemble(p, one);
  const EnsembleResult b = run_ensemble(p, many);
  expect_identical(a.duration, b.duration);
  expect_identical(a.impulse, b.impulse);
  expect_identical(a.normal_impulse, b.normal_impulse);
  expect_identical(a.energy_loss, b.energy_loss);
  expect_identical(a.collisions, b.collisions);
  EXPECT_EQ(a.total_collisions, b.total_collisions);
  EXPECT_EQ(a.exited, b.exited);
}

TEST(Ensemble, SweepEqualsIndependentEnsembles) {
  Params p = default_params();
  std::vector<Params> points;
  for (const double theta : {35.0, 55.0}) {
    p.theta = theta;
    points.push_back(p);
  }
  const EnsembleOptions opt{300, ReleaseDist::Disk, 2, false};
  const auto sweep = run_sweep(points, opt);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const EnsembleResult single = run_ensemble(points[i], opt);
    expect_identical(sweep[i].duration, single.duration);
    expect_identical(sweep[i].energy_loss, single.energy_loss);
  }
}

TEST(Ensemble, MirrorHalvingGivesExactlyTheDirectSimulationOfEverySample) {
  // Line ensembles simulate x0 <= 0 only; every sample must still equal its direct simulation
  // bit for bit, which holds because the engine is exactly mirror symmetric.
  for (const double theta : {25.0, 46.0, 70.0}) {
    for (const std::int64_t n : {199, 200}) {
      Params p = default_params();
      p.theta = theta;
      p.beta0 = 0.31;
      const Geometry g = make_geometry(p);
      const EnsembleOptions opt{n, ReleaseDist::Line, 2, true};
      const EnsembleResult r = run_ensemble(p, opt);
      ASSERT_EQ(r.per_sample.size(), static_cast<std::size_t>(n));
      double sum = 0.0;
      for (std::int64_t k = 0; k < n; ++k) {
        const double f = release_fraction(ReleaseDist::Line, k, n);
        const Trajectory direct = simulate_release(p, g, f);
        const Sample& s = r.per_sample[static_cast<std::size_t>(k)];
        EXPECT_EQ(s.fraction, f);
        EXPECT_TRUE(same_bits(s.trajectory.duration, direct.duration)) << theta << " " << k;
        EXPECT_TRUE(same_bits(s.trajectory.impulse, direct.impulse)) << theta << " " << k;
        EXPECT_TRUE(same_bits(s.trajectory.energy_loss, direct.energy_loss)) << theta << " " << k;
        EXPECT_EQ(s.trajectory.collisions, direct.collisions);
        EXPECT_TRUE(same_bits(s.trajectory.final_state.r.x, direct.final_state.r.x));
        sum += direct.duration;
      }
      EXPECT_TRUE(near(sum / static_cast<double>(n), r.duration.mean, 1e-13));
      EXPECT_EQ(r.exited + r.rest + r.trapped, n);
    }
  }
}

TEST(Ensemble, SteeperThan45DegreesHoldsTheParticleMoreThanTwiceAsLong) {
  // The paper's headline (Fig. 3a, mu = 1): e = 0.99, beta0 = 0, N = 4000.
  Params p = default_params();
  const EnsembleOptions opt{4000, ReleaseDist::Line, 0, false};
  p.theta = 44.0;
  const EnsembleResult below = run_ensemble(p, opt);
  p.theta = 46.0;
  const EnsembleResult above = run_ensemble(p, opt);
  EXPECT_EQ(below.exited, 4000);
  EXPECT_EQ(above.exited, 4000);
  EXPECT_GT(above.duration.mean, 2.0 * below.duration.mean);
  // The impulse and the energy loss are anomalous in the same direction (Figs. 4, 5).
  EXPECT_GT(above.impulse.mean, 2.0 * below.impulse.mean);
  EXPECT_GT(above.energy_loss.mean, below.energy_loss.mean);
}

}  // namespace
}  // namespace funnel
