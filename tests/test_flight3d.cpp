// Event detection in the 3D funnel: run back from a known contact and recover its time; grazing
// approaches of the rim; the 2D face time in a meridian plane.
#include "funnel/flight3d.hpp"
#include "funnel/funnel.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "funnel/random.hpp"
#include "funnel/roots.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

double draw(std::uint64_t index, int lane) { return uniform01(23, static_cast<std::uint64_t>(lane), index); }

/// The state a time T before `s` on the same parabola.
State3 run_back(const State3& s, double T) {
  State3 b = s;
  b.r = s.r - T * s.v + Vec3{0.0, -0.5 * T * T, 0.0};
  b.v = s.v + Vec3{0.0, T, 0.0};
  return b;
}

Cone cone_of(double theta) {
  Params p = default_params();
  p.theta = theta;
  return make_cone(p);
}

/// Horizontal unit vector at azimuth phi (right-handed about +y).
Vec3 e_rho(double phi) { return {std::cos(phi), 0.0, -std::sin(phi)}; }

double cone_gap(const Cone& c, Vec3 r) { return c.g.cos_t * r.y - c.g.sin_t * std::hypot(r.x, r.z); }
double rim_gap(const Cone& c, Vec3 r) {
  return std::hypot(std::hypot(r.x, r.z) - c.rim_radius, r.y - c.g.y_bottom) - c.g.radius;
}

TEST(Flight3d, FaceTimeRecoversTheTimeRunBackFromAContact) {
  int checked = 0;
  for (const double theta : {25.0, 44.0, 60.0, 80.0}) {
    const Cone c = cone_of(theta);
    for (std::uint64_t k = 0; k < 400; ++k) {
      // A contact on the face with an approaching velocity, 3D.
      const double rho = c.g.x_face_end + (0.4 - c.g.x_face_end) * draw(k, 0);
      const double phi = 2.0 * std::numbers::pi * draw(k, 1);
      const Vec3 b = e_rho(phi);
      const Vec3 n = cone_normal(c, b);
      State3 hit{rho * b + Vec3{0.0, rho * c.g.tan_t, 0.0}, {}, {}};
      hit.v = Vec3{draw(k, 2) - 0.5, -draw(k, 3), draw(k + 1000, 0) - 0.5};
      if (dot(hit.v, n) > -0.05) continue;
      const double T = 0.02 + 0.3 * draw(k + 1000, 1);
      const State3 start = run_back(hit, T);
      // Only runs inside the cone all the way (the distance is concave: both ends suffice).
      if (!(cone_gap(c, start.r) > 1e-9)) continue;
      const double t = cone_face_time(c, start, {});
      EXPECT_TRUE(near(t, T, 1e-12)) << theta << " " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 400);
}

TEST(Flight3d, RimTimeRecoversTheTimeRunBackFromAContact) {
  int checked = 0;
  for (const double theta : {20.0, 45.0, 70.0}) {
    const Cone c = cone_of(theta);
    const double psi_top = 0.5 * std::numbers::pi + theta * std::numbers::pi / 180.0;
    for (std::uint64_t k = 0; k < 600; ++k) {
      // A contact on the rim's arc (between C* and the outlet's level), approaching it.
      const double psi = psi_top + (std::numbers::pi - psi_top) * (0.02 + 0.96 * draw(k, 0));
      const Vec3 b = e_rho(2.0 * std::numbers::pi * draw(k, 1));
      const Vec3 n = std::cos(psi) * b + Vec3{0.0, std::sin(psi), 0.0};
      State3 hit{rim_point(c, b) + c.g.radius * n, {}, {}};
      hit.v = Vec3{2.0 * draw(k, 2) - 1.0, -draw(k, 3), 2.0 * draw(k + 2000, 0) - 1.0};
      if (dot(hit.v, n) > -0.05) continue;
      const double T = 0.002 + 0.05 * draw(k + 2000, 1);
      const State3 start = run_back(hit, T);
      // Only flights that stay clear of the rim, above the outlet and off the face before.
      bool clear = true;
      for (int j = 0; j < 400 && clear; ++j) {
        const Vec3 r = advance(start, T * j / 400).r;
        const double rho = std::hypot(r.x, r.z);
        clear = rim_gap(c, r) > 1e-12 && r.y > c.g.y_bottom && (up_face(c, rho, r.y) < 0.0 || cone_gap(c, r) > 0.0);
      }
      if (!clear) continue;
      const NextEvent3 ev = next_event(c, start, {});
      EXPECT_EQ(ev.kind, EventKind::Edge) << theta << " " << k;
      EXPECT_TRUE(near(ev.dt, T, 1e-11)) << theta << " " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
}

TEST(Flight3d, GrazingTheRimIsFoundAndMissingItIsNot) {
  // A flight tangent to a torus of tube radius a(1 -+ 1e-10) about the rim circle, curving away
  // from it: its closest approach to the rim circle is a(1 -+ 1e-10).
  int found = 0, missed = 0;
  for (const double theta : {30.0, 60.0}) {
    const Cone c = cone_of(theta);
    const double psi_top = 0.5 * std::numbers::pi + theta * std::numbers::pi / 180.0;
    for (std::uint64_t k = 0; k < 100; ++k) {
      const double psi = psi_top + (std::numbers::pi - psi_top) * (0.1 + 0.8 * draw(k, 0));
      const Vec3 b = e_rho(2.0 * std::numbers::pi * draw(k, 1));
      const Vec3 n = std::cos(psi) * b + Vec3{0.0, std::sin(psi), 0.0};
      const Vec3 along = -std::sin(psi) * b + Vec3{0.0, std::cos(psi), 0.0};  // in the meridian plane
      for (const double scale : {1.0 - 1e-10, 1.0 + 1e-10}) {
        State3 touch{rim_point(c, b) + (c.g.radius * scale) * n, 0.5 * along, {}};
        const State3 start = run_back(touch, 0.004);
        const double t = rim_time(c, start, {}, 0.008);
        if (scale < 1.0) {
          EXPECT_LT(std::fabs(t - 0.004), 1e-4) << k;
          found += t < 0.008;
        } else {
          EXPECT_EQ(t, never) << k;
          missed += t == never;
        }
      }
    }
  }
  EXPECT_EQ(found, 200);
  EXPECT_EQ(missed, 200);
}

TEST(Flight3d, InAMeridianPlaneTheFaceTimeIsTheTwoDimensionalOneBitForBit) {
  for (const double theta : {20.0, 50.0, 75.0}) {
    Params p = default_params();
    p.theta = theta;
    const Geometry g = make_geometry(p);
    const Cone c = make_cone(p);
    const Funnel f = make_funnel(p);
    for (std::uint64_t k = 0; k < 300; ++k) {
      State s2;
      s2.r = {(2.0 * draw(k, 0) - 1.0) * g.half_width * 0.9, g.y_release * (0.2 + 0.8 * draw(k, 1))};
      if (face_distance(g, Wall::Left, s2.r) <= 0.0 || face_distance(g, Wall::Right, s2.r) <= 0.0) continue;
      s2.v = {2.0 * draw(k, 2) - 1.0, 2.0 * draw(k, 3) - 1.0};
      const double t2 = std::min(face_time(f, s2, {Wall::Left, 0}, {}), face_time(f, s2, {Wall::Right, 0}, {}));
      const State3 s3{{s2.r.x, s2.r.y, 0.0}, {s2.v.x, s2.v.y, 0.0}, {}};
      EXPECT_EQ(cone_face_time(c, s3, {}), t2) << theta << " " << k;
    }
  }
}

}  // namespace
}  // namespace funnel
