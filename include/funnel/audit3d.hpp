// Audit of a 3D trajectory's free flights, rebuilt from its event log: no flight may bring the
// sphere into the cone face or the rim, and every exit lies inside the outlet.
#pragma once

#include <cstdint>
#include <vector>

#include "funnel/audit.hpp"
#include "funnel/cone.hpp"
#include "funnel/engine3d.hpp"

namespace funnel {

/// What the free flights of one or more 3D trajectories did near the funnel.
struct FlightAudit3 {
  std::int64_t flights = 0;                   ///< free flights checked
  std::int64_t rim_overlaps = 0;              ///< flights whose centre came closer than a (1 - tol) to the rim circle
  std::int64_t face_crossings = 0;            ///< flights whose centre went behind the centre cone where the face is
  std::int64_t exits_outside = 0;             ///< exits with the centre farther than R - a (1 - tol) from the axis
  std::int64_t trajectories = 0;              ///< trajectories audited
  std::int64_t trajectories_overlapping = 0;  ///< trajectories with at least one fault above
  double min_rim_distance = 0.0;  ///< smallest distance from the rim circle / a over every flight (1 = touching)
  double max_face_depth = 0.0;    ///< deepest centre behind the centre cone on the face, units of a (>= 0)

  /// Adds another audit (counts add, extremes combine).
  void merge(const FlightAudit3& other);
  /// True when nothing overlapped.
  bool clean() const { return rim_overlaps == 0 && face_crossings == 0 && exits_outside == 0; }
};

/// Rebuilds every free flight of a 3D trajectory that started in `initial` from its event log and
/// checks it against the cone face, the rim and the outlet (tolerance: audit_tolerance); the
/// sustained contacts are not flights.
FlightAudit3 audit_flights_3d(const Cone& cone, const State3& initial, const std::vector<Event3>& events);

}  // namespace funnel
