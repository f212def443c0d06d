// Free flight in the axisymmetric funnel and its next event: the cone face, the rim, the exit
// (docs/model.md §9).
#pragma once

#include <cstddef>
#include <span>

#include "funnel/cone.hpp"
#include "funnel/flight.hpp"

namespace funnel {

/// How the current flight began, so that the contact it left is not found again at t = 0.
struct FlightStart3 {
  bool on_face = false;    ///< centre exactly on the centre cone (after a face collision)
  bool on_rim = false;     ///< centre exactly at distance a from the rim circle (after a rim collision or contact)
  bool slow_rim = false;   ///< on_rim, and the normal speed it left is zero (tangential departure)
  bool skip_face = false;  ///< left the face tangentially at C*: the face cannot be hit again in this flight
};

/// The earliest event of a free flight: EventKind::Face (cone), Edge (rim) or Exit.
struct NextEvent3 {
  EventKind kind = EventKind::Exit;  ///< Face, Edge or Exit
  double dt = 0.0;                   ///< time until the event, units sqrt(H/g); `never` if nothing happens
};

/// Position, velocity and spin after a free flight of duration dt (gravity (0, -1, 0)).
inline State3 advance(const State3& s, double dt) {
  State3 out;
  out.r = {s.r.x + s.v.x * dt, s.r.y + s.v.y * dt - 0.5 * dt * dt, s.r.z + s.v.z * dt};
  out.v = {s.v.x, s.v.y - dt, s.v.z};
  out.omega = s.omega;
  return out;
}

/// Time until the centre reaches the centre cone on the face (above C*), or `never`. The
/// distance to the cone, cos(theta) y - sin(theta) rho, is concave in time; its descending root
/// is found as the fixed point of the roots of the distances to the face's generators (exactly
/// the 2D face time for a flight in a meridian plane).
double cone_face_time(const Cone& c, const State3& s, const FlightStart3& start);

/// The most flights cone_face_times takes at once.
inline constexpr std::size_t max_face_lanes = 16;

/// cone_face_time of up to max_face_lanes flights at once (out[i] for s[i], start[i]), the same
/// bits as one at a time, in less time: their fixed points run side by side.
void cone_face_times(const Cone& c, std::span<const State3> s, std::span<const FlightStart3> start,
                     std::span<double> out);

/// Time until the centre comes within a of the rim circle on the rim's arc (below C*), within
/// (0, t_limit], or `never`. Searched where the centre is in the rim's slab and annulus, as the
/// first descending root of the octic (|r - P|^2 - a^2)((rho + R)^2 + h^2 - a^2) in t.
double rim_time(const Cone& c, const State3& s, const FlightStart3& start, double t_limit);

/// Time until the centre falls through the outlet's level y_b, or `never` for a closed funnel.
double exit_time(const Cone& c, const State3& s);

/// The earliest of the face, rim and exit events (the face wins a tie with the rim at C*).
NextEvent3 next_event(const Cone& c, const State3& s, const FlightStart3& start);

/// next_event given the face time, cone_face_time(c, s, start), computed already.
NextEvent3 next_event(const Cone& c, const State3& s, const FlightStart3& start, double face_time);

namespace detail {
/// cone_face_time and cone_face_times with the fixed point's iteration cap (40 in the engine) as
/// a parameter: a low cap makes tests reach the bracketing fallback, which the engine's flights
/// seldom need (at most 32 iterations in an ensemble of 4000 balls at 60 degrees).
double cone_face_time(const Cone& c, const State3& s, const FlightStart3& start, int max_iterations);
void cone_face_times(const Cone& c, std::span<const State3> s, std::span<const FlightStart3> start,
                     std::span<double> out, int max_iterations);
}  // namespace detail

}  // namespace funnel
