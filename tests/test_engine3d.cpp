// The 3D engine: the 2D trajectory in a meridian plane, symmetries, invariants, bookkeeping,
// the flight audit and termination.
#include "funnel/engine3d.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <cstdint>

#include "funnel/audit3d.hpp"
#include "funnel/ensemble3d.hpp"
#include "funnel/random.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;
using test::rotate;

Params params_with(double theta, double e, double mu, double beta0 = 0.0, double gap = 0.04) {
  Params p = default_params();
  p.theta = theta;
  p.e = e;
  p.mu = mu;
  p.beta0 = beta0;
  p.gap = gap;
  return p;
}


bool close(Vec3 a, Vec3 b, double tol) { return norm(a - b) <= tol * (1.0 + norm(a)); }

TEST(Engine3d, InAMeridianPlaneTheTrajectoryIsTheTwoDimensionalOne) {
  int runs = 0, with_rim = 0, with_contacts = 0, with_rim_contacts = 0;
  for (const double theta : {20.0, 35.0, 44.0, 46.0, 60.0, 75.0}) {
    for (const double e : {0.99, 0.6, 0.0}) {
      for (const double mu : {0.0, 0.3, 1.0}) {
        for (const double beta0 : {-0.31, 0.31}) {
          for (const double x0 : {-0.77, 0.41}) {
            Params p = params_with(theta, e, mu, beta0);
            p.max_collisions = 400;
            // A release just above the faces' ends reaches C* slowly: rim contacts.
            if (e == 0.0 && beta0 > 0.0) p.release_height = p.radius * (1.0 + std::cos(theta * 3.14159265358979 / 180.0));
            EventLog l2;
            EventLog3 l3;
            const Trajectory t2 = simulate_release(p, make_geometry(p), x0, &l2);
            const Trajectory3 t3 = simulate_release_3d(p, make_cone(p), x0, &l3);
            ASSERT_EQ(l2.events.size(), l3.events.size()) << theta << " " << e << " " << mu << " " << x0;
            for (std::size_t i = 0; i < l2.events.size(); ++i) {
              const Event& a = l2.events[i];
              const Event3& b = l3.events[i];
              ASSERT_EQ(a.kind, b.kind) << i;
              ASSERT_TRUE(near(b.time, a.time, 1e-12)) << i;
              ASSERT_TRUE(near(b.position.x, a.position.x, 1e-12, 1e-14)) << i;
              ASSERT_TRUE(near(b.position.y, a.position.y, 1e-12, 1e-14)) << i;
              ASSERT_TRUE(near(b.velocity_after.x, a.velocity_after.x, 1e-12, 1e-14)) << i;
              ASSERT_TRUE(near(b.velocity_after.y, a.velocity_after.y, 1e-12, 1e-14)) << i;
              ASSERT_TRUE(near(b.omega_after.z, a.omega_after, 1e-12, 1e-12)) << i;
              ASSERT_EQ(b.position.z, 0.0);
              ASSERT_EQ(b.velocity_after.z, 0.0);
            }
            EXPECT_EQ(t3.status, t2.status);
            EXPECT_TRUE(near(t3.duration, t2.duration, 1e-12));
            EXPECT_TRUE(near(t3.impulse, t2.impulse, 1e-12));
            EXPECT_TRUE(near(t3.energy_loss, t2.energy_loss, 1e-12, 1e-15));
            EXPECT_EQ(t3.orbits, 0.0);
            ++runs;
            with_rim += t3.edge_collisions > 0;
            with_contacts += t3.contacts > 0;
            with_rim_contacts += t3.edge_contacts > 0;
          }
        }
      }
    }
  }
  EXPECT_EQ(runs, 216);
  // Rim collisions, sustained face contacts and rim contacts are all part of the comparison.
  EXPECT_GT(with_rim, 20);
  EXPECT_GT(with_contacts, 20);
  EXPECT_GT(with_rim_contacts, 2);
}

TEST(Engine3d, RotatingTheReleaseAboutTheAxisRotatesTheTrajectory) {
  struct Case {
    double theta, e, mu, w;
    std::size_t events;  // compared before chaos amplifies the rounding of the rotation
  };
  int contacts = 0;
  for (const Case k : {Case{60.0, 0.99, 1.0, 0.05, 60}, Case{30.0, 0.99, 0.5, 0.1, 12}, Case{50.0, 0.3, 1.0, 0.1, 200},
                       Case{40.0, 0.0, 0.4, 0.0, 200}}) {
    Params p = params_with(k.theta, k.e, k.mu, 0.2);
    p.t_max = 300.0;
    const Cone c = make_cone(p);
    p.release_w = k.w;
    p.release_spin_y = 3.0;
    const State3 s = release_state_3d(p, c, 0.63);
    EventLog3 a;
    simulate_3d(p, c, s, &a);
    for (const double angle : {1.1, -2.4}) {
      EventLog3 b;
      simulate_3d(p, c, rotate(s, angle), &b);
      const std::size_t n = std::min({a.events.size(), b.events.size(), k.events});
      ASSERT_GT(n, 3u);
      for (std::size_t i = 0; i < n; ++i) {
        const Event3& x = a.events[i];
        const Event3& y = b.events[i];
        ASSERT_EQ(x.kind, y.kind) << k.theta << " " << i;
        EXPECT_TRUE(near(y.time, x.time, 1e-8)) << k.theta << " " << i;
        EXPECT_TRUE(close(y.position, rotate(x.position, angle), 1e-8)) << k.theta << " " << i;
        EXPECT_TRUE(close(y.velocity_after, rotate(x.velocity_after, angle), 1e-8)) << k.theta << " " << i;
        contacts += x.kind == EventKind::ContactEnd || x.kind == EventKind::EdgeContactEnd;
      }
    }
  }
  // The meridian release (w = 0) is solved in closed form, its rotated image by the integrator.
  EXPECT_GT(contacts, 2);
}

