// The batched SIMD path (src/batch.cpp) gives the scalar engine's results bit for bit, on every
// path this CPU runs, and it is the path that computes the collisions.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/engine3d.hpp"
#include "funnel/ensemble3d.hpp"
#include "funnel/flight3d.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/random.hpp"
#include "funnel/roots.hpp"
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
  add("asymmetric V, random velocities", [](Params& p) { p.theta_left = 72.0; p.theta_right = 31.0; }, 0.5);
  add("big ball, narrow gap", [](Params& p) { p.radius = 0.05; p.gap = 0.11; p.theta = p.theta_left = p.theta_right = 70.0; });
  add("time cap", [](Params& p) { p.t_max = 2.0; });
  add("collision cap", [](Params& p) { p.max_collisions = 57; });
  add("thrown with spin", [](Params& p) { p.release_u = 0.3; p.release_v = 0.2; p.release_spin = -40.0; });
  add("random velocities", [](Params&) {}, 0.5);
  // Funnels whose walls have more than one face: the lanes take the flights between the top
  // faces above every edge (src/engine.cpp batchable).
  add("spout", [](Params& p) { p.spout_length = 0.2; });
  add("spout at 46 degrees, random velocities", [](Params& p) { p.spout_length = 0.1; p.theta = p.theta_left = p.theta_right = 46.0; }, 0.3);
  add("asymmetric V with a spout", [](Params& p) { p.spout_length = 0.3; p.theta_left = 35.0; p.theta_right = 62.0; });
  add("hopper: a profile that steepens towards its outlet", [](Params& p) {
    ProfileSpec spec;
    spec.sides[0] = {{-1.0, 1.5}, {-0.3, 0.3}, {-0.05, -0.4}};
    spec.sides[1] = {{1.0, 1.5}, {0.3, 0.3}, {0.05, -0.4}};
    spec.mu = {0.3, 1.2};
    spec.source = "test";
    p.profile = std::make_shared<const ProfileSpec>(spec);
  });
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
      const std::string name = c.name;
      if (path == "scalar") {
        EXPECT_EQ(in_lanes, 0) << c.name;
      } else if (name.starts_with("hopper")) {
        // Most of the hopper's collisions are in its steep lower part, below the corner's edge
        // arc: the scalar engine's. The lanes still take the bounces on the top faces.
        EXPECT_GT(in_lanes, 0) << c.name << ", path " << path;
      } else if (name != "collision cap") {
        // The lanes compute most collisions (the point of the path; a path that handed every
        // event to the scalar engine would pass the comparison above). In an asymmetric V the
        // steeper wall's face reaches below the other's edge arc: the landings on it above every
        // arc are the lanes' too (they were not: 45% of the collisions in the lanes).
        EXPECT_GT(10 * in_lanes, 6 * collisions) << c.name << ", path " << path;
      }
    }
  }
}

