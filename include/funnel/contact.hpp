// Sustained sliding/rolling contact with a wall face, solved in closed form (MODEL.md §5).
#pragma once

#include "funnel/geometry.hpp"
#include "funnel/walton.hpp"

namespace funnel {

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
};

/// Moves a particle in sustained contact with `wall` (normal velocity already zero) down to
/// the end of the face, through at most two phases of constant acceleration: sliding until the
/// slip vanishes, then rolling if tan(theta) <= mu (1 + kappa)/kappa, else sliding again.
ContactResult slide_to_end(const State& start, Wall wall, const Geometry& g, const Material& m);

}  // namespace funnel
