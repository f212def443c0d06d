// Sustained contact: closed-form sliding and rolling against the equations of motion.
#include "funnel/contact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

struct Incline {
  Params params;
  Geometry g;
  Funnel f;
  Material m;
};

Incline incline(double theta, double mu, double kappa = 0.4) {
  Incline s;
  s.params = default_params();
  s.params.theta = theta;
  s.params.mu = mu;
  s.params.inertia = kappa;
  s.g = make_geometry(s.params);
  s.f = make_funnel(s.params);
  s.m = material(s.params);
  return s;
}

/// A state on the left face at height y with down-slope speed w and spin omega.
State on_left_face(const Geometry& g, double y, double w, double omega) {
  State st;
  st.r = {-y / g.tan_t, y};
  st.v = w * Vec2{g.cos_t, -g.sin_t};
  st.omega = omega;
  return st;
}

TEST(Contact, RollingFromRestMatchesTheClosedForm) {
  // Rolling without slipping down an incline: acceleration g sin(theta) / (1 + kappa).
  const Incline s = incline(30.0, 1.0);
  const double y0 = 0.5;
  const ContactResult r = slide_on_face(on_left_face(s.g, y0, 0.0, 0.0), s.f.sides[0].faces[0], -1.0, s.m);
  const double length = (y0 - s.g.y_face_end) / s.g.sin_t;
  const double accel = s.g.sin_t / 1.4;
  EXPECT_EQ(r.first_regime, Regime::Rolling);
  EXPECT_FALSE(r.slid);  // mu only passed the rolling test: the same contact for every larger mu
  EXPECT_TRUE(near(r.duration, std::sqrt(2.0 * length / accel), 1e-14));
  const double w = std::sqrt(2.0 * accel * length);
  EXPECT_TRUE(near(std::hypot(r.end.v.x, r.end.v.y), w, 1e-14));
  // Rolling: the contact point does not slip, and no energy is lost.
  EXPECT_TRUE(near(w + s.m.radius * r.end.omega, 0.0, 0.0, 1e-12));
  EXPECT_NEAR(r.energy_lost, 0.0, 1e-15);
  EXPECT_TRUE(near(r.normal_impulse, s.g.cos_t * r.duration, 1e-15));
}

TEST(Contact, SteepFaceSlidesWithKineticFriction) {
  // tan(theta) > mu (1 + kappa)/kappa: it never rolls; acceleration g (sin - mu cos).
  const Incline s = incline(80.0, 0.1);
  const double y0 = 0.8;
  const ContactResult r = slide_on_face(on_left_face(s.g, y0, 0.0, 0.0), s.f.sides[0].faces[0], -1.0, s.m);
  const double length = (y0 - s.g.y_face_end) / s.g.sin_t;
  const double accel = s.g.sin_t - 0.1 * s.g.cos_t;
  EXPECT_EQ(r.last_regime, Regime::Sliding);
  EXPECT_TRUE(r.slid);  // from zero slip straight into sliding: the contact depends on mu
  EXPECT_TRUE(near(r.duration, std::sqrt(2.0 * length / accel), 1e-12));
  // Energy: lost = drop in potential - gain in kinetic energy (translational + spin).
  const double ke = 0.5 * dot(r.end.v, r.end.v) + 0.5 * s.m.kappa * s.m.radius * s.m.radius * r.end.omega * r.end.omega;
  EXPECT_TRUE(near(r.energy_lost, (y0 - s.g.y_face_end) - ke, 1e-12));
  EXPECT_GT(r.energy_lost, 0.0);
}