TEST(Engine3d, APeriodicRunGrowsItsImpulsesAndTurnsInProportionToTheTimeCap) {
  // A ball rolling round the cone for ever (a contact whose radial period repeats, or a cycle
  // between the face and the rim) is extrapolated to the time cap: every accumulated quantity,
  // the impulses, the turns about the axis and the contact time, then grows by the same amount
  // for each further stretch of the cap, and none stands still (the golden 3D cases that end so).
  struct Case {
    double theta, release, u, w;
  };
  for (const Case& c : {Case{60.0, 0.7, 0.02, 0.03}, Case{50.0, 0.99, 0.05, 0.05}, Case{44.0, 0.99, 0.01, 0.05}}) {
    std::array<Trajectory3, 3> runs;
    for (int k = 0; k < 3; ++k) {
      Params p = default_params();
      p.theta = c.theta;
      p.release_u = c.u;
      p.release_w = c.w;
      p.t_max = 300.0 * (k + 1);
      const Cone cone = make_cone(p);
      runs[static_cast<std::size_t>(k)] = simulate_3d(p, cone, release_state_3d(p, cone, c.release));
      ASSERT_TRUE(runs[static_cast<std::size_t>(k)].periodic) << c.theta << " " << k;
    }
    const auto grows = [&](const char* what, auto get) {
      const double d1 = get(runs[1]) - get(runs[0]), d2 = get(runs[2]) - get(runs[1]);
      EXPECT_GT(d1, 0.0) << what << " " << c.theta;
      EXPECT_TRUE(near(d1, d2, 1e-9)) << what << " " << c.theta << " " << d1 << " " << d2;
    };
    grows("impulse", [](const Trajectory3& t) { return t.impulse; });
    grows("normal_impulse", [](const Trajectory3& t) { return t.normal_impulse; });
    grows("orbits", [](const Trajectory3& t) { return std::fabs(t.orbits); });
    grows("contact_time", [](const Trajectory3& t) { return t.contact_time; });
    EXPECT_TRUE(near(runs[1].contact_time - runs[0].contact_time, 300.0, 1e-12)) << c.theta;
  }
}

TEST(Engine3d, TheExitObservablesTurnWithTheRelease) {
  // Released in the x-y plane, a ball stays in it: it leaves with no z, no w and a spin about z
  // only. The same release turned a quarter turn about the axis (into the z-y plane) leaves with
  // its spin about x: exit_spin_x is then what exit_spin was, and exit_spin is 0.
  Params p = params_with(60.0, 0.99, 1.0, 0.2);
  const Cone c = make_cone(p);
  const State3 s = release_state_3d(p, c, 0.4);
  const Trajectory3 a = simulate_3d(p, c, s);
  const Trajectory3 b = simulate_3d(p, c, rotate(s, std::numbers::pi / 2.0));
  ASSERT_EQ(a.status, Status::Exited);
  ASSERT_EQ(b.status, Status::Exited);
  const double spin = value(a, Observable::ExitSpin);
  ASSERT_GT(std::fabs(spin), 0.1);
  for (const Observable o : {Observable::ExitZ, Observable::ExitW, Observable::ExitSpinX, Observable::ExitSpinY}) {
    EXPECT_EQ(value(a, o), 0.0) << static_cast<int>(o);
  }
  EXPECT_TRUE(near(value(b, Observable::ExitSpinX), spin, 1e-8)) << value(b, Observable::ExitSpinX) << " " << spin;
  EXPECT_LT(std::fabs(value(b, Observable::ExitSpin)), 1e-8 * std::fabs(spin));
  EXPECT_LT(std::fabs(value(b, Observable::ExitSpinY)), 1e-8 * std::fabs(spin));
  EXPECT_TRUE(near(value(b, Observable::ExitZ), -value(a, Observable::ExitX), 1e-8, 1e-12));
  EXPECT_TRUE(near(value(b, Observable::ExitSpeed), value(a, Observable::ExitSpeed), 1e-8));
  EXPECT_TRUE(near(value(b, Observable::ExitAngle), value(a, Observable::ExitAngle), 1e-8));
}

