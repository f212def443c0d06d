// Google Benchmark: the collision law, one event search, one trajectory, the reference ensemble,
// the batched path per SIMD path, the edge quartic's root, a sweep over friction and the 3D cone's
// trajectories side by side.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/engine3d.hpp"
#include "funnel/ensemble3d.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/flight.hpp"
#include "funnel/roots.hpp"
#include "funnel/simd.hpp"
#include "funnel/walton.hpp"
#include "../tests/plain_refinement.hpp"

namespace {

using namespace funnel;

/// The reference parameters of docs/performance.md: theta = 60, e = 0.99, mu = 1, beta0 = 0.
Params reference() { return default_params(); }

void BM_Collide(benchmark::State& st) {
  const Params p = reference();
  const CollisionConstants k = collision_constants(material(p));
  const Geometry g = make_geometry(p);
  const Vec2 n = face_normal(g, Wall::Left);
  State s;
  s.v = {0.3, -1.2};
  s.omega = 4.0;
  for (auto _ : st) {
    const Collision c = collide(s, n, k);
    benchmark::DoNotOptimize(c);
    s.omega = c.after.omega * 0.5;  // keep the input changing
  }
  st.counters["collisions_per_second"] = benchmark::Counter(static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Collide);

void BM_NextEventFaceToFace(benchmark::State& st) {
  const Params p = reference();
  const Geometry g = make_geometry(p);
  State s;
  s.r = {-0.3, 0.3 * g.tan_t};
  s.v = {0.9, 0.4};
  FlightStart start;
  start.on_face = WallPart{Wall::Left, 0};
  const Funnel f = make_funnel(p);
  for (auto _ : st) {
    const NextEvent ev = next_event(f, s, start);
    benchmark::DoNotOptimize(ev);
    s.v.y = 0.4 + 1e-9 * ev.dt;
  }
  st.counters["events_per_second"] = benchmark::Counter(static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_NextEventFaceToFace);

void BM_Trajectory(benchmark::State& st) {
  const Params p = reference();
  const Geometry g = make_geometry(p);
  std::int64_t collisions = 0;
  for (auto _ : st) {
    const Trajectory t = simulate_release(p, g, 0.3);
    collisions += t.collisions;
    benchmark::DoNotOptimize(t);
  }
  st.counters["collisions_per_second"] = benchmark::Counter(static_cast<double>(collisions), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Trajectory);

void BM_ReferenceEnsemble(benchmark::State& st) {
  const Params p = reference();
  const EnsembleOptions opt{40000, ReleaseDist::Line, static_cast<int>(st.range(0)), false};
  std::int64_t collisions = 0, simulated = 0;
  for (auto _ : st) {
    const EnsembleResult r = run_ensemble(p, opt);
    collisions += r.total_collisions;
    simulated += r.simulated_collisions;
  }
  // The headline: collisions actually computed (one mirror half); the mirrored count beside it.
  st.counters["computed_collisions_per_second"] =
      benchmark::Counter(static_cast<double>(simulated), benchmark::Counter::kIsRate);
  st.counters["collisions_with_mirror_images_per_second"] =
      benchmark::Counter(static_cast<double>(collisions), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ReferenceEnsemble)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The batched path: 4000 releases of the reference V run together by simulate_many, on one
/// path (argument: the index in simd_paths(); 0 is the scalar engine). A path this CPU does not
/// run is skipped.
void BM_BatchedTrajectories(benchmark::State& st) {
  const std::vector<std::string> paths = simd_paths();
  const auto index = static_cast<std::size_t>(st.range(0));
  if (index >= paths.size()) {
    st.SkipWithError("this CPU does not run this path");
    return;
  }
  const std::string saved = simd_path();
  set_simd_path(paths[index]);
  st.SetLabel(paths[index]);
  const Params p = reference();
  const Funnel f = make_funnel(p);
  std::vector<State> initial;
  for (int k = 0; k < 2000; ++k) initial.push_back(release_state(p, f, (2.0 * k + 1.0 - 4000.0) / 4000.0));
  std::vector<Trajectory> out(initial.size());
  std::int64_t collisions = 0, in_lanes = 0;
  for (auto _ : st) {
    in_lanes += simulate_many(p, f, initial, out);
    for (const Trajectory& t : out) collisions += t.collisions;
  }
  set_simd_path(saved);
  st.counters["computed_collisions_per_second"] =
      benchmark::Counter(static_cast<double>(collisions), benchmark::Counter::kIsRate);
  st.counters["share_in_lanes"] = collisions > 0 ? static_cast<double>(in_lanes) / static_cast<double>(collisions) : 0.0;
}
BENCHMARK(BM_BatchedTrajectories)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The edge quartic's root (docs/performance.md, item 12) on 4096 brackets of edge approaches
/// like the V's (a centre within 4 radii of the edge point, speeds up to sqrt(gH), a = 0.01):
/// argument 0, the reference loop; 1, the engine's choice (the certified root, else the loop).
void BM_EdgeRoot(benchmark::State& st) {
  struct Approach {
    std::array<double, 5> c;
    detail::Bracket b;
  };
  std::vector<Approach> approaches;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double a = 0.01;
  while (approaches.size() < 4096) {
    const double dx = 4 * a * u(rng), dy = 4 * a * u(rng), vx = u(rng), vy = u(rng);
    const std::array<double, 5> c = funnel::test::edge_approach_quartic(dx, dy, vx, vy, a);
    if (c[0] <= 0.0) continue;
    if (const auto b = detail::descending_bracket(c, 0.2)) approaches.push_back({c, *b});
  }
  const bool choice = st.range(0) == 1;
  st.SetLabel(choice ? "certified, else reference" : "reference");
  std::int64_t certified = 0, roots = 0;
  for (auto _ : st) {
    for (const Approach& e : approaches) {
      const detail::Bracket& b = e.b;
      double r = choice ? detail::refine_certified(e.c, b.lo, b.hi, b.flo, b.fhi) : std::numeric_limits<double>::quiet_NaN();
      if (r == r) {
        ++certified;
      } else {
        r = detail::refine_reference(e.c, b.lo, b.hi, b.flo, b.fhi);
      }
      benchmark::DoNotOptimize(r);
    }
    roots += static_cast<std::int64_t>(approaches.size());
  }
  st.counters["roots_per_second"] = benchmark::Counter(static_cast<double>(roots), benchmark::Counter::kIsRate);
  st.counters["share_certified"] = roots > 0 ? static_cast<double>(certified) / static_cast<double>(roots) : 0.0;
}
BENCHMARK(BM_EdgeRoot)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

/// A sweep over friction: theta = 60, mu = 0.1, 0.2, 0.5, 1, 2, 5, N = 4000 each, one thread.
/// Argument 1: one run_sweep, whose points run as a chain (a release runs again at the next mu
/// only if its trajectory slid); 0: each point alone (run_ensemble), the cost without the
/// chain. The same statistics either way; `computed_collisions` counts the collisions run.
void BM_FrictionSweep(benchmark::State& st) {
  std::vector<Params> points;
  for (const double mu : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0}) {
    Params p = reference();
    p.mu = mu;
    points.push_back(p);
  }
  const EnsembleOptions opt{4000, ReleaseDist::Line, 1, false};
  std::int64_t computed = 0, points_done = 0;
  for (auto _ : st) {
    if (st.range(0) == 1) {
      for (const EnsembleResult& r : run_sweep(points, opt)) computed += r.simulated_collisions;
    } else {
      for (const Params& p : points) computed += run_ensemble(p, opt).simulated_collisions;
    }
    points_done += static_cast<std::int64_t>(points.size());
  }
  st.counters["points_per_second"] = benchmark::Counter(static_cast<double>(points_done), benchmark::Counter::kIsRate);
  st.counters["computed_collisions"] =
      benchmark::Counter(static_cast<double>(computed) / static_cast<double>(st.iterations()));
}
BENCHMARK(BM_FrictionSweep)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The 3D cone (theta = 60, e = 0.99, mu = 1, sigma = 0.1, t_max = 300, as in the fig3d page):
/// 256 of its 4000 balls (every 16th). Argument 0: one at a time (simulate_3d, the face times'
/// fixed points one after the other); 1 + i: side by side (simulate_3d_many, their fixed points
/// together) on the path simd_paths()[i], 1 the scalar engine. The same trajectories.
void BM_Cone3d(benchmark::State& st) {
  const std::vector<std::string> paths = simd_paths();
  const auto arg = static_cast<std::size_t>(st.range(0));
  if (arg > paths.size()) {
    st.SkipWithError("this CPU does not run this path");
    return;
  }
  const std::string saved = simd_path();
  if (arg > 0) set_simd_path(paths[arg - 1]);
  st.SetLabel(arg == 0 ? "one at a time" : "side by side, " + paths[arg - 1]);
  Params p = reference();
  p.t_max = 300.0;
  const Cone c = make_cone(p);
  Ensemble3Options o;
  o.velocity_sd = 0.1;
  std::vector<State3> initial;
  for (std::int64_t k = 0; k < o.samples; k += 16) initial.push_back(ensemble_release_3d(p, c, o, k));
  std::vector<Trajectory3> out(initial.size());
  std::int64_t collisions = 0;
  for (auto _ : st) {
    if (arg == 0) {
      for (std::size_t k = 0; k < initial.size(); ++k) out[k] = simulate_3d(p, c, initial[k]);
    } else {
      simulate_3d_many(p, c, initial, out);
    }
    for (const Trajectory3& t : out) collisions += t.collisions;
  }
  set_simd_path(saved);
  st.counters["collisions_per_second"] = benchmark::Counter(static_cast<double>(collisions), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Cone3d)->DenseRange(0, 4)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