TEST(Contact, StaticFrictionHoldsRollingExactlyUpToItsClosedFormSlope) {
  // From rest a ball rolls down a face while tan(theta) <= mu (1 + kappa) / kappa (the friction
  // rolling needs, kappa/(1 + kappa) g sin, within mu g cos), and slides beyond it: half a
  // degree either side of that slope, for several mu and moments of inertia.
  for (const double kappa : {0.4, 0.2, 2.0 / 3.0}) {
    for (const double mu : {0.1, 0.2, 0.5}) {
      const double critical = std::atan(mu * (1.0 + kappa) / kappa) * 180.0 / std::numbers::pi;
      ASSERT_LT(critical, 80.0);
      for (const double theta : {critical - 0.5, critical + 0.5}) {
        const Incline s = incline(theta, mu, kappa);
        const ContactResult r = slide_on_face(on_left_face(s.g, 0.6, 0.0, 0.0), s.f.sides[0].faces[0], -1.0, s.m);
        const bool rolls = theta < critical;
        EXPECT_EQ(r.first_regime, rolls ? Regime::Rolling : Regime::Sliding) << kappa << " " << mu << " " << theta;
        EXPECT_EQ(r.slid, !rolls) << kappa << " " << mu << " " << theta;
        // Rolling loses nothing; sliding loses mu N times the distance the contact point slips,
        // which grows at sin - mu cos (1 + 1/kappa) while the centre speeds up at sin - mu cos.
        const double length = (0.6 - s.g.y_face_end) / s.g.sin_t;
        const double sin_t = s.g.sin_t, cos_t = s.g.cos_t;
        const double slipped = length * (sin_t - mu * cos_t * (1.0 + 1.0 / kappa)) / (sin_t - mu * cos_t);
        EXPECT_TRUE(near(r.energy_lost, rolls ? 0.0 : mu * cos_t * slipped, 1e-10, 1e-14))
            << kappa << " " << mu << " " << theta << " " << r.energy_lost;
      }
    }
  }
}

TEST(Contact, SlipDecaysThenRollsAndEnergyBalances) {
  // Back-spin: slides until the slip vanishes, then rolls.
  const Incline s = incline(40.0, 0.8);
  const double y0 = 0.6;
  const State start = on_left_face(s.g, y0, 0.2, 50.0);  // s = 0.2 + 0.5 > 0
  const ContactResult r = slide_on_face(start, s.f.sides[0].faces[0], -1.0, s.m);
  EXPECT_EQ(r.first_regime, Regime::Sliding);
  EXPECT_EQ(r.last_regime, Regime::Rolling);
  EXPECT_TRUE(r.slid);
  const double e_start = energy(start, s.m.kappa, s.m.radius);
  const double e_end = energy(r.end, s.m.kappa, s.m.radius);
  EXPECT_TRUE(near(e_start - e_end, r.energy_lost, 1e-12));
  const double w = std::hypot(r.end.v.x, r.end.v.y);
  EXPECT_TRUE(near(w + s.m.radius * r.end.omega, 0.0, 0.0, 1e-12));
}

TEST(Contact, BackspinCanDriveTheParticleUpTheFaceFirst) {
  // Strong back-spin and mu > tan(theta): the friction force points up the slope at first.
  const Incline s = incline(20.0, 1.0);
  const State start = on_left_face(s.g, 0.3, 0.0, -200.0);  // s = -2 < 0: friction pushes down
  const ContactResult down = slide_on_face(start, s.f.sides[0].faces[0], -1.0, s.m);
  const State back = on_left_face(s.g, 0.3, 0.0, 200.0);    // s = +2: friction pushes up
  const ContactResult up = slide_on_face(back, s.f.sides[0].faces[0], -1.0, s.m);
  EXPECT_GT(up.duration, down.duration);
  for (const auto& [st, r] : {std::pair{start, down}, std::pair{back, up}}) {
    EXPECT_TRUE(near(energy(st, s.m.kappa, s.m.radius) - energy(r.end, s.m.kappa, s.m.radius), r.energy_lost, 1e-12));
  }
}

TEST(Contact, RightFaceMirrorsLeftFace) {
  const Incline s = incline(55.0, 0.2);
  const State left = on_left_face(s.g, 0.4, 0.3, 12.0);
  State right = left;
  right.r.x = -left.r.x;
  right.v.x = -left.v.x;
  right.omega = -left.omega;
  const ContactResult rl = slide_on_face(left, s.f.sides[0].faces[0], -1.0, s.m);
  const ContactResult rr = slide_on_face(right, s.f.sides[1].faces[0], 1.0, s.m);
  EXPECT_EQ(rr.duration, rl.duration);
  EXPECT_EQ(rr.end.v.x, -rl.end.v.x);
  EXPECT_EQ(rr.end.v.y, rl.end.v.y);
  EXPECT_EQ(rr.end.omega, -rl.end.omega);
  EXPECT_EQ(rr.energy_lost, rl.energy_lost);
}

}  // namespace
}  // namespace funnel
