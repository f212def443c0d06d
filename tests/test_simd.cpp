// The batched SIMD path (src/batch.cpp) gives the scalar engine's results bit for bit, on every
// path this CPU runs, and it is the path that computes the collisions.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/random.hpp"
#include "funnel/closed.hpp"
#include "funnel/simd.hpp"
#include "funnel/watch.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::same_bits;
using test::same_trajectory;

/// The path in use for the test's duration, restored afterwards.
class PathScope {
 public:
  explicit PathScope(const std::string& name) : saved_(simd_path()) { EXPECT_TRUE(set_simd_path(name)) << name; }
  ~PathScope() { set_simd_path(saved_); }
  PathScope(const PathScope&) = delete;
  PathScope& operator=(const PathScope&) = delete;

 private:
  std::string saved_;
};

struct Case {
  const char* name;
  Params params;
  double velocity_sd = 0.0;  ///< random release velocities and spins
};

std::vector<Case> cases() {
  std::vector<Case> out;
  auto add = [&](const char* name, auto edit, double velocity_sd = 0.0) {
    Params p;
    edit(p);
    out.push_back({name, p, velocity_sd});
  };
  add("reference", [](Params&) {});
  add("anomaly 46 degrees", [](Params& p) { p.theta = p.theta_left = p.theta_right = 46.0; });
  add("collapses at 5 degrees", [](Params& p) { p.theta = p.theta_left = p.theta_right = 5.0; });
  add("beta0 0.31, mu 0.2", [](Params& p) { p.beta0 = 0.31; p.mu = 0.2; });
  add("beta0 -0.31, e 0.4", [](Params& p) { p.beta0 = -0.31; p.e = 0.4; });
  add("frictionless elastic", [](Params& p) { p.mu = 0.0; p.e = 1.0; });
  add("e 0.1, mu 5", [](Params& p) { p.e = 0.1; p.mu = 5.0; });
  add("asymmetric V", [](Params& p) { p.theta_left = 40.0; p.theta_right = 55.5; });
  add("big ball, narrow gap", [](Params& p) { p.radius = 0.05; p.gap = 0.11; p.theta = p.theta_left = p.theta_right = 70.0; });
  add("time cap", [](Params& p) { p.t_max = 2.0; });
  add("collision cap", [](Params& p) { p.max_collisions = 57; });
  add("thrown with spin", [](Params& p) { p.release_u = 0.3; p.release_v = 0.2; p.release_spin = -40.0; });
  add("random velocities", [](Params&) {}, 0.5);
  return out;
}

std::vector<State> releases(const Params& params, const Funnel& f, int n, double velocity_sd) {
  std::vector<State> out;
  for (int k = 0; k < n; ++k) {
    State s = release_state(params, f, (2.0 * k + 1.0 - n) / n);
    if (velocity_sd > 0.0) {
      s.v.x += velocity_sd * standard_normal(7, 1, static_cast<std::uint64_t>(k));
      s.v.y += velocity_sd * standard_normal(7, 2, static_cast<std::uint64_t>(k));
      s.omega += 100.0 * velocity_sd * standard_normal(7, 3, static_cast<std::uint64_t>(k));
    }
    out.push_back(s);
  }
  return out;
}

TEST(Simd, TheScalarPathIsAlwaysThereAndTheDefaultIsTheWidest) {
  const std::vector<std::string> paths = simd_paths();
  ASSERT_FALSE(paths.empty());
  EXPECT_EQ(paths.front(), "scalar");
  EXPECT_FALSE(set_simd_path("avx1024"));
  {
    const PathScope scalar("scalar");
    EXPECT_EQ(simd_path(), "scalar");
    EXPECT_EQ(simd_lanes(), 1);
  }
  for (const std::string& p : paths) {
    const PathScope scope(p);
    EXPECT_EQ(simd_path(), p);
    EXPECT_EQ(simd_lanes(), p == "scalar" ? 1 : p == "sse4" ? 2 : p == "avx2" ? 4 : 8) << p;
  }
}

