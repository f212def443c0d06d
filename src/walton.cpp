// Walton's three-parameter collision law (docs/model.md §4).
#include "funnel/walton.hpp"

#include <cmath>
#include <limits>

namespace funnel {

double critical_friction(double p, double slip, const Material& m) {
  const double denom = (1.0 + m.e) * (1.0 + 1.0 / m.kappa) * std::fabs(p);
  const double numer = (1.0 + m.beta0) * std::fabs(slip);
  if (denom == 0.0) return numer == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
  return numer / denom;
}

CollisionConstants collision_constants(const Material& m) {
  CollisionConstants k;
  k.e = m.e;
  k.mu = m.mu;
  k.one_plus_e = 1.0 + m.e;
  k.reduced = 1.0 + 1.0 / m.kappa;  // 1 + m a^2 / I
  k.slide_factor = m.mu * k.one_plus_e * k.reduced;
  k.one_plus_beta0 = 1.0 + m.beta0;
  k.kappa_a = m.kappa * m.radius;
  k.half_1_minus_e2 = 0.5 * (1.0 - m.e * m.e);
  k.half_reduced = 0.5 * k.reduced;
  k.radius = m.radius;
  return k;
}

Collision collide(const State& before, Vec2 n, const Material& m) { return collide(before, n, collision_constants(m)); }

Collision collide(const State& before, Vec2 n, const CollisionConstants& k) {
  // Every member is computed, and the result is built at once (no default-initialised object
  // filled in afterwards: on the hot path its zeroing was a visible cost).
  const Vec2 t{n.y, -n.x};
  const double p = dot(before.v, n);
  const double q = dot(before.v, t);
  const double slip = q + k.radius * before.omega;
  const double p_after = -k.e * p;                // Eq. (1)
  const double j_n = k.one_plus_e * std::fabs(p);  // Eq. (3)
  // mu < mu_c written without the division, so that p = 0 or beta0 = -1 need no special case.
  const bool sliding = k.slide_factor * std::fabs(p) < k.one_plus_beta0 * std::fabs(slip);
  const double j_t = sliding ? -k.mu * j_n * (slip > 0.0 ? 1.0 : -1.0)  // Eq. (6)
                             : -k.one_plus_beta0 * slip / k.reduced;      // Eq. (7): s' = -beta0 s
  const double q_after = q + j_t;  // Eq. (4)
  State after;
  after.r = before.r;
  after.v = p_after * n + q_after * t;
  after.omega = before.omega + j_t / k.kappa_a;  // Eq. (5)
  // Kinetic energy lost, in closed form: normal part plus the work of J_t on the slip.
  const double energy_lost = k.half_1_minus_e2 * p * p - j_t * slip - k.half_reduced * j_t * j_t;
  return Collision{after, p, q, slip, p_after, j_n, j_t, sliding ? Regime::Sliding : Regime::Sticking, energy_lost};
}

}  // namespace funnel
