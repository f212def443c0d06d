// Ensembles: release distributions, statistics, determinism and the paper's headline result.
#include "funnel/ensemble.hpp"
#include "funnel/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "funnel/observables.hpp"
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
  for (const ObservableInfo& o : observables()) expect_identical(a[o.id], b[o.id]);
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
    for (const ObservableInfo& o : observables()) expect_identical(sweep[i][o.id], single[o.id]);
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
        // Every observable, the exit state's odd ones (x, u, angle, spin) included.
        for (const ObservableInfo& o : observables()) {
          const double a = value(s.trajectory, o.id), b = value(direct, o.id);
          EXPECT_TRUE(same_bits(a, b) || (std::isnan(a) && std::isnan(b))) << o.name << " " << theta << " " << k << " " << a << " " << b;
        }
        sum += direct.duration;
      }
      EXPECT_TRUE(near(sum / static_cast<double>(n), r[Observable::Duration].mean, 1e-13));
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
  EXPECT_GT(above[Observable::Duration].mean, 2.0 * below[Observable::Duration].mean);
  // The impulse and the energy loss are anomalous in the same direction (Figs. 4, 5).
  EXPECT_GT(above[Observable::Impulse].mean, 2.0 * below[Observable::Impulse].mean);
  EXPECT_GT(above[Observable::EnergyLoss].mean, below[Observable::EnergyLoss].mean);
}

TEST(Ensemble, RandomReleasesAreKeyedBySeedAndSampleAndIndependentOfThreads) {
  Params p = default_params();
  p.theta = 52.0;
  for (const ReleaseDist dist : {ReleaseDist::Uniform, ReleaseDist::Gaussian}) {
    EnsembleOptions one{600, dist, 1, true};
    one.seed = 1234;
    one.release_mean = 0.3;
    one.release_sd = 0.2;
    one.velocity_sd = 0.05;
    EnsembleOptions two = one;
    two.threads = 3;
    const EnsembleResult a = run_ensemble(p, one), b = run_ensemble(p, two);
    for (const ObservableInfo& o : observables()) expect_identical(a[o.id], b[o.id]);
    // No mirror halving for random releases: every sample is simulated.
    EXPECT_EQ(a.simulated_collisions, a.total_collisions);
    const Geometry g = make_geometry(p);
    double sum = 0.0;
    for (std::int64_t k = 0; k < one.samples; ++k) {
      const Sample& s = a.per_sample[static_cast<std::size_t>(k)];
      const State direct = sample_release(p, g, one, k);
      EXPECT_EQ(s.release.r.x, direct.r.x);
      EXPECT_EQ(s.release.v.y, direct.v.y);
      EXPECT_TRUE(s.fraction > -1.0 && s.fraction < 1.0);
      sum += s.fraction;
    }
    // Another seed gives other samples.
    EnsembleOptions other = one;
    other.seed = 99;
    EXPECT_NE(sample_release(p, g, other, 7).r.x, sample_release(p, g, one, 7).r.x);
    // The mean position: 0 for uniform; near the mean 0.3 for the (slightly truncated) gaussian.
    const double mean = sum / static_cast<double>(one.samples);
    EXPECT_NEAR(mean, dist == ReleaseDist::Uniform ? 0.0 : 0.3, dist == ReleaseDist::Uniform ? 0.1 : 0.04);
  }
}

TEST(Ensemble, RandomVelocitiesHaveTheRequestedSpread) {
  Params p = default_params();
  const Geometry g = make_geometry(p);
  EnsembleOptions o{20000, ReleaseDist::Line, 1, false};
  o.velocity_sd = 0.3;
  Accumulator u, v;
  for (std::int64_t k = 0; k < o.samples; ++k) {
    const State s = sample_release(p, g, o, k);
    u.add(s.v.x);
    v.add(s.v.y);
  }
  // 20000 normal deviates: the sample mean is within 4 sigma/sqrt(N), the sd within 3%.
  EXPECT_NEAR(summarize(u).mean, 0.0, 4 * 0.3 / std::sqrt(20000.0));
  EXPECT_NEAR(summarize(v).mean, 0.0, 4 * 0.3 / std::sqrt(20000.0));
  EXPECT_NEAR(summarize(u).std, 0.3, 0.01);
  EXPECT_NEAR(summarize(v).std, 0.3, 0.01);
}

