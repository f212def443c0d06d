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
  Collision c;
  const Vec2 t{n.y, -n.x};
  c.p = dot(before.v, n);
  c.q = dot(before.v, t);
  c.slip = c.q + k.radius * before.omega;
  c.p_after = -k.e * c.p;                   // Eq. (1)
  c.j_n = k.one_plus_e * std::fabs(c.p);    // Eq. (3)
  // mu < mu_c written without the division, so that p = 0 or beta0 = -1 need no special case.
  if (k.slide_factor * std::fabs(c.p) < k.one_plus_beta0 * std::fabs(c.slip)) {
    c.regime = Regime::Sliding;
    c.j_t = -k.mu * c.j_n * (c.slip > 0.0 ? 1.0 : -1.0);  // Eq. (6)
  } else {
    c.regime = Regime::Sticking;
    c.j_t = -k.one_plus_beta0 * c.slip / k.reduced;  // Eq. (7): s' = -beta0 s
  }
  const double q_after = c.q + c.j_t;  // Eq. (4)
  c.after.r = before.r;
  c.after.v = c.p_after * n + q_after * t;
  c.after.omega = before.omega + c.j_t / k.kappa_a;  // Eq. (5)
  // Kinetic energy lost, in closed form: normal part plus the work of J_t on the slip.
  c.energy_lost = k.half_1_minus_e2 * c.p * c.p - c.j_t * c.slip - k.half_reduced * c.j_t * c.j_t;
  return c;
}

}  // namespace funnel