TEST(Simd, EveryPathGivesTheScalarEnginesTrajectoriesBitForBit) {
  for (const Case& c : cases()) {
    const Funnel f = make_funnel(c.params);
    const std::vector<State> initial = releases(c.params, f, 203, c.velocity_sd);
    std::vector<Trajectory> expected;
    for (const State& s : initial) expected.push_back(simulate(c.params, f, s));
    for (const std::string& path : simd_paths()) {
      const PathScope scope(path);
      std::vector<Trajectory> got(initial.size());
      const std::int64_t in_lanes = simulate_many(c.params, f, initial, got);
      std::int64_t collisions = 0;
      for (std::size_t k = 0; k < initial.size(); ++k) {
        ASSERT_TRUE(same_trajectory(got[k], expected[k])) << c.name << ", path " << path << ", sample " << k;
        collisions += got[k].collisions;
      }
      if (path == "scalar") {
        EXPECT_EQ(in_lanes, 0) << c.name;
      } else if (std::string(c.name) != "collision cap") {
        // The lanes compute most collisions (the point of the path; a path that handed every
        // event to the scalar engine would pass the comparison above). In an asymmetric V the
        // lower wall's outlet edge is below the other's, so that fewer flights are above every
        // edge arc: 45% there, over 80% in the symmetric cases.
        EXPECT_GT(3 * in_lanes, collisions) << c.name << ", path " << path;
      }
    }
  }
}

TEST(Simd, AVWithAMaterialPerWallIsTheSameBitsOnEveryPath) {
  // A one-segment wall profile per side (a V) with its own e and mu on each wall: the lanes
  // take each collision's law from the wall hit.
  ProfileSpec spec;
  spec.sides[0] = {{-1.2, 1.5}, {-0.03, 0.0}};
  spec.sides[1] = {{1.0, 1.3}, {0.03, 0.0}};
  spec.e = {0.9, 0.995};
  spec.mu = {0.2, 1.5};
  spec.beta0 = {0.31, -0.2};
  spec.source = "test";
  Params p;
  p.profile = std::make_shared<const ProfileSpec>(spec);
  const Funnel f = make_funnel(p);
  ASSERT_TRUE(f.one_face);
  const std::vector<State> initial = releases(p, f, 203, 0.0);
  std::vector<Trajectory> expected;
  for (const State& s : initial) expected.push_back(simulate(p, f, s));
  for (const std::string& path : simd_paths()) {
    const PathScope scope(path);
    std::vector<Trajectory> got(initial.size());
    const std::int64_t in_lanes = simulate_many(p, f, initial, got);
    for (std::size_t k = 0; k < initial.size(); ++k) {
      ASSERT_TRUE(same_trajectory(got[k], expected[k])) << "path " << path << ", sample " << k;
    }
    if (path != "scalar") {
      EXPECT_GT(in_lanes, 0) << path;
    }
  }
}

TEST(Simd, EnsemblesAreTheSameBitsOnEveryPath) {
  Params p;
  p.theta = p.theta_left = p.theta_right = 46.0;
  EnsembleOptions o;
  o.samples = 1001;
  o.threads = 2;
  o.keep_samples = true;
  std::vector<EnsembleResult> results;
  for (const std::string& path : simd_paths()) {
    const PathScope scope(path);
    results.push_back(run_ensemble(p, o));
  }
  for (std::size_t i = 1; i < results.size(); ++i) {
    for (std::size_t k = 0; k < results[0].per_sample.size(); ++k) {
      ASSERT_TRUE(same_trajectory(results[i].per_sample[k].trajectory, results[0].per_sample[k].trajectory)) << k;
    }
    for (std::size_t o2 = 0; o2 < results[0].stats.size(); ++o2) {
      EXPECT_TRUE(same_bits(results[i].stats[o2].mean, results[0].stats[o2].mean));
    }
  }
}

