// Free flight under gravity and detection of the next event (docs/model.md §3).
#pragma once

#include <optional>

#include "funnel/funnel.hpp"
#include "funnel/geometry.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// What can happen to the particle; every event of a trajectory is one of these.
enum class EventKind { Face, Edge, ContactStart, ContactEnd, Exit, EdgeContactStart, EdgeContactEnd };

/// A face or a corner of one wall: the wall and the index of the face or corner.
struct WallPart {
  Wall wall = Wall::Left;
  int index = 0;
  bool operator==(const WallPart&) const = default;
};

/// How the current flight began, so that the contact it left is not found again at t = 0.
struct FlightStart {
  std::optional<WallPart> on_face;    ///< centre exactly on this face's centre line (after a face collision)
  std::optional<WallPart> on_edge;    ///< centre exactly on this corner's edge circle (after an edge collision)
  std::optional<WallPart> slow_edge;  ///< on_edge, and the normal speed it left is below p_c: taken as 0
  std::optional<WallPart> skip_face;  ///< left this face tangentially at the end of its region: not hit again
  std::optional<WallPart> skip_edge;  ///< left this corner's circle tangentially, curving away from it
};

/// The earliest event of a free flight.
struct NextEvent {
  EventKind kind = EventKind::Exit;  ///< Face, Edge or Exit
  WallPart part;                     ///< the face of a Face event, the corner of an Edge event
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

/// Time until the centre reaches a face's centre line inside the face's region, or `never`.
double face_time(const Funnel& f, const State& s, WallPart face, const FlightStart& start);

/// Time until the centre reaches a convex corner's edge circle on its arc, within (0, t_limit], or `never`.
double edge_time(const Funnel& f, const State& s, WallPart corner, const FlightStart& start, double t_limit);

/// Time until the centre crosses the outlet downward, or `never` for a closed funnel.
double exit_time(const Funnel& f, const State& s);

/// The earliest of the face, edge and exit events (faces win ties with edges at C*).
NextEvent next_event(const Funnel& f, const State& s, const FlightStart& start);

}  // namespace funnel
