// Walton's three-parameter collision law in vector form.
#include "funnel/walton3d.hpp"

#include <cmath>

namespace funnel {

Collision3 collide(const State3& before, Vec3 n, Vec3 across, const CollisionConstants& k) {
  Collision3 c;
  // Tangent basis: t1 = n x across (in the meridian plane: the 2D tangent (n_y, -n_x) up to
  // sign), t2 = across. With (t1, n, t2) right-handed, omega x n = omega_1 t2 - omega_2 t1.
  const Vec3 t2 = across;
  const Vec3 t1 = cross(n, t2);
  const Vec3& v = before.v;
  const Vec3& w = before.omega;
  c.p = dot(v, n);
  const double q1 = dot(v, t1), q2 = dot(v, t2);
  const double w1 = dot(w, t1), w2 = dot(w, t2);
  const double s1 = q1 + k.radius * w2;  // the 2D slip q + a omega along t1
  const double s2 = q2 - k.radius * w1;
  c.slip = s1 * t1 + s2 * t2;
  c.p_after = -k.e * c.p;                 // Eq. (1)
  c.j_n = k.one_plus_e * std::fabs(c.p);  // Eq. (3)
  const double slip = std::hypot(s1, s2);
  double j1, j2;
  // mu < mu_c without the division (p = 0 and beta0 = -1 need no special case), as in 2D.
  if (k.slide_factor * std::fabs(c.p) < k.one_plus_beta0 * slip) {
    c.regime = Regime::Sliding;
    const double jt = -k.mu * c.j_n;  // Eq. (6), along the slip
    j1 = jt * (s1 / slip);
    j2 = jt * (s2 / slip);
  } else {
    c.regime = Regime::Sticking;
    j1 = -k.one_plus_beta0 * s1 / k.reduced;  // Eq. (7): s' = -beta0 s
    j2 = -k.one_plus_beta0 * s2 / k.reduced;
  }
  c.j_t = j1 * t1 + j2 * t2;
  const double q1_after = q1 + j1, q2_after = q2 + j2;  // Eq. (4)
  c.after.r = before.r;
  c.after.v = c.p_after * n + q1_after * t1 + q2_after * t2;
  // Eq. (5) in vector form: (-a n) x J_t / (kappa a^2) = (j1 t2 - j2 t1) / (kappa a).
  c.after.omega = w + (j1 / k.kappa_a) * t2 - (j2 / k.kappa_a) * t1;
  // Kinetic energy lost in closed form: the normal part plus the work of J_t on the slip.
  c.energy_lost = k.half_1_minus_e2 * c.p * c.p - (j1 * s1 + j2 * s2) -
                  (k.half_reduced * j1 * j1 + k.half_reduced * j2 * j2);
  return c;
}

}  // namespace funnel
