// Sustained sliding/rolling contact with a wall face, solved in closed form (docs/model.md §5).
#pragma once

#include "funnel/funnel.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// One phase of constant acceleration of a sustained face contact, measured along the face.
struct FacePhase {
  double start = 0.0;     ///< centre's distance up the face from the lower end of its region at the start
  double speed = 0.0;     ///< down-slope speed at the start
  double accel = 0.0;     ///< down-slope acceleration
  double force = 0.0;     ///< friction force along the down-slope direction (per unit mass)
  double duration = 0.0;  ///< time spent in the phase
};

/// Outcome of a sustained contact that starts with zero normal velocity on a face.
struct ContactResult {
  State end;                  ///< state at the end: at the lower or the upper end of the face's region
  bool at_high_end = false;   ///< it ended at the upper end (moving up), else at the lower end
  bool at_rest = false;       ///< it came to rest on a level face (a ledge): `end` is where, at rest
  double duration = 0.0;      ///< time in contact
  double impulse = 0.0;       ///< integral of sqrt(N^2 + F^2) dt
  double normal_impulse = 0.0;///< integral of N dt, N = cos(angle of the face)
  double tangential_impulse = 0.0;  ///< integral of the friction force along the wall tangent t = (n_y, -n_x)
  double energy_lost = 0.0;   ///< work done against friction, >= 0
  Regime first_regime = Regime::Sliding;  ///< regime at the start (Sliding or Rolling)
  Regime last_regime = Regime::Sliding;   ///< regime at the end
  FacePhase phases[2];        ///< the phases in order (for the wear along the face)
  int phase_count = 0;        ///< number of phases used (1 or 2)
  bool slid = false;          ///< a sliding phase was run (even one of zero duration): the result depends on mu
};

/// Moves a particle in sustained contact with a face of the wall with mirror sign ws (normal
/// velocity already zero) to an end of the face's region, through at most two phases of
/// constant acceleration: sliding until the slip vanishes, then rolling if
/// tan(angle) <= mu (1 + kappa)/kappa, else sliding again. Down the face it ends at the lower
/// end; a particle moving up (handed over by an edge, or with back-spin) may reach the upper end
/// of a bounded region first, or turn and come back down. On a level face (a ledge) a particle
/// that stops, or rolls with zero speed, rests there for ever (at_rest).
ContactResult slide_on_face(const State& start, const Face& face, double ws, const Material& m);

}  // namespace funnel
