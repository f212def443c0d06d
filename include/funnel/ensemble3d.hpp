// Ensembles of 3D trajectories in the axisymmetric funnel, with random horizontal release
// velocities from a counter-based generator: deterministic for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "funnel/engine3d.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/stats.hpp"

namespace funnel {

/// The random stream of the release velocities: sample k draws normal(seed, release_velocity_stream, k, 0)
/// for u and lane 1 for w.
inline constexpr std::uint64_t release_velocity_stream = 1;

/// How to run a 3D ensemble.
struct Ensemble3Options {
  std::int64_t samples = default_samples;  ///< N >= 1
  ReleaseDist dist = ReleaseDist::Disk;     ///< release distances from the axis (disk: uniform over the opening)
  double velocity_sd = 0.0;   ///< sigma of each horizontal release velocity component (u, w), units sqrt(gH), >= 0
  std::uint64_t seed = 0;     ///< seed of the random release velocities
  Release3 release;           ///< w and the spin about x and y added to every release
  int threads = 0;            ///< 0: all cores
  bool keep_samples = false;  ///< also return every trajectory (O(N) memory)
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
  Summary duration, impulse, normal_impulse, energy_loss, collisions, edge_collisions, contact_time;
  Summary orbits;  ///< of |net turns about the axis|
  Summary duration_exited, impulse_exited, energy_loss_exited;  ///< over the exited samples only
  std::int64_t exited = 0, rest = 0, trapped = 0;  ///< count of each status
  std::int64_t periodic = 0;          ///< trapped by a conservative contact repeating forever (among `trapped`)
  std::int64_t total_collisions = 0;  ///< summed over the samples
  std::int64_t ode_steps = 0;         ///< integrator steps of the sustained contacts, summed
  std::vector<Sample3> per_sample;    ///< filled when keep_samples
};

/// The release state of sample k of a 3D ensemble: at x = L * release_fraction(dist, k, N),
/// z = 0, with the parameters' release velocity and spin, options.release, and the random
/// horizontal velocity of sample k.
State3 ensemble_release_3d(const Params& params, const Cone& cone, const Ensemble3Options& options, std::int64_t k);

/// Runs the 3D ensemble of one parameter set. Bit-identical for any thread count.
Ensemble3Result run_ensemble_3d(const Params& params, const Ensemble3Options& options, const Progress& progress = {});

/// Runs one 3D ensemble per parameter set in one parallel pool; results in input order, each the
/// same, bit for bit, as run_ensemble_3d of that point alone.
std::vector<Ensemble3Result> run_sweep_3d(const std::vector<Params>& points, const Ensemble3Options& options,
                                          const Progress& progress = {});

}  // namespace funnel
