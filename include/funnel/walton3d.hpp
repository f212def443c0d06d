// Walton's collision law in vector form, for the sphere in the axisymmetric funnel
// (docs/model.md §9).
#pragma once

#include "funnel/cone.hpp"
#include "funnel/vec3.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// Result of one collision in 3D: the state after and what the collision did.
struct Collision3 {
  State3 after;          ///< same position, new velocity and spin
  double p = 0.0;        ///< normal velocity before (< 0 when approaching), units sqrt(gH)
  Vec3 slip;             ///< tangential velocity of the contact point before, v - (v.n)n + omega x (-a n)
  double p_after = 0.0;  ///< normal velocity after, -e p
  double j_n = 0.0;      ///< normal impulse (1 + e)|p| >= 0, units m sqrt(gH)
  Vec3 j_t;              ///< tangential impulse (perpendicular to n), units m sqrt(gH)
  Regime regime = Regime::Sticking;  ///< Sliding (mu < mu_c) or Sticking
  double energy_lost = 0.0;          ///< kinetic energy lost (>= 0), units m g H
};

/// Applies Walton's law at a contact with unit normal n (from the contact point to the centre,
/// contact point at -a n). `across` is a unit tangent (perpendicular to n) that, with
/// `in_plane` = n x across, spans the tangent plane: the engine passes the azimuthal direction,
/// so that for a motion in a meridian plane with the spin normal to it the arithmetic is the 2D
/// law's (walton.hpp), bit for bit. The result does not depend on the choice beyond rounding:
///   p = v.n, s = v - p n - a omega x n, mu_c = (1 + beta0)|s| / ((1 + e)(1 + 1/kappa)|p|),
///   J_N = (1 + e)|p|, J_t = -mu J_N s/|s| (mu < mu_c) or -(1 + beta0) s/(1 + 1/kappa),
///   v' = v + J_N n + J_t, omega' = omega + (-a n) x J_t / (kappa a^2).
Collision3 collide(const State3& before, Vec3 n, Vec3 across, const CollisionConstants& k);

}  // namespace funnel
