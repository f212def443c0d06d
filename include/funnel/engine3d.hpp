// One trajectory of the sphere through the axisymmetric funnel in 3D, event by event
// (docs/model.md §9).
#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "funnel/cone.hpp"
#include "funnel/contact3d.hpp"
#include "funnel/engine.hpp"
#include "funnel/flight3d.hpp"
#include "funnel/params.hpp"

namespace funnel {

/// One entry of the optional event log of a 3D trajectory. Kinds as in 2D: `face` is the cone,
/// `edge` the rim.
struct Event3 {
  double time = 0.0;            ///< time of the event, units sqrt(H/g)
  EventKind kind = EventKind::Face;
  Vec3 position;                ///< centre position at the event
  Vec3 velocity_before;         ///< centre velocity just before
  Vec3 velocity_after;          ///< centre velocity just after
  Vec3 omega_before;            ///< spin vector just before
  Vec3 omega_after;             ///< spin vector just after
  Vec3 normal;                  ///< contact normal of a collision (towards the centre); 0 otherwise
  Vec3 slip_before;             ///< slip vector of a collision before it
  Regime regime = Regime::None; ///< collision regime, or the contact's regime at start/end
  double j_n = 0.0;             ///< normal impulse (a contact's end: integral of N dt), units m sqrt(gH)
  Vec3 j_t;                     ///< tangential impulse of a collision, units m sqrt(gH)
  Vec3 contact_impulse;         ///< a contact's end: integral of (N n + F) dt over the contact
  double energy_lost = 0.0;     ///< energy lost in this event (a contact's end: over the contact), units m g H
};

/// Receives the events of a 3D trajectory as they happen.
class EventSink3 {
 public:
  virtual ~EventSink3() = default;
  /// Called once per event, in time order.
  virtual void record(const Event3& event) = 0;
  /// Asked after every collision: true ends the run there.
  virtual bool finished() const { return false; }
  /// False for a sink that only decides when the run ends (finished()): the engine then builds
  /// and records no event for it.
  virtual bool records() const { return true; }
};

/// An EventSink3 that keeps every event.
class EventLog3 final : public EventSink3 {
 public:
  void record(const Event3& event) override { events.push_back(event); }
  std::vector<Event3> events;  ///< the events in time order
};

/// Observables of one 3D trajectory: those of 2D (engine.hpp) plus the turns about the axis.
struct Trajectory3 {
  Status status = Status::Trapped;
  double duration = 0.0;            ///< time of the exit (or of the end of the run), units sqrt(H/g)
  double impulse = 0.0;             ///< sum |J| over collisions + integral sqrt(N^2+|F|^2) dt over contacts
  double normal_impulse = 0.0;      ///< the same with J_N and N only
  double energy_loss = 0.0;         ///< E_0 - E_end from the states, units m g H
  double energy_loss_events = 0.0;  ///< sum of the losses of every event (bookkeeping check)
  std::int64_t collisions = 0;      ///< all collisions, face and rim
  std::int64_t edge_collisions = 0; ///< collisions with the rim (included in `collisions`)
  std::int64_t contacts = 0;        ///< sustained face contacts
  std::int64_t edge_contacts = 0;   ///< sustained rim contacts
  double contact_time = 0.0;        ///< total time in sustained contact
  double orbits = 0.0;              ///< net turns about the vertical axis (signed, right-handed about +y)
  std::int64_t ode_steps = 0;       ///< integrator steps of the sustained contacts (cost diagnostic)
  bool periodic = false;            ///< ended (trapped) by a conservative contact repeating forever
  bool stopped = false;             ///< ended early by EventSink3::finished() (status Trapped)
  /// Ended by a guard before the time cap (status Trapped): an integrated contact reached
  /// Params::max_ode_steps steps (the stick-slip of docs/robustness.md, finding 22) or 100 000
  /// phases, or 1000 events in a row took no time. The CLI warns of it; outputs say `stalled`.
  bool stalled = false;
  bool capped = false;              ///< ended by the collision cap max_collisions inside the funnel (status Trapped)
  State3 final_state;               ///< state when the run ended
  State3 exit_state;                ///< state at the exit level (status Exited only)
};

/// Runs one 3D trajectory from any admissible initial state (units H = g = m = 1).
Trajectory3 simulate_3d(const Params& params, const Cone& cone, const State3& initial, EventSink3* sink = nullptr);

/// simulate_3d of every initial state, out[i] from initial[i] (out.size() >= initial.size()): the
/// same trajectories, bit for bit, faster, as several run side by side (their flights' face
/// times are found together, cone_face_times). Once *cancel is set, it returns at the runs' next
/// event (the outputs of the runs not finished are left as they were).
void simulate_3d_many(const Params& params, const Cone& cone, std::span<const State3> initial,
                      std::span<Trajectory3> out, const std::atomic<bool>* cancel = nullptr);

/// The release state at x = fraction * L, z = 0 on the release plane (fraction in (-1, 1)), with
/// velocity (release_u, release_v, release_w) and spin (release_spin_x, release_spin_y,
/// release_spin): the 2D spin is the spin about z.
State3 release_state_3d(const Params& params, const Cone& cone, double fraction);

/// Runs one 3D trajectory from release_state_3d(params, cone, fraction).
Trajectory3 simulate_release_3d(const Params& params, const Cone& cone, double fraction, EventSink3* sink = nullptr);

/// "face_end", "rim_top", "take_off", "exit", "rest", "time_cap", "periodic".
std::string_view to_string(Contact3End end);

}  // namespace funnel
