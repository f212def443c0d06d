// One trajectory of the particle through the funnel, event by event (docs/model.md §3-7).
#pragma once

#include <cstdint>
#include <optional>
#include <atomic>
#include <span>
#include <string_view>
#include <vector>

#include "funnel/flight.hpp"
#include "funnel/funnel.hpp"
#include "funnel/geometry.hpp"
#include "funnel/params.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// How a trajectory ended (docs/model.md §6).
enum class Status { Exited, Rest, Trapped };

/// Lower-case names used in every output: "exited", "rest", "trapped".
std::string_view to_string(Status status);
/// "face", "edge", "contact_start", "contact_end", "exit", "edge_contact_start", "edge_contact_end".
std::string_view to_string(EventKind kind);
/// "left", "right".
std::string_view to_string(Wall wall);
/// "none", "sliding", "sticking", "rolling".
std::string_view to_string(Regime regime);

/// One entry of the optional event log (docs/model.md §7).
struct Event {
  double time = 0.0;          ///< time of the event, units sqrt(H/g)
  EventKind kind = EventKind::Face;
  std::optional<Wall> wall;   ///< wall of a collision or contact; none for the exit
  Vec2 position;              ///< centre position at the event
  Vec2 velocity_before;       ///< centre velocity just before
  double omega_before = 0.0;  ///< spin just before
  Vec2 velocity_after;        ///< centre velocity just after
  double omega_after = 0.0;   ///< spin just after
  double slip_before = 0.0;   ///< tangential velocity of the contact point before (collisions)
  Regime regime = Regime::None;  ///< collision regime, or the contact's regime at start/end
  double j_n = 0.0;           ///< normal impulse (for a contact's end: integral of N dt)
  double j_t = 0.0;           ///< tangential impulse along t = (n_y, -n_x) (a contact's end: integral of F dt)
  double energy_lost = 0.0;   ///< energy lost in this event (a contact's end: over the whole contact)
};

/// Receives the events of a trajectory as they happen.
class EventSink {
 public:
  virtual ~EventSink() = default;
  /// Called once per event, in time order.
  virtual void record(const Event& event) = 0;
  /// Asked after every collision: true ends the run there (e.g. once an orbit is recognised).
  virtual bool finished() const { return false; }
  /// False for a sink that only decides when the run ends (finished()): the engine then builds
  /// and records no event for it.
  virtual bool records() const { return true; }
};

/// An EventSink that keeps every event.
class EventLog final : public EventSink {
 public:
  void record(const Event& event) override { events.push_back(event); }
  std::vector<Event> events;  ///< the events in time order
};

/// Observables of one trajectory (docs/model.md §7).
struct Trajectory {
  Status status = Status::Trapped;
  double duration = 0.0;            ///< time of the exit (or of the end of the run)
  double impulse = 0.0;             ///< sum |J| over collisions + integral sqrt(N^2+F^2) dt over contacts
  double normal_impulse = 0.0;      ///< the same with J_N and N only
  double energy_loss = 0.0;         ///< E_0 - E_end from the states
  double energy_loss_events = 0.0;  ///< sum of the losses of every event (bookkeeping check)
  std::int64_t collisions = 0;      ///< all collisions, face and edge
  std::int64_t edge_collisions = 0; ///< collisions with an edge (included in `collisions`)
  std::int64_t contacts = 0;        ///< sustained face contacts
  std::int64_t edge_contacts = 0;   ///< sustained edge contacts (rolling or sliding over a corner)
  double contact_time = 0.0;        ///< total time in sustained contact, faces and edges
  bool stopped = false;             ///< ended early by EventSink::finished() (status Trapped)
  bool stalled = false;             ///< ended by the Zeno guard in an open funnel (status Trapped); never expected
  bool capped = false;              ///< ended by the collision cap max_collisions inside the funnel (status Trapped)
  /// Friction reached its Coulomb limit somewhere (a sliding collision or a sliding phase of a
  /// face contact), or the run had an edge contact: the run may depend on mu. When false, the
  /// same release gives this very trajectory, bit for bit, for every larger mu (docs/model.md
  /// §4): sweeps over mu reuse it instead of running it again.
  bool slid = false;
  State final_state;                ///< state when the run ended
  State exit_state;                 ///< state at the exit: on the exit level or under a higher end passed sideways (status Exited only)
};

struct Wear;

/// Runs one trajectory in the funnel `f` (made by make_funnel(params)) from any admissible
/// initial state (units H = g = m = 1). With `wear` (made by Wear::make for this funnel), its
/// collisions and contacts are also binned there.
Trajectory simulate(const Params& params, const Funnel& f, const State& initial, EventSink* sink = nullptr,
                    Wear* wear = nullptr);

/// The same, building the funnel from the parameters (the Geometry argument is not used; kept for
/// callers of the paper's V).
Trajectory simulate(const Params& params, const Geometry& g, const State& initial, EventSink* sink = nullptr,
                    Wear* wear = nullptr);

/// Runs the trajectories from each initial state: out[k] is simulate(params, f, initial[k]), bit
/// for bit. The trajectories run together in the lanes of a SIMD vector (funnel/simd.hpp) while
/// they bounce between the walls' top faces above every edge, in a V (open or closed, with or
/// without a spout) or a profile whose corners are all edges; those of any other funnel run one
/// at a time. out.size() >= initial.size().
/// Returns how many of the collisions were computed in SIMD lanes (0 on the scalar path). Once
/// `cancel` (if given) is true the runs stop where they are and `out` is incomplete (Ctrl-C in
/// Python: the caller then discards it).
std::int64_t simulate_many(const Params& params, const Funnel& f, std::span<const State> initial,
                           std::span<Trajectory> out, const std::atomic<bool>* cancel = nullptr);

/// The release state at X = fraction on the release line (fraction in (-1, 1)), with the
/// parameters' release velocity and spin.
State release_state(const Params& params, const Funnel& f, double fraction);
State release_state(const Params& params, const Geometry& g, double fraction);

/// Runs one trajectory from release_state(params, f, fraction).
Trajectory simulate_release(const Params& params, const Funnel& f, double fraction, EventSink* sink = nullptr,
                            Wear* wear = nullptr);
Trajectory simulate_release(const Params& params, const Geometry& g, double fraction, EventSink* sink = nullptr,
                            Wear* wear = nullptr);

/// Number of consecutive events without any advance of time after which a run is stopped as
/// `trapped`: a guard against Zeno loops that no valid trajectory should ever reach.
inline constexpr int max_stalled_events = 1000;

/// At a concave corner of one wall, collisions without any advance of time whose kinetic energy
/// (with the spin's) falls at each one are a collapse into the corner, not a Zeno loop: they do
/// not count towards max_stalled_events, up to this many in a row (docs/model.md §3).
inline constexpr int max_corner_pile_up = 1000000;

}  // namespace funnel
