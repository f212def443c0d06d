// Ensembles: release distributions, statistics, determinism and the paper's headline result.
#include "funnel/ensemble.hpp"
#include "funnel/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "funnel/funnel.hpp"
#include "funnel/observables.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;
using test::same_bits;

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

TEST(Stats, OneSampleHasAMeanButNoSpread) {
  // The n - 1 of the standard deviation leaves nothing to estimate the spread from: undefined
  // (null in JSON, an empty CSV field), not 0, which read as an exact mean.
  Accumulator one;
  one.add(2.5);
  const Summary s = summarize(one);
  EXPECT_EQ(s.mean, 2.5);
  EXPECT_EQ(s.min, 2.5);
  EXPECT_EQ(s.max, 2.5);
  EXPECT_TRUE(std::isnan(s.std));
  EXPECT_TRUE(std::isnan(s.sem));
  Accumulator two = one;
  two.add(3.5);
  EXPECT_EQ(summarize(two).std, std::sqrt(0.5));
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

TEST(Ensemble, ASweepOverMuReusesTheTrajectoriesThatDidNotSlideBitForBit) {
  // run_sweep runs the points that differ only in mu as a chain, in ascending mu: at the next mu
  // only the releases whose trajectory slid run again (docs/model.md §4). Every point must be
  // exactly its ensemble alone, sample by sample, whatever the order of the points.
  std::vector<Params> points;
  Params p = default_params();
  for (const double theta : {20.0, 46.0, 60.0}) {
    for (const double beta0 : {0.0, 0.31}) {
      for (const double mu : {5.0, 0.2, 1.0, 0.0, 0.05, 1.0 + 1e-12}) {
        p.theta = theta;
        p.beta0 = beta0;
        p.mu = mu;
        points.push_back(p);
      }
    }
  }
  Params hopper = default_params();  // a wall profile with its own mu on the right: mirror symmetric at mu = 0.6 only
  ProfileSpec spec;
  spec.sides[0] = {{-1.0, 1.2}, {-0.1, 0.0}};
  spec.sides[1] = {{1.0, 1.2}, {0.1, 0.0}};
  spec.mu[1] = 0.6;
  hopper.profile = std::make_shared<const ProfileSpec>(spec);
  for (const double mu : {0.6, 0.3, 2.0}) {
    hopper.mu = mu;
    points.push_back(hopper);
  }
  for (const ReleaseDist dist : {ReleaseDist::Line, ReleaseDist::Gaussian}) {
    EnsembleOptions opt{301, dist, 2, true};
    const auto sweep = run_sweep(points, opt);
    std::int64_t chained = 0, alone = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const EnsembleResult single = run_ensemble(points[i], opt);
      for (const ObservableInfo& o : observables()) expect_identical(sweep[i][o.id], single[o.id]);
      EXPECT_EQ(sweep[i].exited, single.exited);
      EXPECT_EQ(sweep[i].rest, single.rest);
      EXPECT_EQ(sweep[i].trapped, single.trapped);
      EXPECT_EQ(sweep[i].total_collisions, single.total_collisions);
      EXPECT_LE(sweep[i].simulated_collisions, single.simulated_collisions);
      ASSERT_EQ(sweep[i].per_sample.size(), single.per_sample.size());
      for (std::size_t k = 0; k < single.per_sample.size(); ++k) {
        ASSERT_TRUE(test::same_trajectory(sweep[i].per_sample[k].trajectory, single.per_sample[k].trajectory))
            << "point " << i << " (theta " << points[i].theta << ", mu " << points[i].mu << "), sample " << k;
      }
      chained += sweep[i].simulated_collisions;
      alone += single.simulated_collisions;
    }
    // The reuse is real: at mu = 1 and above nearly every trajectory sticks.
    EXPECT_LT(static_cast<double>(chained), 0.8 * static_cast<double>(alone)) << chained << " vs " << alone;
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

TEST(Ensemble, RunsEndedByTheCollisionCapAreCountedAmongTheTrappedMirrorImagesIncluded) {
  // At 60 degrees a trajectory makes about 200 collisions: a cap of 40 ends most of them inside
  // the funnel, at the collision that reaches it, as trapped with their observables cut short.
  Params p = default_params();
  p.theta = 60.0;
  p.max_collisions = 40;
  const Geometry g = make_geometry(p);
  for (const std::int64_t n : {201, 200}) {  // mirror halving, with and without a middle sample
    const EnsembleResult r = run_ensemble(p, EnsembleOptions{n, ReleaseDist::Line, 2, true});
    std::int64_t capped = 0;
    for (std::int64_t k = 0; k < n; ++k) {
      const Trajectory& t = r.per_sample[static_cast<std::size_t>(k)].trajectory;
      const Trajectory direct = simulate_release(p, g, release_fraction(ReleaseDist::Line, k, n));
      EXPECT_EQ(t.capped, direct.capped) << k;
      if (!t.capped) continue;
      ++capped;
      EXPECT_EQ(t.status, Status::Trapped) << k;
      EXPECT_EQ(t.collisions, 40) << k;
      EXPECT_LT(t.duration, 60.0) << k;  // far short of t_max
    }
    EXPECT_EQ(r.capped, capped);
    EXPECT_GT(capped, n / 2);
    EXPECT_LE(r.capped, r.trapped);
    EXPECT_EQ(r.stalled, 0);
    // The same counts on one thread, and without the samples kept.
    const EnsembleResult one = run_ensemble(p, EnsembleOptions{n, ReleaseDist::Line, 1, false});
    EXPECT_EQ(one.capped, capped);
    EXPECT_EQ(one.trapped, r.trapped);
  }
  // Runs that end otherwise are not capped: exits under the default cap, and a closed funnel's
  // runs still bouncing at the time cap.
  Params free = default_params();
  free.theta = 60.0;
  const EnsembleResult exits = run_ensemble(free, EnsembleOptions{101, ReleaseDist::Line, 2, false});
  EXPECT_EQ(exits.exited, 101);
  EXPECT_EQ(exits.capped, 0);
  Params closed = free;
  closed.gap = 0.0;
  closed.t_max = 5.0;
  const EnsembleResult held = run_ensemble(closed, EnsembleOptions{101, ReleaseDist::Line, 2, false});
  EXPECT_GT(held.trapped, 0);
  EXPECT_EQ(held.capped, 0);
}

TEST(Ensemble, FrictionlessEnsemblesDoNotDependOnBeta0) {
  // `funnel paper` runs mu = 0 once for every beta0 (Figs. 3-5's three panels share that curve):
  // without friction beta0 must change no bit of any sample. Covered here: collapses (5 deg),
  // edge-heavy angles, a closed funnel, an asymmetric V with a spout, and a spinning release.
  struct Case {
    double theta, gap, theta_right, spout, spin;
  };
  const Case cases[] = {{5, 0.04, Params::unset, 0, 0},   {20, 0.04, Params::unset, 0, 0},
                        {44, 0.04, Params::unset, 0, 0},  {46, 0.04, Params::unset, 0, 0.7},
                        {60, 0.04, Params::unset, 0, 0},  {80, 0.04, Params::unset, 0, 0},
                        {50, 0.0, Params::unset, 0, 0},   {40, 0.04, 55, 0.2, -0.3}};
  for (const Case& c : cases) {
    Params p = default_params();
    p.theta = c.theta;
    p.gap = c.gap;
    p.theta_right = c.theta_right;
    p.spout_length = c.spout;
    p.release_spin = c.spin;
    p.mu = 0.0;
    p.t_max = 200.0;
    const EnsembleOptions opt{200, ReleaseDist::Line, 2, true};
    p.beta0 = 0.0;
    const EnsembleResult base = run_ensemble(p, opt);
    ASSERT_GT(base.total_collisions, 400) << c.theta;  // at least two collisions per sample
    for (const double beta0 : {-0.9, -0.31, 0.31, 1.0}) {
      p.beta0 = beta0;
      const EnsembleResult r = run_ensemble(p, opt);
      EXPECT_EQ(r.total_collisions, base.total_collisions) << c.theta << " " << beta0;
      for (std::size_t k = 0; k < r.per_sample.size(); ++k) {
        for (const ObservableInfo& o : observables()) {
          const double a = value(r.per_sample[k].trajectory, o.id), b = value(base.per_sample[k].trajectory, o.id);
          EXPECT_TRUE(same_bits(a, b) || (std::isnan(a) && std::isnan(b))) << o.name << " " << c.theta << " " << beta0 << " " << k;
        }
      }
      for (const ObservableInfo& o : observables()) expect_identical(r[o.id], base[o.id]);
    }
    // With friction beta0 matters (the test would see a difference).
    p.mu = 0.2;
    p.beta0 = 0.0;
    const double with_friction = run_ensemble(p, opt)[Observable::Duration].mean;
    p.beta0 = 0.31;
    EXPECT_NE(run_ensemble(p, opt)[Observable::Duration].mean, with_friction) << c.theta;
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

/// Every number of two ensemble results, compared bit for bit (per-sample outputs included).
void expect_identical(const EnsembleResult& a, const EnsembleResult& b) {
  for (const ObservableInfo& o : observables()) expect_identical(a[o.id], b[o.id]);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_EQ(a.exited, b.exited);
  EXPECT_EQ(a.rest, b.rest);
  EXPECT_EQ(a.trapped, b.trapped);
  EXPECT_EQ(a.total_collisions, b.total_collisions);
  EXPECT_EQ(a.simulated_collisions, b.simulated_collisions);
  EXPECT_EQ(a.wear.bins, b.wear.bins);
  for (int w = 0; w < 2; ++w) {
    EXPECT_EQ(a.wear.walls[w].collisions, b.wear.walls[w].collisions);
    EXPECT_EQ(a.wear.walls[w].impulse, b.wear.walls[w].impulse);
    EXPECT_TRUE(same_bits(a.wear.walls[w].edge_normal_impulse, b.wear.walls[w].edge_normal_impulse));
  }
  ASSERT_EQ(a.per_sample.size(), b.per_sample.size());
  for (std::size_t k = 0; k < a.per_sample.size(); ++k) {
    const Sample &x = a.per_sample[k], &y = b.per_sample[k];
    EXPECT_TRUE(same_bits(x.fraction, y.fraction) && same_bits(x.release.v.x, y.release.v.x)) << k;
    EXPECT_TRUE(same_bits(x.trajectory.duration, y.trajectory.duration)) << k;
    EXPECT_TRUE(same_bits(x.trajectory.exit_state.r.x, y.trajectory.exit_state.r.x)) << k;
    EXPECT_EQ(x.trajectory.collisions, y.trajectory.collisions) << k;
  }
}

TEST(Ensemble, ChunkStatisticsAreWelfordOverEveryObservableInSampleOrder) {
  // One chunk (N <= 16) of a mirror-halved line ensemble whose samples partly exit and partly
  // reach the time cap: its accumulators must be Welford's over value(t, o) of each sample and
  // then its mirror image, in index order, the exit observables over the exited samples only.
  Params p = default_params();
  p.theta = 46.0;
  p.t_max = 20.0;
  const EnsembleOptions o{16, ReleaseDist::Line, 1, true};
  ASSERT_EQ(chunk_count(o.samples), 1);
  const ChunkStats chunk = run_chunk(p, o, 0);
  ASSERT_EQ(chunk.samples.size(), 8u);
  std::array<Accumulator, observable_count> expected{};
  int exited = 0;
  for (const Sample& sample : chunk.samples) {
    for (const Trajectory& t : {sample.trajectory, mirrored(sample.trajectory)}) {
      exited += t.status == Status::Exited;
      for (const ObservableInfo& info : observables()) {
        if (info.exited_only && t.status != Status::Exited) continue;
        expected[static_cast<std::size_t>(info.id)].add(value(t, info.id));
      }
    }
  }
  EXPECT_GT(exited, 0);
  EXPECT_LT(exited, 16);
  for (const ObservableInfo& info : observables()) {
    const Accumulator &a = chunk.acc[static_cast<std::size_t>(info.id)], &b = expected[static_cast<std::size_t>(info.id)];
    EXPECT_EQ(a.n, b.n) << info.name;
    EXPECT_TRUE(same_bits(a.mean, b.mean) && same_bits(a.m2, b.m2) && same_bits(a.min, b.min) && same_bits(a.max, b.max))
        << info.name;
  }
}

TEST(Ensemble, ChunkPartitionDependsOnTheSampleCountOnly) {
  EXPECT_EQ(chunk_count(1), 1);
  EXPECT_EQ(chunk_count(16), 1);
  EXPECT_EQ(chunk_count(17), 2);
  EXPECT_EQ(chunk_count(4000), 250);
  EXPECT_EQ(chunk_count(1'000'000'000), 256);
}

TEST(Ensemble, ChunksComputedInAnyOrderAndSplitReduceToRunEnsembleBitForBit) {
  // What lets many processes share an ensemble: each chunk is a pure function of (point, chunk),
  // and the reduction merges them in chunk order, whoever computed them and in whatever order.
  Params p = default_params();
  p.theta = 47.0;
  EnsembleOptions line{1000, ReleaseDist::Line, 2, true};  // mirror halving, per-sample outputs
  EnsembleOptions random{300, ReleaseDist::Uniform, 2, false};
  random.velocity_sd = 0.05;
  random.seed = 77;
  random.wear_bins = 5;
  const EnsembleOptions disk{17, ReleaseDist::Disk, 1, true};
  for (const EnsembleOptions& o : {line, random, disk}) {
    const EnsembleResult reference = run_ensemble(p, o);
    const std::int64_t n_chunks = chunk_count(o.samples);
    // One by one, last chunk first, on this thread.
    std::vector<ChunkStats> backwards(static_cast<std::size_t>(n_chunks));
    for (std::int64_t c = n_chunks - 1; c >= 0; --c) backwards[static_cast<std::size_t>(c)] = run_chunk(p, o, c);
    expect_identical(reduce_chunks(p, o, std::move(backwards)), reference);
    // In three uneven batches of interleaved chunks, with 1 and 3 threads, among other points.
    Params other = p;
    other.theta = 60.0;
    const std::vector<Params> points{other, p};
    std::vector<ChunkStats> split(static_cast<std::size_t>(n_chunks));
    for (int batch = 0; batch < 3; ++batch) {
      std::vector<ChunkId> ids{{0, 0}};
      for (std::int64_t c = batch; c < n_chunks; c += 3) ids.push_back({1, c});
      EnsembleOptions t = o;
      t.threads = batch == 1 ? 1 : 3;
      std::vector<ChunkStats> done = run_chunks(points, t, ids);
      ASSERT_EQ(done.size(), ids.size());
      for (std::size_t i = 1; i < ids.size(); ++i) split[static_cast<std::size_t>(ids[i].chunk)] = std::move(done[i]);
    }
    expect_identical(reduce_chunks(p, o, split), reference);
    // The first chunks folded elsewhere (a process that computed chunks 0..k), then the rest.
    std::vector<ChunkStats> pieces(1);
    const std::int64_t k = n_chunks / 2;
    for (std::int64_t c = 0; c <= k; ++c) fold_chunk(pieces[0], std::move(split[static_cast<std::size_t>(c)]));
    for (std::int64_t c = k + 1; c < n_chunks; ++c) pieces.push_back(std::move(split[static_cast<std::size_t>(c)]));
    expect_identical(reduce_chunks(p, o, std::move(pieces)), reference);
  }
}

TEST(Ensemble, RunChunksRunsTheChunksOfPointsThatDifferOnlyInMuAsChainsBitForBit) {
  // What an MPI run computes (run_chunks on a unit of tasks): the ids' points that differ only
  // in mu run each shared chunk as a chain, and every chunk must still be run_chunk's, bit for
  // bit, whatever the order of the ids, with chunks missing for some points and an id named twice.
  Params p = default_params();
  std::vector<Params> points;
  for (const double mu : {1.0, 2.0, 5.0}) {
    p.mu = mu;
    points.push_back(p);
  }
  p.theta = 46.0;
  p.mu = 0.5;
  points.push_back(p);
  const std::vector<ChunkId> ids{{0, 3}, {1, 0}, {2, 1}, {0, 1}, {3, 0}, {1, 1}, {1, 2}, {0, 0},
                                 {1, 3}, {2, 2}, {3, 1}, {1, 2}};
  for (const ReleaseDist dist : {ReleaseDist::Line, ReleaseDist::Gaussian}) {
    const EnsembleOptions o{301, dist, 2, true};
    const std::vector<ChunkStats> got = run_chunks(points, o, ids);
    ASSERT_EQ(got.size(), ids.size());
    std::int64_t chained = 0, alone = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const ChunkStats want = run_chunk(points[ids[i].point], o, ids[i].chunk);
      const ChunkStats& c = got[i];
      for (std::size_t k = 0; k < want.acc.size(); ++k) {
        const Accumulator &a = c.acc[k], &b = want.acc[k];
        EXPECT_TRUE(a.n == b.n && same_bits(a.mean, b.mean) && same_bits(a.m2, b.m2) && same_bits(a.min, b.min) &&
                    same_bits(a.max, b.max))
            << "id " << i << ", observable " << k;
      }
      EXPECT_EQ(c.exited, want.exited);
      EXPECT_EQ(c.rest, want.rest);
      EXPECT_EQ(c.trapped, want.trapped);
      EXPECT_EQ(c.total_collisions, want.total_collisions);
      EXPECT_LE(c.simulated_collisions, want.simulated_collisions);
      ASSERT_EQ(c.samples.size(), want.samples.size()) << i;
      for (std::size_t k = 0; k < want.samples.size(); ++k) {
        ASSERT_TRUE(test::same_trajectory(c.samples[k].trajectory, want.samples[k].trajectory)) << "id " << i << ", sample " << k;
      }
      chained += c.simulated_collisions;
      alone += want.simulated_collisions;
    }
    // The reuse is real: at mu = 1 nearly every trajectory of theta = 60 sticks.
    EXPECT_LT(static_cast<double>(chained), 0.7 * static_cast<double>(alone)) << chained << " vs " << alone;
  }
  // The chains an MPI run deals together: each in ascending mu, in the order of their first point.
  std::vector<Params> mixed{points[3], points[1], points[0], points[3], points[2]};  // mu: 0.5 (46°), 2, 1, 0.5 (47°), 5
  mixed[3].theta = 47.0;
  EXPECT_EQ(friction_chains(mixed, EnsembleOptions{}), (std::vector<std::vector<std::size_t>>{{0}, {2, 1, 4}, {3}}));
  EnsembleOptions wear;
  wear.wear_bins = 4;  // a point with a wear record runs alone
  EXPECT_EQ(friction_chains(mixed, wear), (std::vector<std::vector<std::size_t>>{{0}, {1}, {2}, {3}, {4}}));
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
