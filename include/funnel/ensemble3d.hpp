// Ensembles of 3D trajectories in the axisymmetric funnel, with random horizontal release
// velocities from a counter-based generator: deterministic for any thread count.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "funnel/engine3d.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/stats.hpp"

namespace funnel {

/// The random streams of the release velocities: sample k adds velocity_sd times
/// standard_normal(seed, stream, k) to u with stream release_velocity_u_stream (the stream of u
/// in 2D ensembles) and to w with release_velocity_w_stream.
inline constexpr std::uint64_t release_velocity_u_stream = 1;
inline constexpr std::uint64_t release_velocity_w_stream = 3;  ///< free in 2D (position 0, u 1, v 2)

/// How to run a 3D ensemble.
struct Ensemble3Options {
  std::int64_t samples = default_samples;  ///< N >= 1
  ReleaseDist dist = ReleaseDist::Disk;     ///< release distances from the axis (disk: uniform over the opening)
  double velocity_sd = 0.0;   ///< sigma of each horizontal release velocity component (u, w), units sqrt(gH), >= 0
  std::uint64_t seed = 1;     ///< seed of the random release velocities
  int threads = 0;            ///< 0: all cores
  bool keep_samples = false;  ///< also return every trajectory (O(N) memory)
  /// When set and it becomes true, the trajectories not yet started are skipped and the results
  /// are incomplete (e.g. Ctrl-C in Python); the caller checks it after the run.
  std::atomic<bool>* cancel = nullptr;
};

/// One sample of a 3D ensemble, kept on request.
struct Sample3 {
  double fraction = 0.0;    ///< release distance from the axis / L (negative: on the -x side)
  Vec3 velocity;            ///< release velocity
  Trajectory3 trajectory;   ///< its observables
};

/// Statistics of a 3D ensemble.
struct Ensemble3Result {
  std::int64_t samples = 0;
  std::array<Summary, observable_count_3d> stats{};  ///< every 3D observable; exit ones over the exited samples
  std::int64_t exited = 0, rest = 0, trapped = 0;  ///< count of each status
  std::int64_t periodic = 0;          ///< trapped by a conservative contact repeating forever (among `trapped`)
  std::int64_t stalled = 0;           ///< trapped by a guard before the time cap (Trajectory3::stalled; among `trapped`)
  std::int64_t capped = 0;            ///< ended by the collision cap inside the funnel (Trajectory3::capped; among `trapped`)
  std::int64_t total_collisions = 0;  ///< summed over the samples
  std::int64_t ode_steps = 0;         ///< integrator steps of the sustained contacts, summed
  std::vector<Sample3> per_sample;    ///< filled when keep_samples

  /// The statistics of one observable.
  const Summary& operator[](Observable o) const { return stats[static_cast<std::size_t>(o)]; }
};

/// Value of an observable (observables_3d()) for a 3D trajectory; NaN for an exit observable of
/// a trajectory that did not exit. exit_speed is |v|, exit_angle the angle of v from the downward
/// vertical in degrees (>= 0), exit_spin the spin about z.
double value(const Trajectory3& t, Observable o);

/// The release state of sample k of a 3D ensemble: at x = L * release_fraction(dist, k, N),
/// z = 0, with the parameters' release velocity and spin, and the random
/// horizontal velocity of sample k.
State3 ensemble_release_3d(const Params& params, const Cone& cone, const Ensemble3Options& options, std::int64_t k);

/// Runs the 3D ensemble of one parameter set. Bit-identical for any thread count.
Ensemble3Result run_ensemble_3d(const Params& params, const Ensemble3Options& options, const Progress& progress = {});

/// Called once per finished point with its index and result; from one thread at a time, in
/// completion order.
using PointDone3 = std::function<void(std::size_t, const Ensemble3Result&)>;

/// Runs one 3D ensemble per parameter set in one parallel pool; results in input order, each the
/// same, bit for bit, as run_ensemble_3d of that point alone.
std::vector<Ensemble3Result> run_sweep_3d(const std::vector<Params>& points, const Ensemble3Options& options,
                                          const Progress& progress = {}, const PointDone3& point_done = {});

/// The same with one velocity_sd per point (velocity_sds[i] for points[i], overriding
/// options.velocity_sd; the two vectors have the same size), so that ensembles differing in
/// their random velocities share one pool. Each result is the same, bit for bit.
std::vector<Ensemble3Result> run_sweep_3d(const std::vector<Params>& points, const std::vector<double>& velocity_sds,
                                          const Ensemble3Options& options, const Progress& progress = {},
                                          const PointDone3& point_done = {});

}  // namespace funnel
