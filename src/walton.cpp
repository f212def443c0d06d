// Walton's three-parameter collision law (MODEL.md §4).
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

Collision collide(const State& before, Vec2 n, const Material& m) {
  Collision c;
  const Vec2 t{n.y, -n.x};
  c.p = dot(before.v, n);
  c.q = dot(before.v, t);
  c.slip = c.q + m.radius * before.omega;
  c.p_after = -m.e * c.p;                       // Eq. (1)
  c.j_n = (1.0 + m.e) * std::fabs(c.p);         // Eq. (3)
  const double reduced = 1.0 + 1.0 / m.kappa;   // 1 + m a^2 / I
  // mu < mu_c written without the division, so that p = 0 or beta0 = -1 need no special case.
  if (m.mu * (1.0 + m.e) * reduced * std::fabs(c.p) < (1.0 + m.beta0) * std::fabs(c.slip)) {
    c.regime = Regime::Sliding;
    c.j_t = -m.mu * c.j_n * (c.slip > 0.0 ? 1.0 : -1.0);  // Eq. (6)
  } else {
    c.regime = Regime::Sticking;
    c.j_t = -(1.0 + m.beta0) * c.slip / reduced;  // Eq. (7): s' = -beta0 s
  }
  const double q_after = c.q + c.j_t;                          // Eq. (4)
  c.after.r = before.r;
  c.after.v = c.p_after * n + q_after * t;
  c.after.omega = before.omega + c.j_t / (m.kappa * m.radius);  // Eq. (5)
  // Kinetic energy lost, in closed form: normal part plus the work of J_t on the slip.
  c.energy_lost = 0.5 * (1.0 - m.e * m.e) * c.p * c.p - c.j_t * c.slip - 0.5 * reduced * c.j_t * c.j_t;
  return c;
}

}  // namespace funnel
