// Walton's law in vector form: the 2D law in a meridian plane, invariances and conservation.
#include "funnel/walton3d.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "funnel/random.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

/// A uniform draw in (-1, 1) from a counter.
double draw(std::uint64_t index, int lane) { return 2.0 * uniform01(11, static_cast<std::uint64_t>(lane), index) - 1.0; }

/// Rotation about the unit axis u by angle a (Rodrigues).
Vec3 rotate(Vec3 v, Vec3 u, double a) {
  return std::cos(a) * v + std::sin(a) * cross(u, v) + ((1.0 - std::cos(a)) * dot(u, v)) * u;
}

Vec3 unit(Vec3 v) { return (1.0 / norm(v)) * v; }

Material some_material(std::uint64_t k) {
  Material m;
  m.e = 0.5 + 0.5 * std::fabs(draw(k, 0));
  m.mu = 2.0 * std::fabs(draw(k, 1));
  m.beta0 = draw(k, 2);
  m.kappa = 0.4;
  m.radius = 0.01;
  return m;
}

TEST(Walton3d, InAMeridianPlaneItIsTheTwoDimensionalLawBitForBit) {
  for (std::uint64_t k = 0; k < 2000; ++k) {
    const Material m = some_material(k);
    const auto law = collision_constants(m);
    // A wall normal in the plane z = 0, on either side, and an approaching velocity.
    const double psi = 3.0 * draw(k, 3);
    const Vec2 n2{std::cos(psi), std::sin(psi)};
    State s2;
    s2.r = {0.1, 0.2};
    s2.v = {draw(k + 5000, 0), draw(k + 5000, 1)};
    if (dot(s2.v, n2) > 0.0) s2.v = -1.0 * s2.v;
    s2.omega = 100.0 * draw(k + 5000, 2);
    const Collision c2 = collide(s2, n2, law);
    State3 s3{{0.1, 0.2, 0.0}, {s2.v.x, s2.v.y, 0.0}, {0.0, 0.0, s2.omega}};
    const Vec3 b{n2.x < 0.0 ? 1.0 : -1.0, 0.0, 0.0};  // the meridian half-plane of the contact
    const Collision3 c3 = collide(s3, {n2.x, n2.y, 0.0}, azimuthal_direction(b), law);
    EXPECT_EQ(c3.after.v.x, c2.after.v.x);
    EXPECT_EQ(c3.after.v.y, c2.after.v.y);
    EXPECT_EQ(c3.after.v.z, 0.0);
    EXPECT_EQ(c3.after.omega.z, c2.after.omega);
    EXPECT_EQ(c3.after.omega.x, 0.0);
    EXPECT_EQ(c3.after.omega.y, 0.0);
    EXPECT_EQ(c3.energy_lost, c2.energy_lost);
    EXPECT_EQ(c3.j_n, c2.j_n);
    EXPECT_EQ(c3.regime, c2.regime);
  }
}