TEST(Simd, ClosedFunnelsWithTheOrbitWatchAreTheSameBitsOnEveryPath) {
  // The closed V of Figs. 11-12 (e = 1: the period-2 orbit or, through friction, rest at the
  // vertex), an inelastic one that always comes to rest, and an asymmetric one.
  std::vector<Params> cases(3);
  for (Params& p : cases) {
    p.gap = 0.0;
    p.e = 1.0;
    p.t_max = 1e4;
    p.max_collisions = 10'000'000;
  }
  cases[0].theta = cases[0].theta_left = cases[0].theta_right = 50.0;
  cases[0].mu = 0.01;
  cases[1].e = 0.9;
  cases[1].mu = 0.2;
  cases[2].theta_left = 55.0;
  cases[2].theta_right = 65.0;
  cases[2].mu = 0.05;
  cases[2].t_max = 300.0;
  for (const Params& p : cases) {
    const Funnel f = make_funnel(p);
    const std::vector<State> initial = releases(p, f, 61, 0.0);
    const OrbitTest test{20, 1e-6, 1e-6};
    std::vector<Trajectory> expected;
    std::vector<OrbitWatch> expected_watches(initial.size(), OrbitWatch(test));
    for (std::size_t k = 0; k < initial.size(); ++k) expected.push_back(simulate(p, f, initial[k], &expected_watches[k]));
    int periodic = 0, rest = 0;
    for (const Trajectory& t : expected) {
      periodic += t.stopped;
      rest += t.status == Status::Rest;
    }
    // In the symmetric Vs every release ends periodic or at rest; the asymmetric V's orbits do
    // not repeat their heights, and its runs reach the time cap (undecided), on every path alike.
    if (p.left_angle() == p.right_angle()) {
      EXPECT_EQ(periodic + rest, 61) << "theta " << p.left_angle() << ", e " << p.e;
    }
    for (const std::string& path : simd_paths()) {
      const PathScope scope(path);
      std::vector<Trajectory> got(initial.size());
      std::vector<OrbitWatch> watches(initial.size(), OrbitWatch(test));
      const std::int64_t in_lanes = simulate_many(p, f, initial, got, watches);
      std::int64_t collisions = 0;
      for (std::size_t k = 0; k < initial.size(); ++k) {
        ASSERT_TRUE(same_trajectory(got[k], expected[k])) << "theta " << p.left_angle() << ", path " << path << ", sample " << k;
        EXPECT_TRUE(same_bits(watches[k].last().x, expected_watches[k].last().x) &&
                    same_bits(watches[k].last().y, expected_watches[k].last().y) &&
                    same_bits(watches[k].prev().x, expected_watches[k].prev().x) &&
                    same_bits(watches[k].prev().y, expected_watches[k].prev().y));
        EXPECT_EQ(watches[k].memory().streak, expected_watches[k].memory().streak);
        collisions += got[k].collisions;
      }
      if (path != "scalar") {  // a closed V has no edge: nearly all
        EXPECT_GT(2 * in_lanes, collisions) << path;
      }
    }
  }
  // run_closed (Figs. 11-12) on every path, sample by sample.
  Params p = cases[0];
  EnsembleOptions o;
  o.samples = 203;
  o.threads = 2;
  std::vector<ClosedResult> results;
  for (const std::string& path : simd_paths()) {
    const PathScope scope(path);
    results.push_back(run_closed(p, o, ClosedOptions{}));
  }
  for (std::size_t i = 1; i < results.size(); ++i) {
    for (std::size_t k = 0; k < results[0].samples.size(); ++k) {
      const ClosedSample& a = results[i].samples[k];
      const ClosedSample& b = results[0].samples[k];
      EXPECT_TRUE(a.state == b.state && a.collisions == b.collisions && same_bits(a.time, b.time) &&
                  same_bits(a.energy, b.energy) && same_bits(a.x_last, b.x_last) && same_bits(a.y_prev, b.y_prev))
          << k;
    }
  }
}

TEST(Simd, AChunkLongerThanOneBlockOfReleasesIsEverySampleBitForBit) {
  // N = 2 200 000 line releases: 1 100 000 simulated in 256 chunks of about 4300, more than the
  // 4096 releases an ensemble runs together (its memory stays bounded whatever N), so that the
  // chunk spans two blocks. Each of its samples is the direct simulation.
  Params p;
  p.theta = p.theta_left = p.theta_right = 80.0;
  EnsembleOptions o;
  o.samples = 2'200'000;
  o.keep_samples = true;
  const Funnel f = make_funnel(p);
  const ChunkStats chunk = run_chunk(p, o, 1);
  ASSERT_GT(chunk.samples.size(), 4096U);
  for (const Sample& s : chunk.samples) {
    ASSERT_TRUE(same_trajectory(s.trajectory, simulate(p, f, s.release))) << s.fraction;
  }
}

TEST(Simd, OtherFunnelsRunOneTrajectoryAtATime) {
  Params p;
  p.spout_length = 0.2;  // a V with a spout: three faces, not the batched V
  const Funnel f = make_funnel(p);
  const std::vector<State> initial = releases(p, f, 50, 0.0);
  std::vector<Trajectory> got(initial.size());
  EXPECT_EQ(simulate_many(p, f, initial, got), 0);
  for (std::size_t k = 0; k < initial.size(); ++k) EXPECT_TRUE(same_trajectory(got[k], simulate(p, f, initial[k])));
}

}  // namespace
}  // namespace funnel
