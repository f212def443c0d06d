// Long-time states of a closed funnel (docs/theory.md, paper Figs. 11 and 12).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "funnel/ensemble.hpp"
#include "funnel/params.hpp"

namespace funnel {

/// Where a trajectory in a closed funnel ends up.
enum class FinalState {
  Periodic,   ///< the period-2 orbit: alternating walls, no slip, equal collision heights
  Rest,       ///< the dead state: all energy lost, at the vertex
  Undecided,  ///< neither before the caps
};

/// "periodic", "rest", "undecided".
std::string_view to_string(FinalState state);

/// How a closed-funnel run is classified; every tolerance is relative.
struct ClosedOptions {
  double max_time = 1e4;                    ///< time cap per release, units sqrt(H/g)
  std::int64_t max_collisions = 10'000'000; ///< collision cap per release
  int window = 20;            ///< consecutive collisions that must pass the periodic test
  double slip_tol = 1e-6;     ///< |slip before| <= slip_tol * |velocity before|
  double height_tol = 1e-6;   ///< |y_k - y_(k-1)| <= height_tol * |y_k| (y_(k-2) if not mirror symmetric: OrbitTest)
};

/// Outcome for one release position.
struct ClosedSample {
  double fraction = 0.0;  ///< x0 / L
  FinalState state = FinalState::Undecided;
  double x_last = 0.0;    ///< x of the last collision (0 at rest; NaN if there was none)
  double x_prev = 0.0;    ///< x of the one before (0 at rest; NaN if there was none)
  double y_last = 0.0;    ///< heights of the same two collisions
  double y_prev = 0.0;
  std::int64_t collisions = 0;  ///< collisions simulated
  double time = 0.0;            ///< time simulated
  double energy = 0.0;          ///< energy above the vertex at the end
};

/// Runs one release in a closed funnel (the gap is forced to 0) and classifies its end.
ClosedSample classify_release(const Params& params, double fraction, const ClosedOptions& options);

/// Outcome over an ensemble of release positions.
struct ClosedResult {
  std::vector<ClosedSample> samples;  ///< in release order
  std::int64_t periodic = 0, rest = 0, undecided = 0;
  double periodic_fraction = 0.0;     ///< periodic / N
};

/// Classifies every release of an ensemble (in parallel; bit-identical for any thread count).
/// `progress`, if given, is called with (finished tasks, tasks), one thread at a time.
ClosedResult run_closed(const Params& params, const EnsembleOptions& ensemble, const ClosedOptions& options,
                        const Progress& progress = {});

}  // namespace funnel
