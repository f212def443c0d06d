// Free flight under gravity and detection of the next event (docs/model.md §3).
#pragma once

#include <optional>

#include "funnel/geometry.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// What can happen to the particle; every event of a trajectory is one of these.
enum class EventKind { Face, Edge, ContactStart, ContactEnd, Exit, EdgeContactStart, EdgeContactEnd };

/// How the current flight began, so that the contact it left is not found again at t = 0.
struct FlightStart {
  std::optional<Wall> on_face;    ///< centre exactly on this wall's centre line (after a face collision)
  std::optional<Wall> on_edge;    ///< centre exactly on this wall's edge circle (after an edge collision)
  std::optional<Wall> slow_edge;  ///< on_edge, and the normal speed it left is below p_c: taken as 0
  std::optional<Wall> skip_face;  ///< left this wall's face tangentially at C*: it cannot be hit again
  std::optional<Wall> skip_edge;  ///< left this wall's edge circle tangentially, curving away from it
};

/// The earliest event of a free flight.
struct NextEvent {
  EventKind kind = EventKind::Exit;  ///< Face, Edge or Exit
  Wall wall = Wall::Left;            ///< wall of a Face or Edge event
  double dt = 0.0;                   ///< time until the event; `never` if nothing happens
};

/// Position, velocity and spin after a free flight of duration dt (gravity (0, -1)).
inline State advance(const State& s, double dt) {
  State out;
  out.r = {s.r.x + s.v.x * dt, s.r.y + s.v.y * dt - 0.5 * dt * dt};
  out.v = {s.v.x, s.v.y - dt};
  out.omega = s.omega;
  return out;
}

/// Time until the centre reaches a wall's centre line inside its face region, or `never`.
double face_time(const Geometry& g, const State& s, Wall wall, const FlightStart& start);

/// Time until the centre reaches a wall's edge circle on the edge arc, within (0, t_limit], or `never`.
double edge_time(const Geometry& g, const State& s, Wall wall, const FlightStart& start, double t_limit);

/// Time until the centre falls through the exit level y_b, or `never` for a closed funnel.
double exit_time(const Geometry& g, const State& s);

/// The earliest of the face, edge and exit events (faces win ties with edges at C*).
NextEvent next_event(const Geometry& g, const State& s, const FlightStart& start);

}  // namespace funnel