TEST(Ensemble, MirrorHalvingOnlyForSymmetricReleases) {
  Params p = default_params();
  EnsembleOptions o{400, ReleaseDist::Line, 0, false};
  EXPECT_TRUE(mirror_symmetric(p, o));
  const EnsembleResult sym = run_ensemble(p, o);
  EXPECT_LT(sym.simulated_collisions, sym.total_collisions);
  p.release_v = -0.2;  // a vertical throw keeps the symmetry
  EXPECT_TRUE(mirror_symmetric(p, o));
  p.release_u = 0.1;
  EXPECT_FALSE(mirror_symmetric(p, o));
  const EnsembleResult asym = run_ensemble(p, o);
  EXPECT_EQ(asym.simulated_collisions, asym.total_collisions);
  p.release_u = 0.0;
  p.release_spin = 1.0;
  EXPECT_FALSE(mirror_symmetric(p, o));
  p.release_spin = 0.0;
  o.velocity_sd = 0.01;
  EXPECT_FALSE(mirror_symmetric(p, o));
  o.velocity_sd = 0.0;
  o.dist = ReleaseDist::Disk;
  EXPECT_FALSE(mirror_symmetric(p, o));
}

TEST(Ensemble, ExitStatisticsAreOverTheExitedSamplesOnly) {
  // A short time cap traps part of the ensemble: the exit speed's statistics come from the
  // exited samples, whose exit speeds each satisfy the energy balance.
  Params p = default_params();
  p.theta = 60.0;
  p.t_max = 20.0;
  const EnsembleOptions o{400, ReleaseDist::Line, 0, true};
  const EnsembleResult r = run_ensemble(p, o);
  ASSERT_GT(r.trapped, 0);
  ASSERT_GT(r.exited, 0);
  Accumulator speed;
  for (const Sample& s : r.per_sample) {
    if (s.trajectory.status == Status::Exited) {
      speed.add(value(s.trajectory, Observable::ExitSpeed));
    } else {
      EXPECT_TRUE(std::isnan(value(s.trajectory, Observable::ExitSpeed)));
    }
  }
  EXPECT_EQ(speed.n, r.exited);
  EXPECT_TRUE(near(summarize(speed).mean, r[Observable::ExitSpeed].mean, 1e-12));
  EXPECT_EQ(summarize(speed).max, r[Observable::ExitSpeed].max);
}

TEST(Ensemble, OptionsAreValidatedWithTheirNameValueAndRange) {
  EnsembleOptions o;
  EXPECT_FALSE(validate(o).has_value());
  auto bad = [](auto change, const char* name) {
    EnsembleOptions x;
    change(x);
    const auto err = validate(x);
    ASSERT_TRUE(err.has_value()) << name;
    EXPECT_EQ(err->name, name);
    EXPECT_NE(err->message().find("valid range"), std::string::npos);
  };
  bad([](EnsembleOptions& x) { x.samples = 0; }, "samples");
  bad([](EnsembleOptions& x) { x.threads = -1; }, "threads");
  bad([](EnsembleOptions& x) { x.release_mean = 1.0; }, "release");
  bad([](EnsembleOptions& x) { x.release_sd = 0.0; }, "release-sd");
  bad([](EnsembleOptions& x) { x.release_sd = std::nan(""); }, "release-sd");
  bad([](EnsembleOptions& x) { x.velocity_sd = -1e-9; }, "velocity-sd");
  bad([](EnsembleOptions& x) { x.wear_bins = -1; }, "wear-bins");
}

}  // namespace
}  // namespace funnel
