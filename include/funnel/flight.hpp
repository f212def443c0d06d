// Free flight under gravity and detection of the next event (docs/model.md §3).
#pragma once

#include <array>
#include <cstdint>

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
/// An optional face or corner packed in one integer (none: -1). A FlightStart is built and read
/// on every collision: as five std::optional<WallPart> it was 60 bytes written byte by byte and
/// read back as wide words, and the failed store-to-load forwarding cost ~30% of a run's time.
class PartSlot {
 public:
  PartSlot() = default;
  PartSlot(WallPart p) : code_(code_of(p)) {}  // NOLINT(google-explicit-constructor): set from a part
  bool operator==(WallPart p) const { return code_ == code_of(p); }
  bool has_value() const { return code_ >= 0; }

 private:
  static std::int32_t code_of(WallPart p) { return 2 * p.index + (p.wall == Wall::Left ? 0 : 1); }
  std::int32_t code_ = -1;
};

struct FlightStart {
  PartSlot on_face;    ///< centre exactly on this face's centre line (after a face collision)
  PartSlot on_edge;    ///< centre exactly on this corner's edge circle (after an edge collision)
  PartSlot slow_edge;  ///< on_edge, and the normal speed it left is below p_c: taken as 0
  PartSlot skip_face;  ///< left this face tangentially at the end of its region: not hit again
  PartSlot skip_edge;  ///< left this corner's circle tangentially, curving away from it
};

/// The earliest event of a free flight.
struct NextEvent {
  EventKind kind = EventKind::Exit;  ///< Face, Edge or Exit
  WallPart part;                     ///< the face of a Face event, the corner of an Edge event
  bool sideways = false;             ///< Exit: under the higher lower end (Funnel::side_exit), not through the exit level
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

/// Time until the centre crosses, outward and below it, the vertical through the higher of two
/// unequal lower ends (Funnel::side_exit), or `never`.
double side_exit_time(const Funnel& f, const State& s);

/// The earliest of the face, edge and exit events (faces win ties with edges at C*).
NextEvent next_event(const Funnel& f, const State& s, const FlightStart& start);

namespace detail {

/// Cheap proofs that the edge quartic f(t) = |d + v t - (0, t^2/2)|^2 - a^2 of edge_time has no
/// root in (0, T]: fl(f) > 0 there, so first_descending_root would answer `never`. False when
/// the proof does not go through, not that there is a root.
///
/// clears_circle: for the quartic of d (the centre relative to the edge point) and v, with
/// c[0] = |d|^2 - a^2 and c[1] = 2 d.v, the flight stays farther than a from the point, by a
/// margin above the rounding of the quartic's coefficients and of its evaluation.
bool clears_circle(Vec2 d, Vec2 v, double T, double a);

/// moves_away_for_good: for a flight that starts on or outside the circle (c[0] >= 0, c[4] =
/// 1/4) and moves away from it (c[1] > 0), (f(t) - c[0]) / t stays positive, beyond rounding,
/// up to T (its Bernstein coefficients on [0, T]).
bool moves_away_for_good(const std::array<double, 5>& c, double T);

}  // namespace detail

}  // namespace funnel