TEST(Engine3d, MirrorReleaseGivesMirrorTrajectory) {
  // Reflection z -> -z: positions and velocities flip z, the spin (a pseudovector) flips x and y.
  auto mirror = [](Vec3 v) { return Vec3{v.x, v.y, -v.z}; };
  auto mirror_spin = [](Vec3 w) { return Vec3{-w.x, -w.y, w.z}; };
  for (const double theta : {35.0, 60.0}) {
    Params p = params_with(theta, 0.9, 0.5, 0.31);
    p.t_max = 200.0;
    const Cone c = make_cone(p);
    p.release_w = 0.15;
    p.release_spin_x = 2.0;
    const State3 s = release_state_3d(p, c, 0.5);
    EventLog3 a, b;
    const Trajectory3 ta = simulate_3d(p, c, s, &a);
    const Trajectory3 tb = simulate_3d(p, c, {mirror(s.r), mirror(s.v), mirror_spin(s.omega)}, &b);
    ASSERT_EQ(a.events.size(), b.events.size());
    for (std::size_t i = 0; i < a.events.size(); ++i) {
      EXPECT_EQ(a.events[i].kind, b.events[i].kind);
      EXPECT_TRUE(near(b.events[i].time, a.events[i].time, 1e-12));
      EXPECT_TRUE(close(b.events[i].position, mirror(a.events[i].position), 1e-12));
      EXPECT_TRUE(close(b.events[i].omega_after, mirror_spin(a.events[i].omega_after), 1e-10));
    }
    EXPECT_TRUE(near(tb.orbits, -ta.orbits, 1e-12, 1e-12));
  }
}

/// Records the worst drift of the energy and of the orbital angular momentum about the axis.
class Invariants final : public EventSink3 {
 public:
  Invariants(const State3& s, const Params& p) : kappa_(p.inertia), a_(p.radius) {
    e0_ = energy(s, kappa_, a_);
    l0_ = orbital_momentum_y(s);
  }
  void record(const Event3& e) override {
    const State3 s{e.position, e.velocity_after, e.omega_after};
    energy_drift = std::max(energy_drift, std::fabs(energy(s, kappa_, a_) - e0_));
    momentum_drift = std::max(momentum_drift, std::fabs(orbital_momentum_y(s) - l0_) / std::fabs(l0_));
    ++count;
    contacts += e.kind == EventKind::ContactEnd || e.kind == EventKind::EdgeContactEnd;
  }
  double energy_drift = 0.0, momentum_drift = 0.0;
  long count = 0, contacts = 0;

 private:
  double kappa_, a_, e0_ = 0.0, l0_ = 0.0;
};