TEST(Simd, AReleasesFirstFlightRunsInTheLanes) {
  // With a cap of two collisions the lanes can take only a release's first flight (the second
  // collision reaches the cap, which is the scalar engine's): each release lands on a face
  // above the edges, so each first collision is the lanes'.
  for (const double theta : {20.0, 60.0}) {
    Params p;
    p.theta = p.theta_left = p.theta_right = theta;
    p.max_collisions = 2;
    const Funnel f = make_funnel(p);
    const std::vector<State> initial = releases(p, f, 203, 0.0);
    for (const std::string& path : simd_paths()) {
      if (path == "scalar") continue;
      const PathScope scope(path);
      std::vector<Trajectory> got(initial.size());
      const std::int64_t in_lanes = simulate_many(p, f, initial, got);
      std::int64_t landed = 0;  // all but the releases over the gap, which fall through
      for (std::size_t k = 0; k < initial.size(); ++k) {
        ASSERT_TRUE(same_trajectory(got[k], simulate(p, f, initial[k]))) << path << ", sample " << k;
        if (got[k].collisions > 0) ++landed;
      }
      EXPECT_GT(landed, 190) << theta;
      EXPECT_EQ(in_lanes, landed) << path << ", theta " << theta;
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

TEST(Simd, FunnelsTheLanesCannotTakeRunOneTrajectoryAtATime) {
  // Ledges: each wall turns horizontal at a concave corner (x = -+0.25, y = 0.2), below its top
  // face's edge. A face bounded by a concave corner is a hit anywhere on its line beyond that
  // end (the neighbouring face bounds it), so that no argument keeps the flights between the
  // top faces off the lower ones: the lanes, which look at the top faces only, must leave such
  // a funnel to the scalar engine.
  ProfileSpec spec;
  spec.sides[0] = {{-1.0, 1.5}, {-0.3, 0.6}, {-0.25, 0.2}, {-0.15, 0.2}, {-0.05, -0.3}};
  spec.sides[1] = {{1.0, 1.5}, {0.3, 0.6}, {0.25, 0.2}, {0.15, 0.2}, {0.05, -0.3}};
  spec.source = "test";
  Params p;
  p.profile = std::make_shared<const ProfileSpec>(spec);
  p.release_height = 1.5;  // released above every edge arc, where the lanes would take over
  const Funnel f = make_funnel(p);
  const std::vector<State> initial = releases(p, f, 50, 0.0);
  for (const std::string& path : simd_paths()) {
    const PathScope scope(path);
    std::vector<Trajectory> got(initial.size());
    EXPECT_EQ(simulate_many(p, f, initial, got), 0) << path;
    for (std::size_t k = 0; k < initial.size(); ++k) {
      EXPECT_TRUE(same_trajectory(got[k], simulate(p, f, initial[k]))) << path << ", sample " << k;
    }
  }
}

// ---- The 3D engine: the face times of many flights at once (src/batch3d.cpp) ----

double uniform(std::uint64_t stream, std::uint64_t k, double lo, double hi) {
  return lo + (hi - lo) * (0.5 + 0.5 * std::erf(standard_normal(11, stream, k) / std::sqrt(2.0)));
}

/// Flights of every kind the 3D engine starts: those after the events of random 3D trajectories
/// (off a face, off the rim, after a contact), and made-up ones: anywhere in and below the cone
/// with any velocity (distances behind a generator, negative ones below C*), in a meridian plane
/// (exact zeros), and grazing the cone (slow fixed points).
void flights_3d(const Params& p, const Cone& c, std::vector<State3>& s, std::vector<FlightStart3>& start) {
  Ensemble3Options o;
  o.samples = 24;
  o.velocity_sd = 0.3;
  for (std::int64_t k = 0; k < o.samples; ++k) {
    State3 r = ensemble_release_3d(p, c, o, k);
    r.omega = {30.0 * standard_normal(5, 1, static_cast<std::uint64_t>(k)), 0.0, 0.0};
    s.push_back(r);
    start.push_back({});
    EventLog3 log;
    simulate_3d(p, c, r, &log);
    for (std::size_t i = 0; i < log.events.size() && i < 400; ++i) {
      const Event3& e = log.events[i];
      FlightStart3 f;
      f.on_face = e.kind == EventKind::Face;
      f.on_rim = e.kind == EventKind::Edge || e.kind == EventKind::EdgeContactEnd;
      f.skip_face = e.kind == EventKind::ContactEnd && i % 2 == 0;
      s.push_back({e.position, e.velocity_after, e.omega_after});
      start.push_back(f);
    }
  }
  const Geometry& g = c.g;
  for (std::uint64_t k = 0; k < 3000; ++k) {
    const double y = uniform(1, k, g.y_bottom - 0.05, 1.3 * g.y_release);
    const double phi = uniform(2, k, -3.2, 3.2);
    const double rho = uniform(3, k, 0.0, 1.1) * std::fmax(y / std::tan(p.theta * std::numbers::pi / 180.0), c.rim_radius);
    State3 f;
    f.r = {rho * std::cos(phi), y, rho * std::sin(phi)};
    f.v = {standard_normal(12, 4, k), standard_normal(12, 5, k), standard_normal(12, 6, k)};
    FlightStart3 st;
    st.on_face = k % 3 == 0;
    if (k % 5 == 0) {  // a meridian plane: z exactly 0, sometimes on the axis
      f.r.z = 0.0;
      f.v.z = 0.0;
      if (k % 25 == 0) f.r.x = 0.0;
    }
    if (k % 7 == 0) {
      // Grazing the cone: tangent to it at a point above C*, started a little before.
      const Vec3 b{std::cos(phi), 0.0, std::sin(phi)};
      const double l = uniform(7, k, 0.0, 1.0) * (g.y_release - g.y_face_end) / g.sin_t;
      const Vec3 at{(g.x_face_end + l * g.cos_t) * b.x, g.y_face_end + l * g.sin_t, (g.x_face_end + l * g.cos_t) * b.z};
      const Vec3 along{g.cos_t * b.x, g.sin_t, g.cos_t * b.z}, across{-b.z, 0.0, b.x};
      const double a1 = standard_normal(13, 1, k), a2 = standard_normal(13, 2, k);
      const double back = uniform(8, k, 1e-6, 0.5);
      State3 touch{at, a1 * along + a2 * across, {}};
      f = advance(touch, -back);
    }
    s.push_back(f);
    start.push_back(st);
  }
}

TEST(Simd, TheFaceTimesOfManyConeFlightsAtOnceAreEachFlightsBitForBitOnEveryPath) {
  std::int64_t hits = 0, misses = 0, total = 0, capped_differ = 0;
  for (const double theta : {20.0, 44.0, 60.0, 85.0}) {
    for (const double gap : {0.04, 0.0}) {
      Params p = default_params();
      p.theta = theta;
      p.gap = gap;
      p.t_max = 50.0;
      const Cone c = make_cone(p);
      std::vector<State3> s;
      std::vector<FlightStart3> start;
      flights_3d(p, c, s, start);
      total += static_cast<std::int64_t>(s.size());
      // The engine's cap of 40 iterations, and low caps that send many flights to the
      // bracketing fallback (which the engine's flights seldom reach).
      for (const int cap : {40, 1, 2, 3}) {
        std::vector<double> expected;
        for (std::size_t i = 0; i < s.size(); ++i) expected.push_back(detail::cone_face_time(c, s[i], start[i], cap));
        for (std::size_t i = 0; i < s.size(); ++i) {
          if (cap == 40) (expected[i] == never ? misses : hits) += 1;
          if (cap == 2) capped_differ += !same_bits(expected[i], cone_face_time(c, s[i], start[i]));
        }
        for (const std::string& path : simd_paths()) {
          const PathScope scope(path);
          std::vector<double> got(s.size(), -1.0);
          // Groups of every size from 1 to max_face_lanes.
          for (std::size_t first = 0, n = 1; first < s.size(); first += n, n = n % max_face_lanes + 1) {
            const std::size_t m = std::min(n, s.size() - first);
            detail::cone_face_times(c, {s.data() + first, m}, {start.data() + first, m}, {got.data() + first, m}, cap);
          }
          for (std::size_t i = 0; i < s.size(); ++i) {
            ASSERT_TRUE(same_bits(got[i], expected[i]))
                << "theta " << theta << ", gap " << gap << ", cap " << cap << ", path " << path << ", flight " << i
                << ": " << got[i] << " instead of " << expected[i];
          }
          if (cap == 40) {
            std::vector<double> public_api(s.size());
            for (std::size_t first = 0; first < s.size(); first += max_face_lanes) {
              const std::size_t m = std::min(max_face_lanes, s.size() - first);
              cone_face_times(c, {s.data() + first, m}, {start.data() + first, m}, {public_api.data() + first, m});
            }
            for (std::size_t i = 0; i < s.size(); ++i) ASSERT_TRUE(same_bits(public_api[i], expected[i])) << i;
          }
        }
      }
    }
  }
  EXPECT_GT(total, 40000);
  EXPECT_GT(hits, total / 4);
  EXPECT_GT(misses, 200);
  EXPECT_GT(capped_differ, 100);  // the fallback ran, and its last bits are its own
}

TEST(Simd, ManyThreeDimensionalTrajectoriesRunSideBySideAreEachTheSameBitsOnEveryPath) {
  struct Case3 {
    const char* name;
    double theta, e, mu, beta0, gap, t_max, velocity_sd;
    std::int64_t max_collisions;
  };
  const Case3 cases3[] = {
      {"60 degrees, sigma 0.1 (collapses, rolling round the cone)", 60, 0.99, 1, 0, 0.04, 300, 0.1, 100'000'000},
      {"44 degrees, sigma 0.3", 44, 0.99, 1, 0.31, 0.04, 300, 0.3, 100'000'000},
      {"frictionless elastic", 50, 1.0, 0.0, -1.0, 0.04, 60, 0.2, 100'000'000},
      {"closed cone", 50, 0.9, 0.2, 0, 0.0, 12, 0.2, 100'000'000},
      {"time cap", 60, 0.99, 1, 0, 0.04, 3, 0.1, 100'000'000},
      {"collision cap", 60, 0.99, 1, 0, 0.04, 300, 0.1, 57},
  };
  for (const Case3& k : cases3) {
    Params p = default_params();
    p.theta = k.theta;
    p.e = k.e;
    p.mu = k.mu;
    p.beta0 = k.beta0;
    p.gap = k.gap;
    p.t_max = k.t_max;
    p.max_collisions = k.max_collisions;
    const Cone c = make_cone(p);
    Ensemble3Options o;
    o.samples = 61;
    o.velocity_sd = k.velocity_sd;
    o.seed = 9;
    std::vector<State3> initial;
    std::vector<Trajectory3> expected;
    for (std::int64_t i = 0; i < o.samples; ++i) {
      initial.push_back(ensemble_release_3d(p, c, o, i));
      expected.push_back(simulate_3d(p, c, initial.back()));
    }
    for (const std::string& path : simd_paths()) {
      const PathScope scope(path);
      std::vector<Trajectory3> got(initial.size());
      simulate_3d_many(p, c, initial, got);
      for (std::size_t i = 0; i < initial.size(); ++i) {
        ASSERT_TRUE(same_trajectory(got[i], expected[i])) << k.name << ", path " << path << ", sample " << i;
      }
    }
  }
  // Cancelled before it starts: no trajectory is run, the outputs are left as they were.
  Params p = default_params();
  const Cone c = make_cone(p);
  const std::vector<State3> initial(5, release_state_3d(p, c, 0.3));
  std::vector<Trajectory3> got(5);
  got[2].duration = -7.0;
  const std::atomic<bool> cancel{true};
  simulate_3d_many(p, c, initial, got, &cancel);
  EXPECT_EQ(got[2].duration, -7.0);
  EXPECT_EQ(got[0].collisions, 0);
}

TEST(Simd, ThreeDimensionalEnsemblesAreTheSameBitsOnEveryPath) {
  Params p = default_params();
  p.theta = 60.0;
  p.t_max = 300.0;
  Ensemble3Options o;
  o.samples = 300;
  o.velocity_sd = 0.05;
  o.threads = 2;
  o.keep_samples = true;
  std::vector<Ensemble3Result> results;
  for (const std::string& path : simd_paths()) {
    const PathScope scope(path);
    results.push_back(run_ensemble_3d(p, o));
  }
  const Cone c = make_cone(p);
  for (std::size_t k = 0; k < results[0].per_sample.size(); ++k) {
    const Trajectory3 alone = simulate_3d(p, c, ensemble_release_3d(p, c, o, static_cast<std::int64_t>(k)));
    for (const Ensemble3Result& r : results) ASSERT_TRUE(same_trajectory(r.per_sample[k].trajectory, alone)) << k;
  }
  for (std::size_t i = 1; i < results.size(); ++i) {
    for (std::size_t o2 = 0; o2 < results[0].stats.size(); ++o2) {
      EXPECT_TRUE(same_bits(results[i].stats[o2].mean, results[0].stats[o2].mean));
      EXPECT_TRUE(same_bits(results[i].stats[o2].sem, results[0].stats[o2].sem));
    }
  }
  EXPECT_GT(results[0].trapped, 0);  // rolling round the cone: long trajectories among short ones
}

}  // namespace
}  // namespace funnel
