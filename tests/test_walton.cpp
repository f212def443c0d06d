// Walton's collision law against hand-computed values and the paper's energy formulas.
#include "funnel/walton.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

// Left wall at theta = 30 degrees: n = (sin, cos), t = (cos, -sin).
constexpr double kTheta = 30.0 * 3.14159265358979323846 / 180.0;
const Vec2 kNormal{std::sin(kTheta), std::cos(kTheta)};
const Vec2 kTangent{std::cos(kTheta), -std::sin(kTheta)};

State incoming(double p, double q, double omega) {
  State s;
  s.v = p * kNormal + q * kTangent;
  s.omega = omega;
  return s;
}

// The paper's energy losses Delta E1 (sliding) and Delta E2 (sticking), with m = 1, I = kappa a^2.
double paper_delta_e1(double p, double q, double omega, const Material& m) {
  const double s = q + m.radius * omega;
  const double mu_c = critical_friction(p, s, m);
  return 0.5 * (1 - m.e * m.e) * p * p +
         0.5 * m.mu * (1 + m.e) * std::fabs(p * s) * (2 - m.mu * (1 + m.beta0) / mu_c);
}
double paper_delta_e2(double p, double q, double omega, const Material& m) {
  const double s = q + m.radius * omega;
  const double inertia = m.kappa * m.radius * m.radius;
  return 0.5 * (1 - m.e * m.e) * p * p +
         0.5 * inertia * (1 - m.beta0 * m.beta0) / (inertia + m.radius * m.radius) * s * s;
}

TEST(Walton, SlidingBranchMatchesHandComputedValues) {
  // p = -2, q = 1, omega = 0, a = 0.1, e = 0.5, beta0 = 0, kappa = 0.4:
  // mu_c = 1 / (1.5 * 3.5 * 2) = 0.0952, so mu = 0.05 slides.
  const Material m{0.5, 0.05, 0.0, 0.4, 0.1};
  const Collision c = collide(incoming(-2.0, 1.0, 0.0), kNormal, m);
  EXPECT_EQ(c.regime, Regime::Sliding);
  EXPECT_TRUE(near(c.p_after, 1.0, 1e-15));
  EXPECT_TRUE(near(c.j_n, 3.0, 1e-15));
  EXPECT_TRUE(near(c.j_t, -0.15, 1e-15));                       // -mu (1+e)|p| sign(s)
  EXPECT_TRUE(near(dot(c.after.v, kTangent), 0.85, 1e-15));     // Eq. (8)
  EXPECT_TRUE(near(c.after.omega, -0.15 / (0.4 * 0.1), 1e-15)); // Eq. (9): -3.75
  EXPECT_TRUE(near(dot(c.after.v, kNormal), 1.0, 1e-15));
}

TEST(Walton, StickingBranchMatchesPaperEquations10And11) {
  // p = -1, q = 0.5, omega = 2, a = 0.1, e = 0.9, mu = 1, beta0 = 0.31, kappa = 0.4.
  const Material m{0.9, 1.0, 0.31, 0.4, 0.1};
  const double q = 0.5, omega = 2.0, a = 0.1, kappa = 0.4, beta0 = 0.31;
  const Collision c = collide(incoming(-1.0, q, omega), kNormal, m);
  EXPECT_EQ(c.regime, Regime::Sticking);
  const double big_i = kappa * a * a;
  const double q_after = (a * a - big_i * beta0) / (big_i + a * a) * q - big_i * a / (big_i + a * a) * (1 + beta0) * omega;
  const double w_after = -a * (1 + beta0) / (big_i + a * a) * q + (big_i - a * a * beta0) / (big_i + a * a) * omega;
  EXPECT_TRUE(near(dot(c.after.v, kTangent), q_after, 1e-14));
  EXPECT_TRUE(near(c.after.omega, w_after, 1e-14));
  // Hand values: s = 0.7, J_t = -1.31 * 0.7 / 3.5 = -0.262, q' = 0.238, omega' = 2 - 6.55 = -4.55.
  EXPECT_TRUE(near(c.j_t, -0.262, 1e-14));
  EXPECT_TRUE(near(q_after, 0.238, 1e-14));
  EXPECT_TRUE(near(w_after, -4.55, 1e-14));
  // Eq. (7): the slip is reversed and scaled by beta0.
  EXPECT_TRUE(near(dot(c.after.v, kTangent) + a * c.after.omega, -beta0 * 0.7, 1e-14));
}

