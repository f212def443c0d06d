// Audit of a trajectory's free flights, rebuilt from its event log: no flight may bring the
// sphere into a wall face or an edge, and every exit lies between the edges (docs/model.md §5b).
#pragma once

#include <cstdint>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/funnel.hpp"

namespace funnel {

/// What the free flights of one or more trajectories did near the walls.
struct FlightAudit {
  std::int64_t flights = 0;             ///< free flights checked
  std::int64_t edge_overlaps = 0;       ///< flights whose centre came closer than a (1 - tol) to an edge point
  std::int64_t face_crossings = 0;      ///< flights whose centre went behind a centre line where the face is
  std::int64_t exits_outside = 0;       ///< exits with the centre not between the edge circles
  std::int64_t missed_exits = 0;        ///< flights that left the funnel (through the exit level, or under a higher lower end) and went on
  std::int64_t trajectories = 0;        ///< trajectories audited
  std::int64_t trajectories_overlapping = 0;  ///< trajectories with at least one fault above
  double min_edge_distance = 0.0;       ///< smallest |centre - E| / a over every flight (1 = touching)
  double max_face_depth = 0.0;          ///< deepest centre behind a centre line, in units of a (>= 0)

  /// Adds another audit (counts add, extremes combine).
  void merge(const FlightAudit& other);
  /// True when nothing overlapped.
  bool clean() const { return edge_overlaps == 0 && face_crossings == 0 && exits_outside == 0 && missed_exits == 0; }
};

/// Relative tolerance of the audit: a distance of a (1 - 1e-9) to an edge point is still a touch.
inline constexpr double audit_tolerance = 1e-9;
/// Its absolute floor, per unit of the funnel's size (the largest of 1 H, its half width and
/// its heights): coordinates of that size carry a rounding of ~1e-16 of it that grazing flights
/// and long runs of bounces amplify to ~1e-13 .. 1e-12 of it, more than 1e-9 a for a particle
/// of a ~ 1e-6 (found by the fuzzer). For the paper's funnel and a >= 1e-3 the relative
/// tolerance is the larger.
inline constexpr double audit_floor = 1e-12;

/// The audit's relative tolerance for a particle of radius a in a funnel of the given size. At
/// an edge, a flight is also allowed the rounding of its own quartic, 16 eps ((|d| + |v| T +
/// T^2/2) / a)^2 (d from the edge point at its start, T its duration; at most 1e-3): the engine
/// cannot place the contact better (src/audit.cpp edge_conditioning; docs/robustness.md).
inline double audit_tolerance_for(double radius, double size = 1.0) {
  const double floor = audit_floor * (size > 1.0 ? size : 1.0) / radius;
  return audit_tolerance > floor ? audit_tolerance : floor;
}

/// The funnel's size for audit_tolerance_for: the largest of its half width plus the release
/// line's offset and the heights of its release line and exit (coordinates of that size carry
/// its rounding, whatever the particle).
double audit_size(const Funnel& f);

/// Rebuilds every free flight of a trajectory that started in `initial` from its event log and
/// checks it against the walls, the edges and the exit; the sustained contacts (between
/// contact_start/contact_end and edge_contact_start/edge_contact_end) are not flights.
FlightAudit audit_flights(const Funnel& f, const State& initial, const std::vector<Event>& events);

}  // namespace funnel
