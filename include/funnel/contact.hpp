// Sustained sliding/rolling contact with a wall face, solved in closed form (docs/model.md §5).
#pragma once

#include "funnel/geometry.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// One phase of constant acceleration of a sustained face contact, measured along the face.
struct FacePhase {
  double start = 0.0;     ///< centre's distance up the face from the face's end (C*, or the vertex) at the start
  double speed = 0.0;     ///< down-slope speed at the start
  double accel = 0.0;     ///< down-slope acceleration
  double force = 0.0;     ///< friction force along the down-slope direction (per unit mass)
  double duration = 0.0;  ///< time spent in the phase
};

/// Outcome of a sustained contact that starts with zero normal velocity on a face.
struct ContactResult {
  State end;                  ///< state at the end: at C*, or at the vertex of a closed funnel
  double duration = 0.0;      ///< time in contact
  double impulse = 0.0;       ///< integral of sqrt(N^2 + F^2) dt
  double normal_impulse = 0.0;///< integral of N dt, N = cos(theta)
  double tangential_impulse = 0.0;  ///< integral of the friction force along the wall tangent t
  double energy_lost = 0.0;   ///< work done against friction, >= 0
  Regime first_regime = Regime::Sliding;  ///< regime at the start (Sliding or Rolling)
  Regime last_regime = Regime::Sliding;   ///< regime at the end
  FacePhase phases[2];        ///< the phases in order (for the wear along the face)
  int phase_count = 0;        ///< number of phases used (1 or 2)
};

/// Moves a particle in sustained contact with `wall` (normal velocity already zero) down to
/// the end of the face, through at most two phases of constant acceleration: sliding until the
/// slip vanishes, then rolling if tan(theta) <= mu (1 + kappa)/kappa, else sliding again. A
/// particle may start at the face's end moving up the face (handed over by its edge): it goes
/// up, turns and comes back down to the end.
ContactResult slide_to_end(const State& start, Wall wall, const Geometry& g, const Material& m);

}  // namespace funnel