TEST(Walton, EnergyLossEqualsPaperDeltaE1AndDeltaE2) {
  for (const double mu : {0.01, 0.1, 0.3, 1.0, 10.0}) {
    for (const double beta0 : {-0.31, 0.0, 0.31, 0.9}) {
      const Material m{0.8, mu, beta0, 0.4, 0.02};
      const double p = -1.3, q = 0.7, omega = -11.0;
      const State before = incoming(p, q, omega);
      const Collision c = collide(before, kNormal, m);
      const double from_states = energy(before, m.kappa, m.radius) - energy(c.after, m.kappa, m.radius);
      const double paper = c.regime == Regime::Sliding ? paper_delta_e1(p, q, omega, m) : paper_delta_e2(p, q, omega, m);
      EXPECT_TRUE(near(c.energy_lost, paper, 1e-13)) << "mu " << mu << " beta0 " << beta0;
      EXPECT_TRUE(near(c.energy_lost, from_states, 1e-12));
      EXPECT_GE(c.energy_lost, 0.0);
    }
  }
}

TEST(Walton, LossIsContinuousAtCriticalFriction) {
  const Material base{0.7, 0.0, 0.2, 0.4, 0.05};
  const double p = -0.9, q = 0.4, omega = 3.0;
  const double mu_c = critical_friction(p, q + base.radius * omega, base);
  Material at = base;
  at.mu = mu_c;
  // Delta E1 and Delta E2 coincide at mu = mu_c.
  EXPECT_TRUE(near(paper_delta_e1(p, q, omega, at), paper_delta_e2(p, q, omega, at), 1e-14));
  Material below = at, above = at;
  below.mu = std::nextafter(mu_c, 0.0);
  above.mu = std::nextafter(mu_c, 1.0);
  const Collision cb = collide(incoming(p, q, omega), kNormal, below);
  const Collision ca = collide(incoming(p, q, omega), kNormal, above);
  EXPECT_EQ(cb.regime, Regime::Sliding);
  EXPECT_EQ(ca.regime, Regime::Sticking);
  EXPECT_TRUE(near(cb.energy_lost, ca.energy_lost, 1e-13));
  EXPECT_TRUE(near(cb.after.omega, ca.after.omega, 1e-13));
}

TEST(Walton, ElasticCollisionConservesEnergyWithoutSlipOrWithFullTangentialRestitution) {
  // e = 1 and s = 0: no loss whatever mu.
  for (const double mu : {0.0, 0.5, 100.0}) {
    const Material m{1.0, mu, 0.3, 0.4, 0.01};
    const State before = incoming(-1.0, 0.25, -25.0);  // s = 0.25 - 0.01 * 25 = 0
    const Collision c = collide(before, kNormal, m);
    EXPECT_NEAR(c.energy_lost, 0.0, 1e-15);
    EXPECT_TRUE(near(energy(c.after, m.kappa, m.radius), energy(before, m.kappa, m.radius), 1e-15));
  }
  // e = 1 and |beta0| = 1 with a sticking collision: no loss either.
  for (const double beta0 : {-1.0, 1.0}) {
    const Material m{1.0, 1000.0, beta0, 0.4, 0.01};
    const State before = incoming(-1.0, 0.6, 7.0);
    const Collision c = collide(before, kNormal, m);
    EXPECT_EQ(c.regime, Regime::Sticking);
    EXPECT_TRUE(near(energy(c.after, m.kappa, m.radius), energy(before, m.kappa, m.radius), 1e-15));
  }
}

TEST(Walton, FrictionlessCollisionLeavesTangentialVelocityAndSpinUnchanged) {
  const Material m{0.9, 0.0, 0.31, 0.4, 0.01};
  const State before = incoming(-1.0, 0.6, 7.0);
  const Collision c = collide(before, kNormal, m);
  EXPECT_EQ(dot(c.after.v, kTangent), dot(before.v, kTangent));
  EXPECT_EQ(c.after.omega, before.omega);
  EXPECT_TRUE(near(dot(c.after.v, kNormal), 0.9, 1e-15));
}

TEST(Walton, RightWallIsTheMirrorImageOfTheLeftWall) {
  const Material m{0.95, 0.3, 0.1, 0.4, 0.01};
  const Vec2 n_right{-kNormal.x, kNormal.y};
  State left = incoming(-0.8, 0.3, 5.0);
  State right = left;
  right.v.x = -left.v.x;
  right.omega = -left.omega;
  const Collision cl = collide(left, kNormal, m);
  const Collision cr = collide(right, n_right, m);
  EXPECT_EQ(cr.after.v.x, -cl.after.v.x);
  EXPECT_EQ(cr.after.v.y, cl.after.v.y);
  EXPECT_EQ(cr.after.omega, -cl.after.omega);
  EXPECT_EQ(cr.energy_lost, cl.energy_lost);
}

}  // namespace
}  // namespace funnel
