// Walton's collision law for a sphere hitting a wall or an edge (docs/model.md §4, paper Eqs. 1-11).
#pragma once

#include <cmath>
#include <limits>

#include "funnel/geometry.hpp"

namespace funnel {

/// Kinematic state of the particle: centre position, velocity and counter-clockwise spin.
struct State {
  Vec2 r;              ///< centre position
  Vec2 v;              ///< centre velocity
  double omega = 0.0;  ///< angular velocity, counter-clockwise positive
};

/// Total mechanical energy (u^2 + v^2)/2 + kappa a^2 omega^2/2 + y, units m g H.
inline double energy(const State& s, double kappa, double radius) {
  return 0.5 * dot(s.v, s.v) + 0.5 * kappa * radius * radius * s.omega * s.omega + s.r.y;
}

/// The energy_loss observable, E_0 - E_end (2D and 3D): a loss within rounding of zero below it
/// (64 eps of the larger energy's size: an elastic run) is reported as 0, not -2e-16.
inline double reported_energy_loss(double e0, double e_end) {
  const double loss = e0 - e_end;
  const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * std::fmax(std::fabs(e0), std::fabs(e_end));
  return loss < 0.0 && loss > -rounding ? 0.0 : loss;
}

/// Regime of a collision or of a phase of sustained contact.
enum class Regime { None, Sliding, Sticking, Rolling };

/// Material constants of a collision.
struct Material {
  double e = 0.99;       ///< normal restitution
  double mu = 1.0;       ///< friction coefficient
  double beta0 = 0.0;    ///< maximum tangential restitution
  double kappa = 0.4;    ///< I / (m a^2)
  double radius = 0.01;  ///< a
};

/// Material constants of a parameter set.
inline Material material(const Params& p) { return {p.e, p.mu, p.beta0, p.inertia, p.radius}; }

/// Result of one collision: the state after and what the collision did.
struct Collision {
  State after;          ///< same position, new velocity and spin
  double p = 0.0;       ///< normal velocity before (< 0 when approaching)
  double q = 0.0;       ///< tangential velocity before, along t = (n_y, -n_x)
  double slip = 0.0;    ///< s = q + a omega, tangential velocity of the contact point before
  double p_after = 0.0; ///< normal velocity after, -e p
  double j_n = 0.0;     ///< normal impulse (1 + e)|p|, >= 0
  double j_t = 0.0;     ///< tangential impulse along t
  Regime regime = Regime::Sticking;  ///< Sliding (mu < mu_c) or Sticking
  double energy_lost = 0.0;          ///< kinetic energy lost, >= 0 (paper's Delta E1 or Delta E2)
};

/// Constants of the collision law derived once from a Material; every value is the same
/// expression the law would otherwise evaluate per collision, so results are bit-identical.
struct CollisionConstants {
  double e = 0.0;              ///< normal restitution
  double mu = 0.0;             ///< friction coefficient
  double one_plus_e = 0.0;     ///< 1 + e
  double reduced = 0.0;        ///< 1 + 1/kappa = 1 + m a^2 / I
  double slide_factor = 0.0;   ///< mu (1 + e)(1 + 1/kappa): mu < mu_c iff slide_factor |p| < (1 + beta0)|s|
  double one_plus_beta0 = 0.0; ///< 1 + beta0
  double kappa_a = 0.0;        ///< kappa a
  double half_1_minus_e2 = 0.0;///< (1 - e^2)/2
  double half_reduced = 0.0;   ///< (1 + 1/kappa)/2
  double radius = 0.0;         ///< a
};

/// The constants of a material.
CollisionConstants collision_constants(const Material& m);

/// Applies Walton's law at a contact with unit normal n (from the contact point to the centre).
Collision collide(const State& before, Vec2 n, const Material& m);

/// The same with precomputed constants (the engine's hot path).
Collision collide(const State& before, Vec2 n, const CollisionConstants& k);

/// Critical friction mu_c of a collision (paper, after Eq. 7); infinite when p = 0 and s != 0.
double critical_friction(double p, double slip, const Material& m);

}  // namespace funnel