TEST(Engine3d, FrictionlessMotionConservesAngularMomentumAboutTheAxis) {
  double worst = 0.0;
  long contacts = 0;
  for (const double gap : {0.04, 0.0}) {
    for (const double theta : {40.0, 65.0}) {
      Params p = params_with(theta, 0.8, 0.0, 0.0, gap);
      p.t_max = 150.0;
      const Cone c = make_cone(p);
      p.release_w = 0.12;
      p.release_spin_x = 5.0;
      const State3 s = release_state_3d(p, c, 0.7);
      Invariants inv(s, p);
      const Trajectory3 t = simulate_3d(p, c, s, &inv);
      EXPECT_GT(inv.count, 20);
      worst = std::max(worst, inv.momentum_drift);
      contacts += inv.contacts;
      EXPECT_EQ(t.final_state.omega.x, s.omega.x);  // no friction, no torque: the spin is constant
    }
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(contacts, 0);  // collapses into frictionless sliding are part of it
  std::printf("mu = 0: worst relative drift of L_y over flights, collisions and contacts %.3g\n", worst);
}

TEST(Engine3d, ElasticCollisionsThatDoNotDissipateConserveEnergy) {
  // e = 1 with beta0 = -1 (no tangential impulse), or beta0 = 1 and sticking (mu huge): a long
  // 3D trajectory in a closed cone keeps its energy.
  double worst = 0.0;
  for (const double beta0 : {-1.0, 1.0}) {
    Params p = params_with(50.0, 1.0, beta0 < 0.0 ? 1.0 : 1e6, beta0, 0.0);
    p.max_collisions = 20000;
    const Cone c = make_cone(p);
    p.release_w = 0.2;
    p.release_spin_x = -4.0;
    p.release_spin_y = 7.0;
    const State3 s = release_state_3d(p, c, -0.45);
    Invariants inv(s, p);
    const Trajectory3 t = simulate_3d(p, c, s, &inv);
    EXPECT_EQ(t.collisions, 20000);
    EXPECT_LT(inv.energy_drift, 1e-10) << beta0;
    worst = std::max(worst, inv.energy_drift);
  }
  std::printf("e = 1, |beta0| = 1: worst energy drift over 20000 collisions %.3g\n", worst);
}

TEST(Engine3d, AnElasticFrictionlessRunLosesNoEnergyNotMinusRounding) {
  // Its E_0 - E_end is -3.1e-15, rounding: reported as 0, as in 2D (it was -3.1e-15 in 3D only).
  Params p = params_with(30.0, 1.0, 0.0);
  p.t_max = 2000.0;
  const Cone c = make_cone(p);
  const State3 s = release_state_3d(p, c, 0.6);
  const Trajectory3 t = simulate_3d(p, c, s);
  ASSERT_EQ(t.status, Status::Exited);
  EXPECT_LT(energy(s, p.inertia, p.radius) - energy(t.final_state, p.inertia, p.radius), 0.0);  // the rounding
  EXPECT_EQ(t.energy_loss, 0.0);
}

TEST(Engine3d, InAClosedConeAContactThatReachesTheVertexEndsAtRest) {
  // Balls of a closed-cone ensemble (theta = 50, e = 0.9, mu = 0.2, random sideways velocity)
  // that end in contact at the vertex: one sliding in a spiral (it took 20 million integrator
  // steps, 18 s, to come from 1.2e-9 to 3e-10 H of the vertex, then ended `trapped` by the step
  // guard), one rolling round the axis 1.7e-8 H from it (the same, 17 s). docs/model.md §6: a
  // sustained contact that reaches the vertex rests there; it has once its energy above the
  // vertex is below 1e-4 a (§9).
  Params p = params_with(50.0, 0.9, 0.2, 0.0, 0.0);
  p.t_max = 60.0;
  const Cone c = make_cone(p);
  struct Release {
    double x, u, w;
  };
  for (const Release r : {Release{0.3535533905932738, -0.03200873454552607, -0.16810381489235798},
                          Release{0.45267873021259264, 0.296263256421682, 0.14262118999254011}}) {
    Params q = p;
    q.release_u = r.u;
    q.release_w = r.w;
    EventLog3 log;
    const Trajectory3 t = simulate_3d(q, c, release_state_3d(q, c, r.x), &log);
    EXPECT_EQ(t.status, Status::Rest) << r.x;
    EXPECT_FALSE(t.stalled);
    EXPECT_LT(t.duration, 25.0);
    EXPECT_LT(t.ode_steps, 100000);
    EXPECT_LE(axis_distance(t.final_state.r), 1e-4 * p.radius * (1.0 + 1e-9));
    EXPECT_LT(t.final_state.r.y, 1e-4 * p.radius);
    EXPECT_EQ(t.final_state.v.x, 0.0);
    EXPECT_TRUE(near(t.energy_loss, t.energy_loss_events, 1e-12));
    ASSERT_FALSE(log.events.empty());
    EXPECT_EQ(log.events.back().kind, EventKind::ContactEnd);
  }
}

TEST(Engine3d, InAClosedConeAnIntegratedContactThatReachesTheVertexRestsThere) {
  // Found by a random 3D campaign (docs/robustness.md, finding 23). A face contact off the
  // meridian plane (spin about a horizontal axis) slid into a closed cone's vertex with an energy
  // above the vertex kept above 1e-4 a by its spin, which mu = 0 never takes away: the integration
  // went on through the apex of the centre's cone, and the ball ended at the time cap 1.4e4 H
  // below the vertex, `trapped`. A contact that started exactly on the axis gave NaN (the
  // azimuth's rate h / rho^2 at rho = 0). A third collapsed onto the vertex (bounces of 1e-19 H)
  // and, spinning, was driven out of it by friction in 18 million integrator steps (15 s) until
  // the time cap. docs/model.md §5 and §9: the contact ends at the vertex (within 1e-9 a), at rest.
  struct Case {
    double theta, e, mu, beta0, radius, inertia, t_max, release, u, v, spin_z, spin_x, spin_y;
  };
  for (const Case& k : {Case{63.38668602264677, 0.9598233580633417, 0.0, 1.0, 0.0014424979624671748, 0.4,
                            230.4107885288246, 0.1094332475621833, 0.6105763898720452, 0.004480772024203694,
                            -25.427328730194912, -9.087942294028498, -6.476677427266285},
                       Case{80.28963150785843, 0.0, 2.485712538144175, -1.0, 0.00012454192192585745, 0.4,
                            71.07367637450469, 0.0, 0.0, 0.0, -0.0044622209517168904, -0.31555640244594024,
                            0.13486976997895972},
                       Case{85.28033682906388, 0.9009302290481235, 0.046699859444103535, -1.0, 0.003568119487368158,
                            0.861373574720947, 10.340525284559046, 0.9207733155909997, 0.0, 0.0, -4.168832765618735,
                            7.445898715202002, -6.5567487237228566}}) {
    Params p = params_with(k.theta, k.e, k.mu, k.beta0, 0.0);
    p.radius = k.radius;
    p.inertia = k.inertia;
    p.t_max = k.t_max;
    p.release_u = k.u;
    p.release_v = k.v;
    p.release_spin = k.spin_z;
    p.release_spin_x = k.spin_x;
    p.release_spin_y = k.spin_y;
    const Cone c = make_cone(p);
    EventLog3 log;
    const Trajectory3 t = simulate_release_3d(p, c, k.release, &log);
    EXPECT_EQ(t.status, Status::Rest) << k.theta;
    EXPECT_FALSE(t.stalled);
    EXPECT_LT(t.duration, 0.5 * k.t_max);
    EXPECT_LT(t.ode_steps, 100000);
    EXPECT_TRUE(std::isfinite(t.energy_loss) && std::isfinite(t.impulse)) << t.energy_loss << " " << t.impulse;
    EXPECT_LE(norm(t.final_state.r), 1e-12) << t.final_state.r.x << " " << t.final_state.r.y;
    EXPECT_TRUE(near(t.energy_loss, t.energy_loss_events, 1e-12));
    ASSERT_FALSE(log.events.empty());
    EXPECT_EQ(log.events.back().kind, EventKind::ContactEnd);
    EXPECT_TRUE(audit_flights_3d(c, release_state_3d(p, c, k.release), log.events).clean());
    // The same release turned about the axis: the collapse onto the vertex ends 6e-12 H from it,
    // off the meridian plane, where the frictionless ball then orbited (its spin, which mu = 0
    // never exchanges, kept the energy above 1e-4 a) until the step guard, `stalled`.
    const Trajectory3 turned = simulate_3d(p, c, rotate(release_state_3d(p, c, k.release), -1.9025409959866046));
    EXPECT_EQ(turned.status, Status::Rest) << k.theta;
    EXPECT_FALSE(turned.stalled);
    EXPECT_LT(turned.ode_steps, 100000);
    EXPECT_TRUE(near(turned.duration, t.duration, 1e-5)) << turned.duration << " " << t.duration;
  }
}

TEST(Engine3d, ClosedConeContactsNeverLeaveTheConeWhateverTheSpin) {
  // Random releases into closed cones, thrown and spinning about any axis, with and without
  // friction: every contact ends on or above the vertex (a face contact's centre on the centre
  // cone l >= 0), no result is NaN, and a run at rest is at the vertex or on the face.
  std::uint64_t draws = 0;
  auto uniform = [&draws](double lo, double hi) { return lo + (hi - lo) * uniform01(12345, 0, draws++); };
  int rests = 0, contacts = 0;
  for (int i = 0; i < 80; ++i) {
    Params p = params_with(uniform(20.0, 85.0), i % 3 == 0 ? 0.0 : uniform(0.5, 1.0), i % 2 == 0 ? 0.0 : uniform(0.05, 2.0),
                           uniform(-1.0, 1.0), 0.0);
    p.radius = uniform(1e-3, 0.05);
    p.t_max = 20.0;
    p.release_u = uniform(-0.5, 0.5);
    p.release_w = i % 4 == 0 ? 0.0 : uniform(-0.05, 0.05);
    p.release_spin = uniform(-20.0, 20.0);
    p.release_spin_x = uniform(-20.0, 20.0);
    p.release_spin_y = uniform(-20.0, 20.0);
    const Cone c = make_cone(p);
    EventLog3 log;
    const Trajectory3 t = simulate_release_3d(p, c, uniform(-0.9, 0.9), &log);
    ASSERT_TRUE(std::isfinite(t.energy_loss) && std::isfinite(t.final_state.r.y)) << i;
    EXPECT_FALSE(t.stalled) << i;
    for (const Event3& ev : log.events) {
      if (ev.kind != EventKind::ContactEnd) continue;
      ++contacts;
      EXPECT_GE(ev.position.y, -1e-12) << i << " " << ev.time;
    }
    if (t.status == Status::Rest) ++rests;
    EXPECT_GE(t.final_state.r.y, -1e-12) << i;
  }
  EXPECT_GT(rests, 10);
  EXPECT_GT(contacts, 10);
}

TEST(Engine3d, InARingBarelyWiderThanTheBallTheFarSideOfTheRimIsFound) {
  // Found by the random 3D campaign (docs/robustness.md, finding 24): a ring 1.4e-7 a wider than
  // the ball (d/2a - 1), the ball chattering between the two sides of the rim near the axis, in
  // a meridian plane. The rim search only looks where the centre is in the annulus
  // R - a pad <= rho <= R + a pad (pad = 1 + 1e-6); here R - a pad < 0, and its square excluded
  // the centres within 5.9e-8 H of the axis: a hit on the far side at rho = 5.9e-8 was missed
  // after 2266 events, and the ball exited through the rim, 3.2e-5 H off the axis with the rim
  // 4.7e-4 a inside it. It must be the 2D run, event for event.
  Params p = params_with(56.80004989556421, 0.993566988978814, 0.0, 0.770275906678433, 0.13816695647568283);
  p.radius = 0.0690834684581524;
  p.t_max = 262.2174414021325;
  p.release_u = -0.006261781627216114;
  p.release_v = 0.014732381865008703;
  p.release_spin = -18.01616251947285;
  const double x0 = 0.6456391015214681;
  EventLog l2;
  EventLog3 l3;
  const Trajectory t2 = simulate_release(p, make_geometry(p), x0, &l2);
  const Cone c = make_cone(p);
  const Trajectory3 t3 = simulate_release_3d(p, c, x0, &l3);
  ASSERT_EQ(t2.status, Status::Exited);
  EXPECT_EQ(t3.status, Status::Exited);
  EXPECT_EQ(t3.collisions, t2.collisions);
  EXPECT_EQ(l3.events.size(), l2.events.size());
  EXPECT_GT(t2.edge_collisions, 2000);
  EXPECT_TRUE(near(t3.duration, t2.duration, 1e-12));
  EXPECT_LE(axis_distance(t3.exit_state.r), c.rim_radius - p.radius);
  EXPECT_TRUE(audit_flights_3d(c, release_state_3d(p, c, x0), l3.events).clean());
}

TEST(Engine3d, ATimeCapInsideAnIntegratedContactIsNotAStall) {
  // Found by the random 3D campaign (finding 23): the cap fell inside an integrated contact, whose
  // budget t_max - t ends it exactly, but t + (t_max - t) rounded 1 ulp below t_max, and the run
  // was flagged `stalled` (the guard against a contact that never ends), as 218 of 35 883 random
  // runs were.
  Params p = params_with(15.334552628969817, 0.07663176832152153, 6.258555897618983, 0.5883970860683323,
                         0.2745633249129569);
  p.radius = 0.0030073434046603;
  p.inertia = 0.4536588499813188;
  p.t_max = 5.473350031383107;
  p.release_spin = -2.317393259329977;
  p.release_spin_x = -22.925753376544854;
  p.release_spin_y = 16.775485344413305;
  const Trajectory3 t = simulate_release_3d(p, make_cone(p), 0.7533581196081566);
  EXPECT_EQ(t.status, Status::Trapped);
  EXPECT_FALSE(t.stalled);
  EXPECT_GT(t.contacts + t.edge_contacts, 0);
  EXPECT_TRUE(near(t.duration, p.t_max, 1e-15));
}

/// A small ball spun up on an 86-degree open cone: rolling down the steep face turns its fall into
/// spin, and it circles the axis pressed onto the face, hovering at the limit of rolling: a
/// stick-slip whose sliding phases the integrator resolves only in steps down to 1e-13. With the
/// default guard its contact takes 2e7 steps (about 20 s) and ends `stalled` after 2.7 time
/// units (docs/robustness.md, finding 22, open).
Params steep_stick_slip() {
  Params p = params_with(86.01593143426537, 0.14390672371155014, 0.8610508103691801, -0.15092973196734505,
                         0.0004446501503738709);
  p.radius = 0.00022010929764117512;
  p.t_max = 66.4595276798649;
  p.release_spin = 1.7457709304520292;
  p.release_spin_x = -20.732256122143752;
  p.release_spin_y = 17.483654399884536;
  return p;
}
constexpr double steep_stick_slip_release = 0.6557602573781002;

TEST(Engine3d, AContactBeyondTheStepGuardEndsTheRunStalledBeforeTheCap) {
  Params p = steep_stick_slip();
  const Cone c = make_cone(p);
  double duration = 0.0;
  for (const std::int64_t guard : {4000, 8000}) {
    p.max_ode_steps = guard;
    EventLog3 log;
    const Trajectory3 t = simulate_3d(p, c, release_state_3d(p, c, steep_stick_slip_release), &log);
    EXPECT_EQ(t.status, Status::Trapped) << guard;
    EXPECT_TRUE(t.stalled) << guard;
    EXPECT_FALSE(t.periodic) << guard;
    EXPECT_LT(t.duration, p.t_max) << guard;
    EXPECT_LE(t.ode_steps, guard * (t.contacts + t.edge_contacts)) << guard;
    EXPECT_GE(t.ode_steps, guard) << guard;
    // The guard only stops the run: the energy is booked and no flight enters the cone.
    EXPECT_TRUE(near(t.energy_loss, t.energy_loss_events, 1e-12)) << guard;
    EXPECT_TRUE(audit_flights_3d(c, release_state_3d(p, c, steep_stick_slip_release), log.events).clean()) << guard;
    // A higher guard lets the same contact go on further.
    EXPECT_GT(t.duration, duration) << guard;
    duration = t.duration;
  }
}

TEST(Engine3d, TheStepGuardChangesNoRunWhoseContactsNeedFewerSteps) {
  // The paper's 3D page at 60 degrees: balls thrown sideways, some rolling round the cone to the
  // time cap (periodic). A guard just above the steps any of their runs needs changes no bit.
  Params p = params_with(60.0, 0.99, 1.0);
  p.t_max = 300.0;
  Ensemble3Options o;
  o.samples = 64;
  o.velocity_sd = 0.1;
  o.keep_samples = true;
  const Ensemble3Result plain = run_ensemble_3d(p, o);
  std::int64_t most = 0;
  for (const Sample3& s : plain.per_sample) most = std::max(most, s.trajectory.ode_steps);
  ASSERT_GT(most, 100);
  EXPECT_EQ(plain.stalled, 0);
  p.max_ode_steps = most + 1;
  const Ensemble3Result guarded = run_ensemble_3d(p, o);
  EXPECT_EQ(guarded.stalled, 0);
  for (std::size_t i = 0; i < plain.per_sample.size(); ++i) {
    const Trajectory3& a = plain.per_sample[i].trajectory;
    const Trajectory3& b = guarded.per_sample[i].trajectory;
    EXPECT_EQ(a.status, b.status) << i;
    EXPECT_EQ(a.duration, b.duration) << i;
    EXPECT_EQ(a.energy_loss, b.energy_loss) << i;
    EXPECT_EQ(a.ode_steps, b.ode_steps) << i;
  }
  // Below what they need, the guard stops some of them, and the ensemble counts them.
  p.max_ode_steps = most / 4;
  const Ensemble3Result tight = run_ensemble_3d(p, o);
  std::int64_t stalled = 0;
  for (const Sample3& s : tight.per_sample) {
    stalled += s.trajectory.stalled;
    if (s.trajectory.stalled) {
      EXPECT_EQ(s.trajectory.status, Status::Trapped);
    }
  }
  EXPECT_GT(stalled, 0);
  EXPECT_EQ(tight.stalled, stalled);
  EXPECT_LE(tight.stalled, tight.trapped);
}

TEST(Engine3d, TheStepGuardCountsTheStepsOfEachContactNotOfTheWholeRun) {
  // Balls thrown sideways at 45 degrees (releases of a 64-ball ensemble) that settle onto the
  // face, roll down to the rim and over it: integrated contacts on the face and on the rim. The
  // least guard under which a run is unchanged is what its longest contact needs, below the
  // run's total; a budget for the whole run would need them all.
  Params p = params_with(45.0, 0.5, 0.1);
  p.t_max = 10.0;
  Ensemble3Options o;
  o.samples = 64;
  o.velocity_sd = 0.1;
  const Cone c = make_cone(p);
  int shared = 0;
  for (const std::int64_t k : {23, 24, 36, 37}) {
    const State3 release = ensemble_release_3d(p, c, o, k);
    const auto run = [&](std::int64_t guard) {
      Params q = p;
      q.max_ode_steps = guard;
      return simulate_3d(q, c, release);
    };
    const Trajectory3 t = run(default_max_ode_steps);
    const std::int64_t contacts = t.contacts + t.edge_contacts;
    ASSERT_FALSE(t.stalled) << "release " << k;
    ASSERT_GE(contacts, 2) << "release " << k;
    const auto unchanged = [&](std::int64_t guard) {
      const Trajectory3 u = run(guard);
      return !u.stalled && u.status == t.status && u.duration == t.duration && u.energy_loss == t.energy_loss &&
             u.ode_steps == t.ode_steps;
    };
    // Bisect for the least guard that changes nothing: unchanged(hi), not unchanged(lo).
    std::int64_t lo = 0;
    std::int64_t hi = t.ode_steps + 1;
    ASSERT_TRUE(unchanged(hi)) << "release " << k;
    while (hi - lo > 1) {
      const std::int64_t mid = lo + (hi - lo) / 2;
      (unchanged(mid) ? hi : lo) = mid;
    }
    EXPECT_GE(hi * contacts, t.ode_steps) << "release " << k;
    // Just below it, the longest contact is cut short and the run is flagged.
    const Trajectory3 cut = run(lo);
    EXPECT_TRUE(cut.stalled) << "release " << k;
    EXPECT_EQ(cut.status, Status::Trapped) << "release " << k;
    shared += hi < t.ode_steps;
  }
  EXPECT_GE(shared, 3);
}

TEST(Engine3d, ARimContactThatStartsAtTheOnsetOfSlidingNeverGainsEnergy) {
  // A ball rolls down a shallow cone into a ring 5% wider than itself and crosses the rim at speed:
  // on the rim the normal force falls (3.6 to 0.12 m g), rolling cannot be held, and the slip grows
  // to 4e-6 within the onset's first step, where static friction can hold rolling again. That
  // slip used to be discarded by rolling at once, which gave the ball 9.2e-7 m g H at each pass
  // (found by a random 3D campaign; docs/robustness.md, finding 25). Now it slides until friction
  // has taken the slip away, and every event loses energy.
  Params p = params_with(9.683201325809506, 0.7096699309029338, 3.199673328188112, 0.11312066645304997,
                         0.09349855315127335);
  p.radius = 0.04443457953974535;
  p.inertia = 0.2502415602370436;
  p.t_max = 8.0;
  p.release_spin = -3.7648175298626017;
  p.release_spin_x = -1.4912887986923538;
  p.release_spin_y = 1.6066591294827786;
  const Cone c = make_cone(p);
  for (const double angle : {0.0, 1.0}) {
    const State3 s = rotate(release_state_3d(p, c, 0.5185358823345182), angle);
    EventLog3 log;
    const Trajectory3 t = simulate_3d(p, c, s, &log);
    int rim_contacts = 0;
    double energy_after = energy(s, p.inertia, p.radius);
    for (const Event3& ev : log.events) {
      const double before = energy({ev.position, ev.velocity_before, ev.omega_before}, p.inertia, p.radius);
      EXPECT_LE(before - energy_after, 1e-12) << "energy gained before the event at t = " << ev.time;
      EXPECT_GE(ev.energy_lost, -1e-12) << ev.time;
      energy_after = energy({ev.position, ev.velocity_after, ev.omega_after}, p.inertia, p.radius);
      rim_contacts += ev.kind == EventKind::EdgeContactEnd;
    }
    EXPECT_EQ(rim_contacts, 1) << angle;
    EXPECT_GT(t.energy_loss, 0.0);
    EXPECT_TRUE(near(t.energy_loss, t.energy_loss_events, 1e-12));
  }
}

TEST(Engine3d, ABallDroppedOnAClosedConesAxisMeetsTheVertexAsInTheMeridianPlane) {
  // Dropped on the axis, the ball meets the vertex, where it touches every generator at once.
  // Each bounce there is off the generator it moves towards, as in the 2D corner between the two
  // walls, and a contact after a collapse there is on the generator of the last bounce: the
  // trajectory is the 2D one, mirrored (the 2D engine meets the left wall first). Before (finding
  // 26) every bounce there was off the same generator, the second undid the first, and the ball
  // rested at once: with e = 1 and no friction it lost 98% of its energy. With e = 0 a centre
  // placed past the apex began its contact in the wrong half-plane (0.13 m g H unbooked), and
  // after the first fix a collapse onto the far generator still did (0.028 m g H unbooked).
  struct Drop {
    double theta, e, mu, beta0, radius, kappa, t_max, spin;
  };
  // Two runs of a random 3D campaign (e = 1 without friction; e = 0 with a sticking collision)
  // and one of a review (a bounce, then a collapse onto the other generator).
  const Drop drops[] = {
      {66.35984824795585, 1.0, 0.0, 0.468882518220473, 0.0071850207053931895, 1.6641461637630819, 7.72, 1.4072451739026826},
      {53.84185173403141, 0.0, 6.1174678498438535, 0.8585643639777416, 0.0005409510122884236, 0.4, 14.78, -24.569868109293253},
      {20.0, 2e-9, 0.0, 0.0, 0.01, 0.4, 20.0, 0.0}};
  for (const Drop& d : drops) {
    Params p = params_with(d.theta, d.e, d.mu, d.beta0, 0.0);
    p.radius = d.radius;
    p.inertia = d.kappa;
    p.t_max = d.t_max;
    p.release_spin = d.spin;
    Params mirrored = p;  // the 2D run's mirror image is the 3D run
    mirrored.release_spin = -p.release_spin;
    EventLog l2;
    EventLog3 l3;
    const Trajectory t2 = simulate_release(mirrored, make_geometry(mirrored), 0.0, &l2);
    const Trajectory3 t3 = simulate_release_3d(p, make_cone(p), 0.0, &l3);
    ASSERT_EQ(l2.events.size(), l3.events.size()) << d.theta;
    for (std::size_t i = 0; i < l2.events.size(); ++i) {
      const Event& a = l2.events[i];
      const Event3& b = l3.events[i];
      ASSERT_EQ(a.kind, b.kind) << i;
      ASSERT_TRUE(near(b.time, a.time, 1e-12)) << i;
      ASSERT_TRUE(near(b.velocity_after.x, -a.velocity_after.x, 1e-12, 1e-14)) << i;
      ASSERT_TRUE(near(b.velocity_after.y, a.velocity_after.y, 1e-12, 1e-14)) << i;
      ASSERT_TRUE(near(b.omega_after.z, -a.omega_after, 1e-12, 1e-12)) << i;
    }
    EXPECT_EQ(t3.status, t2.status) << d.theta;
    EXPECT_TRUE(near(t3.contact_time, t2.contact_time, 1e-12, 1e-13)) << d.theta;
    EXPECT_TRUE(near(t3.energy_loss, t2.energy_loss, 1e-12, 1e-13)) << d.theta;
    EXPECT_TRUE(near(t3.energy_loss, t3.energy_loss_events, 1e-12, 1e-13)) << d.theta;
  }
}

TEST(Engine3d, EnergyLossEqualsSumOfEventLosses) {
  int with_contacts = 0;
  for (const double theta : {25.0, 50.0, 70.0}) {
    for (const double e : {0.99, 0.5}) {
      Params p = params_with(theta, e, 0.7, 0.31);
      p.t_max = 300.0;
      const Cone c = make_cone(p);
      p.release_w = 0.08;
      const State3 s = release_state_3d(p, c, 0.55);
      EventLog3 log;
      const Trajectory3 t = simulate_3d(p, c, s, &log);
      double sum = 0.0;
      for (const Event3& ev : log.events) sum += ev.energy_lost;
      EXPECT_TRUE(near(t.energy_loss, t.energy_loss_events, 1e-9)) << theta << " " << e;
      EXPECT_TRUE(near(sum, t.energy_loss_events, 1e-12));
      with_contacts += t.contacts + t.edge_contacts > 0;
    }
  }
  EXPECT_GT(with_contacts, 1);
}

TEST(Engine3d, FlightsNeverEnterTheConeOrTheRimAndExitsAreInsideTheOutlet) {
  FlightAudit3 total;
  for (const double theta : {20.0, 40.0, 60.0, 80.0}) {
    for (const double e : {0.99, 0.5}) {
      Params p = params_with(theta, e, 1.0);
      p.t_max = 200.0;
      Ensemble3Options o;
      o.samples = 40;
      o.velocity_sd = 0.1;
      o.seed = 3;
      const Cone c = make_cone(p);
      for (std::int64_t k = 0; k < o.samples; ++k) {
        const State3 s = ensemble_release_3d(p, c, o, k);
        EventLog3 log;
        simulate_3d(p, c, s, &log);
        total.merge(audit_flights_3d(c, s, log.events));
      }
    }
  }
  EXPECT_TRUE(total.clean()) << total.rim_overlaps << " " << total.face_crossings << " " << total.exits_outside;
  EXPECT_GT(total.flights, 10000);
  EXPECT_LT(total.min_rim_distance, 1.0 + 1e-6);  // the rim was touched
  std::printf("3D audit: %ld flights, closest approach to the rim %.15g a, deepest behind the cone %.3g a\n",
              static_cast<long>(total.flights), total.min_rim_distance, total.max_face_depth);
}

TEST(Engine3d, TimeAdvancesAtEveryEventNoZenoLoops) {
  for (const double theta : {5.0, 30.0, 60.0, 85.0}) {
    for (const double e : {0.0, 0.5, 0.95}) {
      for (const double mu : {0.0, 0.2, 5.0}) {
        Params p = params_with(theta, e, mu);
        p.t_max = 100.0;
        const Cone c = make_cone(p);
        for (const double w : {0.0, 0.1}) {
          p.release_w = w;
          EventLog3 log;
          const Trajectory3 t = simulate_release_3d(p, c, 0.6, &log);
          EXPECT_FALSE(t.stalled) << theta << " " << e << " " << mu << " " << w;
          int same = 0, worst = 0;
          for (std::size_t i = 1; i < log.events.size(); ++i) {
            same = log.events[i].time == log.events[i - 1].time ? same + 1 : 0;
            worst = std::max(worst, same);
          }
          EXPECT_LT(worst, 3) << theta << " " << e << " " << mu << " " << w;
        }
      }
    }
  }
}

}  // namespace
}  // namespace funnel
