// Sustained contact with an edge point: the sphere rolls or slides around the corner until the
// normal force vanishes (docs/model.md §5b). Solved phase by phase from first integrals in the
// angle psi, with the elapsed time and the impulses by quadrature; no time stepping.
#pragma once

#include "funnel/geometry.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// An edge point and the arc of contact normals over which it acts. The normal of a contact is
/// n = (cos psi, sin psi) (from the edge point to the centre); beyond the arc's ends the wall's
/// faces take over.
struct EdgeArc {
  Vec2 point;             ///< the edge point E, units of H
  double psi_low = 0.0;   ///< smallest normal angle of the arc, radians
  double psi_high = 0.0;  ///< largest normal angle of the arc, radians (psi_low < psi_high)
};

/// How a sustained edge contact ended.
enum class EdgeExit {
  TakeOff,  ///< the normal force fell to zero: the particle flies on, tangent to the edge circle
  High,     ///< the centre reached the arc's upper end (psi_high): the face above takes over
  Low,      ///< the centre reached the arc's lower end (psi_low): the face below takes over
};

/// Outcome of a sustained edge contact.
struct EdgeContactResult {
  State end;                      ///< state at the end (on the circle of radius a about E)
  EdgeExit exit = EdgeExit::TakeOff;
  double duration = 0.0;          ///< time in contact, units sqrt(H/g)
  double impulse = 0.0;           ///< integral of sqrt(N^2 + F^2) dt, units m sqrt(gH)
  double normal_impulse = 0.0;    ///< integral of N dt
  double tangential_impulse = 0.0;///< integral of F dt along t = (n_y, -n_x)
  double energy_lost = 0.0;       ///< work done against friction (>= 0), units m g H
  Regime first_regime = Regime::Sliding;  ///< Sliding or Rolling at the start
  Regime last_regime = Regime::Sliding;   ///< at the end
  int phases = 0;                 ///< phases solved (rolling/sliding, split at turning points)
};

/// Normal force per unit mass that an edge contact would need now, N = n_y - |v|^2 / a, for a
/// centre at distance a from `point` moving tangentially; a contact holds only while N > 0.
double edge_normal_force(const State& s, Vec2 point, double radius);

/// Moves a particle in sustained contact with an edge (centre at distance a from arc.point,
/// velocity tangential to the circle, start angle inside the arc, edge_normal_force > 0) until
/// the normal force vanishes or the centre reaches an end of the arc.
EdgeContactResult edge_contact(const State& start, const EdgeArc& arc, const Material& m);

}  // namespace funnel