TEST(Walton3d, EnergyLostIsTheDropOfKineticEnergyAndAngularMomentumAboutTheContactIsKept) {
  for (std::uint64_t k = 0; k < 2000; ++k) {
    const Material m = some_material(k);
    const auto law = collision_constants(m);
    const Vec3 n = unit({draw(k, 4), draw(k, 5), draw(k, 6)});
    const Vec3 across = unit(cross(n, {draw(k, 7), draw(k + 1, 7), draw(k + 2, 7)}));
    State3 s{{0.0, 0.0, 0.0}, {draw(k + 9000, 0), draw(k + 9000, 1), draw(k + 9000, 2)},
             {100.0 * draw(k + 9000, 3), 100.0 * draw(k + 7000, 0), 100.0 * draw(k + 7000, 1)}};
    if (dot(s.v, n) > 0.0) s.v = -1.0 * s.v;
    const Collision3 c = collide(s, n, across, law);
    const double kinetic_before = energy(s, m.kappa, m.radius), kinetic_after = energy(c.after, m.kappa, m.radius);
    EXPECT_TRUE(near(kinetic_before - kinetic_after, c.energy_lost, 1e-11, 1e-14)) << k;
    EXPECT_GE(c.energy_lost, -1e-14);
    EXPECT_TRUE(near(dot(c.after.v, n), -m.e * dot(s.v, n), 1e-13, 1e-15));
    // The impulse acts at the contact point -a n: the angular momentum about it is unchanged.
    auto about_contact = [&](const State3& x) { return m.radius * cross(n, x.v) + (m.kappa * m.radius * m.radius) * x.omega; };
    const Vec3 l0 = about_contact(s), l1 = about_contact(c.after);
    EXPECT_LT(norm(l1 - l0), 1e-14 * (norm(l0) + 1e-3)) << k;
    // Sticking leaves the slip at -beta0 times its value.
    if (c.regime == Regime::Sticking) {
      const Vec3 slip_after = c.after.v - dot(c.after.v, n) * n - m.radius * cross(c.after.omega, n);
      EXPECT_LT(norm(slip_after + m.beta0 * c.slip), 1e-13 * (norm(c.slip) + 1e-12));
    }
  }
}

TEST(Walton3d, RotatingTheCollisionRotatesItsResult) {
  for (std::uint64_t k = 0; k < 500; ++k) {
    const Material m = some_material(k);
    const auto law = collision_constants(m);
    const Vec3 n = unit({draw(k, 4), draw(k, 5), draw(k, 6)});
    const Vec3 across = unit(cross(n, {0.3, 0.7, -0.2}));
    State3 s{{0.0, 0.0, 0.0}, {draw(k + 9000, 0), draw(k + 9000, 1), draw(k + 9000, 2)},
             {50.0 * draw(k + 9000, 3), 50.0 * draw(k + 7000, 0), 50.0 * draw(k + 7000, 1)}};
    if (dot(s.v, n) > 0.0) s.v = -1.0 * s.v;
    const Vec3 u = unit({draw(k, 8), draw(k + 3, 8), draw(k + 4, 8)});
    const double angle = 3.0 * draw(k, 9);
    State3 r = s;
    r.v = rotate(s.v, u, angle);
    r.omega = rotate(s.omega, u, angle);
    const Collision3 c = collide(s, n, across, law);
    // Rotated, and with another tangent basis (the law does not depend on it).
    const Vec3 rn = rotate(n, u, angle);
    const Collision3 d = collide(r, rn, unit(cross(rn, {-0.5, 0.1, 0.9})), law);
    EXPECT_LT(norm(d.after.v - rotate(c.after.v, u, angle)), 1e-13);
    EXPECT_LT(norm(d.after.omega - rotate(c.after.omega, u, angle)), 1e-11);
    EXPECT_TRUE(near(d.energy_lost, c.energy_lost, 1e-11, 1e-15));
  }
}

TEST(Walton3d, FrictionlessCollisionKeepsTangentialVelocityAndSpin) {
  Material m;
  m.e = 0.8;
  m.mu = 0.0;
  const auto law = collision_constants(m);
  const Vec3 n = unit({0.2, 1.0, -0.4});
  State3 s{{}, {0.3, -1.0, 0.5}, {5.0, -7.0, 2.0}};
  const Collision3 c = collide(s, n, unit(cross(n, {1.0, 0.0, 0.0})), law);
  const Vec3 vt = s.v - dot(s.v, n) * n, vt_after = c.after.v - dot(c.after.v, n) * n;
  EXPECT_LT(norm(vt_after - vt), 1e-15);
  EXPECT_EQ(c.after.omega.x, s.omega.x);
  EXPECT_EQ(c.after.omega.y, s.omega.y);
  EXPECT_EQ(c.after.omega.z, s.omega.z);
  EXPECT_TRUE(near(c.energy_lost, 0.5 * (1.0 - m.e * m.e) * c.p * c.p, 1e-14));
}

}  // namespace
}  // namespace funnel
