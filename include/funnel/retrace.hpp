// Self-retracing orbits of an elastic frictionless particle (mu = 0, e = 1): search, period, stability.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "funnel/engine.hpp"
#include "funnel/params.hpp"

// With mu = 0 and e = 1 the motion is time-reversible. A particle released at rest that, after k
// collisions, hits a wall perpendicularly (a "wall turn") bounces straight back, retraces its path
// and comes to rest at the release point: a periodic orbit of period 2 T_k that never leaves the
// funnel. A particle whose velocity after its k-th collision is vertical and upward (a "rest turn")
// rises to rest at a second point of the release height and retraces from there. These are the only
// two ways a periodic orbit can pass through a release at rest (docs/theory.md, "Self-retracing
// orbits"). Everything is computed with the engine (funnel::simulate) in the funnel of the given
// parameters; only e and mu are overridden (frictionless() below). Units: H = g = m = 1.
namespace funnel::retrace {

/// How an orbit turns back.
enum class Turn {
  Wall,  ///< perpendicular hit on a wall at collision k; 2k - 1 collisions per period
  Rest,  ///< vertical rise after collision k to a second rest point; 2k collisions per period
};

/// "wall" or "rest".
std::string_view to_string(Turn turn);

/// How the release line is searched.
struct Options {
  int max_bounces = 6;          ///< K: collisions up to the turn, 1 <= K <= 20
  int scan_points = 2000;       ///< grid points on the half line x0/L in (-1, 0), >= 16
  bool rest_turns = false;      ///< also find orbits that turn at a second rest point
  double accept_angle = 1e-8;   ///< a refined root counts if its turn angle is below this, radians
  double repeat_angle = 1e-6;   ///< an earlier turn below this angle marks a repetition, radians
  int threads = 0;              ///< scan(): worker threads, 0 = all cores
  /// scan(): once set, the angles not yet begun are skipped (Ctrl-C in Python); the result is
  /// then incomplete and discarded.
  const std::atomic<bool>* cancel = nullptr;
  /// scan(): called with (angles finished, angles), one thread at a time, if given.
  std::function<void(std::int64_t, std::int64_t)> progress;
};

/// One self-retracing orbit in one funnel.
struct Orbit {
  double theta = 0.0;           ///< wall angle, degrees
  double release = 0.0;         ///< x0/L in (-1, 1); the mirror release -x0/L is the mirror orbit
  double y0 = 0.0;              ///< release height above the origin (where the centre lines meet), units H
  std::string sequence;         ///< walls of collisions 1..k, 'L' or 'R', e.g. "LRL"
  Turn turn = Turn::Wall;       ///< how it turns back
  int bounces = 0;              ///< k, collisions up to and including the turn
  int collisions_per_period = 0;///< 2k - 1 (wall turn) or 2k (rest turn)
  double period = 0.0;          ///< time to return to rest at the release point, units sqrt(H/g)
  double turn_x = 0.0;          ///< x/L of the turn: the perpendicular hit, or the second rest point
  double trace = 0.0;           ///< trace of the reduced monodromy (monodromy()), dimensionless
  bool stable = false;          ///< |trace| < 2 - parabolic_margin: elliptic, linearly (neutrally) stable
  double min_height = 0.0;      ///< lowest collision height above the origin, units H
  double residual = 0.0;        ///< |turn angle| left at the refined release, radians
};

/// |trace| within this of 2 is parabolic (marginal), not stable: e.g. every orbit at exactly 45 degrees.
inline constexpr double parabolic_margin = 1e-9;

/// The parameters with e = 1 and mu = 0 (beta0 and the inertia then play no role: no spin).
Params frictionless(const Params& params);

/// Every self-retracing orbit with k <= K at params.theta, releases x0/L in (-1, 1), sorted by k,
/// then release. Roots of the turn angle are bracketed on a grid of x0/L per collision sequence and
/// refined to the last bits; repetitions of a shorter orbit are left out. params must be valid.
std::vector<Orbit> find_orbits(const Params& params, const Options& options = {});

/// find_orbits at every angle of `thetas` (degrees), in parallel; bit-identical for any thread count.
/// Results are ordered by the angles' order, then as find_orbits.
std::vector<Orbit> scan(const Params& params, const std::vector<double>& thetas, const Options& options = {});

/// The engine's collisions of one period plus the first of the next (face events only), from rest at the release.
std::vector<Event> period_collisions(const Params& params, const Orbit& orbit);

/// Jacobian d(s', q')/d(s, q) of one collision-to-collision map on the energy surface, in Birkhoff
/// coordinates: s = distance of the centre from the origin along the centre line, q = velocity
/// component up the wall. `from` is the earlier collision (its state after), `to` the next one
/// (its state before, and its time). Area-preserving: det = 1.
Eigen::Matrix2d collision_map_jacobian(const Params& params, const Event& from, const Event& to);

/// Reduced monodromy: the product of the collision_map_jacobian of one period, from the first
/// collision back to it, at the engine's own states. det = 1; stable when |trace| < 2.
Eigen::Matrix2d monodromy(const Params& params, const Orbit& orbit);

/// The same by central finite differences of the engine itself, relative step `step` of (s, q).
Eigen::Matrix2d monodromy_fd(const Params& params, const Orbit& orbit, double step = 1e-7);

/// How far the engine, run from rest at the release for one period, ends from rest there.
struct ReturnCheck {
  double position_error = 0.0;  ///< |r(T) - r(0)|, units H
  double speed = 0.0;           ///< |v(T)|, units sqrt(gH)
  std::int64_t collisions = 0;  ///< collisions in the period
  bool left = false;            ///< exited, rested or hit an edge on the way
};

/// Runs the engine (the parameters' funnel, e = 1, mu = 0) from rest at the release for one period.
ReturnCheck check_return(const Params& params, const Orbit& orbit);

/// The same orbit in another funnel of the same angle (e.g. the open funnel of Fig. 2): the release
/// x0/L is re-refined there and the orbit checked; nullopt if it does not exist there (it would pass
/// below the end of the faces, where the open funnel has its edges and exit).
std::optional<Orbit> transfer(const Orbit& orbit, const Params& target, const Options& options = {});

/// A range of funnel angles on a grid where an orbit family exists, or exists and is stable.
struct Window {
  std::string sequence;     ///< canonical sequence (first collision on the left wall); the mirror is the same orbit
  Turn turn = Turn::Wall;
  bool stable = false;      ///< true: the orbit is stable over the range; false: it exists there
  double theta_from = 0.0;  ///< first grid angle of the range, degrees
  double theta_to = 0.0;    ///< last grid angle of the range, degrees
  int points = 0;           ///< grid angles in the range
};

/// Existence and stability windows of each family (sequence and turn) over the grid `thetas`
/// (ascending): maximal runs of consecutive grid angles. Sorted by bounces, sequence, then angle.
std::vector<Window> windows(const std::vector<Orbit>& orbits, const std::vector<double>& thetas);

namespace detail {

/// std::atan2(y, x) < 0, without calling atan2 where y's sign decides it (the scan for orbits
/// compares most turn angles by sign only).
bool atan2_negative(double y, double x);

}  // namespace detail

}  // namespace funnel::retrace
