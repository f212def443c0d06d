// Trajectory invariants: energy, mirror symmetry, book-keeping, termination, no stalls.
#include "funnel/engine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <memory>
#include <vector>

#include "funnel/funnel.hpp"
#include "funnel/random.hpp"
#include "funnel/roots.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

Params params_with(double theta, double e, double mu, double beta0 = 0.0, double gap = 0.04) {
  Params p = default_params();
  p.theta = theta;
  p.e = e;
  p.mu = mu;
  p.beta0 = beta0;
  p.gap = gap;
  return p;
}

/// Records the energy after every event.
class EnergyTrace final : public EventSink {
 public:
  explicit EnergyTrace(const Params& p) : kappa_(p.inertia), a_(p.radius) {}
  void record(const Event& e) override {
    State s;
    s.r = e.position;
    s.v = e.velocity_after;
    s.omega = e.omega_after;
    max_dev = std::max(max_dev, std::fabs(energy(s, kappa_, a_) - reference));
    ++count;
    sticking += e.regime == Regime::Sticking;
  }
  double reference = 0.0;
  double max_dev = 0.0;
  long count = 0;
  long sticking = 0;  ///< collisions in the sticking regime

 private:
  double kappa_, a_;
};

TEST(Engine, ElasticFrictionlessClosedFunnelConservesEnergy) {
  for (const double theta : {30.0, 52.0, 75.0}) {
    Params p = params_with(theta, 1.0, 0.0, 0.0, 0.0);
    p.max_collisions = 20000;
    const Geometry g = make_geometry(p);
    EnergyTrace trace(p);
    trace.reference = g.y_release;  // released at rest: E0 = y0
    const Trajectory t = simulate_release(p, g, 0.37, &trace);
    EXPECT_EQ(t.status, Status::Trapped);
    EXPECT_EQ(t.collisions, 20000);
    EXPECT_LT(trace.max_dev, 1e-10) << theta;
    EXPECT_LT(std::fabs(t.energy_loss), 1e-10);
  }
}

TEST(Engine, ElasticCollisionsWithFullTangentialRestitutionConserveEnergy) {
  // e = 1, beta0 = 1 and sticking collisions (large mu): no dissipation at all, with spin.
  Params p = params_with(50.0, 1.0, 1e6, 1.0, 0.0);
  p.max_collisions = 10000;
  const Geometry g = make_geometry(p);
  EnergyTrace trace(p);
  trace.reference = g.y_release;
  const Trajectory t = simulate_release(p, g, -0.61, &trace);
  EXPECT_LT(trace.max_dev, 1e-10);
  // The check covers what it claims: thousands of collisions, (nearly) all of them sticking.
  EXPECT_EQ(t.collisions, 10000);
  EXPECT_GE(trace.count, 10000);
  EXPECT_GT(trace.sticking, 9000);
}

/// The logs of releases at x0 and -x0 are exact mirror images, event by event: the same kinds
/// on the other wall, at the same times, with x, u, spin, slip and the friction impulse j_t
/// negated (t = (n_y, -n_x) of each wall's own normal mirrors to -t), the rest equal. Exactly:
/// mirror halving of ensembles relies on the engine's exact mirror symmetry.
void expect_mirror_logs(const EventLog& a, const EventLog& b, const std::string& where) {
  ASSERT_EQ(a.events.size(), b.events.size()) << where;
  for (std::size_t i = 0; i < a.events.size(); ++i) {
    const Event& ea = a.events[i];
    const Event& eb = b.events[i];
    const std::string at = where + " event " + std::to_string(i) + " " + std::string(to_string(ea.kind));
    ASSERT_EQ(ea.kind, eb.kind) << at;
    if (ea.wall) {
      EXPECT_NE(*ea.wall, *eb.wall) << at;
    }
    EXPECT_EQ(ea.time, eb.time) << at;
    EXPECT_EQ(ea.position.x, 0.0 - eb.position.x) << at;
    EXPECT_EQ(ea.position.y, eb.position.y) << at;
    EXPECT_EQ(ea.velocity_after.x, 0.0 - eb.velocity_after.x) << at;
    EXPECT_EQ(ea.velocity_after.y, eb.velocity_after.y) << at;
    EXPECT_EQ(ea.omega_after, 0.0 - eb.omega_after) << at;
    EXPECT_EQ(ea.regime, eb.regime) << at;
    EXPECT_EQ(ea.j_n, eb.j_n) << at;
    EXPECT_EQ(ea.j_t, 0.0 - eb.j_t) << at;
    EXPECT_EQ(ea.energy_lost, eb.energy_lost) << at;
    EXPECT_EQ(ea.slip_before, 0.0 - eb.slip_before) << at;
  }
}

TEST(Engine, MirrorReleaseGivesMirrorTrajectory) {
  for (const double theta : {25.0, 44.0, 46.0, 60.0}) {
    for (const double x0 : {0.13, 0.52, 0.91}) {
      Params p = params_with(theta, 0.99, 0.4, 0.31);
      p.max_collisions = 40;
      const Geometry g = make_geometry(p);
      EventLog a, b;
      simulate_release(p, g, x0, &a);
      simulate_release(p, g, -x0, &b);
      expect_mirror_logs(a, b, "theta " + std::to_string(theta) + " x0 " + std::to_string(x0));
    }
  }
}

TEST(Engine, MirrorReleaseGivesTheMirrorEventLogEdgeContactsIncluded) {
  // The friction impulses of contacts with the outlet's edges mirror too (the right wall's edge
  // contact is solved in its mirror image, and its tangential impulse turned back).
  int edge_contacts = 0, face_collisions = 0;
  // Shallow funnels and little bounce: balls slide down to the outlet slowly enough to roll over
  // its edge.
  for (const double theta : {5.0, 8.0, 12.0}) {
    for (const double e : {0.0, 0.2}) {
      for (const double x0 : {0.1, 0.3, 0.5, 0.7, 0.9}) {
        const Params p = params_with(theta, e, 0.4, 0.31);
        const Geometry g = make_geometry(p);
        EventLog a, b;
        simulate_release(p, g, x0, &a);
        simulate_release(p, g, -x0, &b);
        expect_mirror_logs(a, b, "theta " + std::to_string(theta) + " e " + std::to_string(e) + " x0 " + std::to_string(x0));
        for (const Event& ea : a.events) {
          edge_contacts += ea.kind == EventKind::EdgeContactEnd && ea.j_t != 0.0;
          face_collisions += ea.kind == EventKind::Face && ea.j_t != 0.0;
        }
      }
    }
  }
  EXPECT_GT(edge_contacts, 5);
  EXPECT_GT(face_collisions, 50);
}

TEST(Engine, EveryContactsLoggedFrictionImpulseIsItsChangeOfSpin) {
  // The friction force F acts at the contact point, a from the centre along -n, so its torque is
  // a F about the centre (F along t = (n_y, -n_x)) whatever n does: over a contact with a face or
  // over an edge, I (omega_end - omega_start) = a j_t, i.e. delta omega = j_t / (kappa a). An
  // independent check of the logged j_t (its sign, and its factor while rolling) on both walls.
  int faces = 0, edges = 0;
  for (const double theta : {5.0, 8.0, 12.0, 30.0, 80.0}) {
    for (const double e : {0.0, 0.2}) {
      for (const double kappa : {0.4, 0.25}) {
        for (const double x0 : {-0.9, -0.6, -0.3, 0.1, 0.4, 0.7}) {
          Params p = params_with(theta, e, theta > 50.0 ? 0.1 : 0.4, 0.31);
          p.inertia = kappa;
          const Geometry g = make_geometry(p);
          EventLog log;
          simulate_release(p, g, x0, &log);
          const Event* start = nullptr;
          for (const Event& ev : log.events) {
            if (ev.kind == EventKind::ContactStart || ev.kind == EventKind::EdgeContactStart) start = &ev;
            const bool face_end = ev.kind == EventKind::ContactEnd, edge_end = ev.kind == EventKind::EdgeContactEnd;
            if (!face_end && !edge_end) continue;
            ASSERT_NE(start, nullptr);
            // The spin at the contact's end, before a rest sets it to 0 (omega_before of a face
            // contact's end), against the spin it started with.
            const double spun = (face_end ? ev.omega_before : ev.omega_after) - start->omega_after;
            const double expected = ev.j_t / (kappa * p.radius);
            EXPECT_TRUE(near(spun, expected, 1e-9, 1e-9)) << theta << " " << e << " " << kappa << " " << x0 << " "
                                                          << to_string(ev.kind) << " " << spun << " " << expected;
            (face_end ? faces : edges) += ev.j_t != 0.0;
            start = nullptr;
          }
        }
      }
    }
  }
  EXPECT_GT(faces, 50);
  EXPECT_GT(edges, 10);
}

TEST(Engine, EnergyLossEqualsSumOfCollisionAndContactLosses) {
  int with_contacts = 0;
  for (const double theta : {15.0, 35.0, 50.0, 70.0}) {
    for (const double e : {0.99, 0.7, 0.2}) {
      for (const double x0 : {-0.8, -0.3, 0.45}) {
        const Params p = params_with(theta, e, 0.5, 0.31);
        const Geometry g = make_geometry(p);
        EventLog log;
        const Trajectory t = simulate_release(p, g, x0, &log);
        double sum = 0.0;
        for (const Event& ev : log.events) sum += ev.energy_lost;
        EXPECT_EQ(t.status, Status::Exited);
        EXPECT_TRUE(near(t.energy_loss, t.energy_loss_events, 1e-9)) << theta << " " << e << " " << x0;
        EXPECT_TRUE(near(sum, t.energy_loss_events, 1e-12));
        with_contacts += t.contacts > 0;
      }
    }
  }
  EXPECT_GT(with_contacts, 3);  // sustained contacts are part of the check
}

TEST(Engine, ShallowFunnelsStillEmptyThroughTheEdges) {
  // For theta < 30 deg at the defaults the centre lines cross above the funnel bottom:
  // the particle leaves between the edges, touching them.
  long edge_hits = 0;
  for (const double theta : {10.0, 20.0, 29.0}) {
    const Params p = params_with(theta, 0.99, 1.0);
    const Geometry g = make_geometry(p);
    ASSERT_LT(g.y_bottom, 0.0);
    for (int k = 0; k < 50; ++k) {
      const Trajectory t = simulate_release(p, g, -0.98 + 0.04 * k);
      EXPECT_EQ(t.status, Status::Exited) << theta << " " << k;
      edge_hits += t.edge_collisions;
    }
  }
  EXPECT_GT(edge_hits, 0);
}

TEST(Engine, ClosedInelasticFunnelEndsAtRest) {
  for (const double theta : {20.0, 45.0, 70.0}) {
    for (const double e : {0.9, 0.5, 0.0}) {
      const Params p = params_with(theta, e, 0.5, 0.0, 0.0);
      const Geometry g = make_geometry(p);
      const Trajectory t = simulate_release(p, g, 0.4);
      EXPECT_EQ(t.status, Status::Rest) << theta << " " << e;
      EXPECT_TRUE(near(t.energy_loss, g.y_release, 1e-9));  // everything down to the vertex is lost
      EXPECT_TRUE(near(t.energy_loss, t.energy_loss_events, 1e-9));
    }
  }
}

TEST(Engine, CollapseEndsInSustainedContactAndTheParticleExits) {
  // e = 0: the first collision already collapses; the particle then slides or rolls to C*.
  const Params p = params_with(40.0, 0.0, 1.0);
  const Geometry g = make_geometry(p);
  EventLog log;
  const Trajectory t = simulate_release(p, g, 0.5, &log);
  EXPECT_EQ(t.status, Status::Exited);
  EXPECT_GE(t.contacts, 1);
  EXPECT_GT(t.contact_time, 0.0);
  bool start = false, end = false;
  for (const Event& e : log.events) {
    start |= e.kind == EventKind::ContactStart;
    end |= e.kind == EventKind::ContactEnd;
  }
  EXPECT_TRUE(start && end);
  // The contact ended at C*.
  for (const Event& e : log.events) {
    if (e.kind == EventKind::ContactEnd) {
      EXPECT_EQ(e.position.y, g.y_face_end);
    }
  }
}

TEST(Engine, TimeAdvancesAtEveryEventNoZenoLoops) {
  // Small e and grazing starts stress the collapse and C* hand-offs; no event may repeat at
  // the same time thousands of times, and every run must end before the caps.
  for (const double theta : {5.0, 30.0, 45.0, 60.0, 85.0}) {
    for (const double e : {0.0, 0.3, 0.95}) {
      for (const double mu : {0.0, 0.2, 5.0}) {
        const Params p = params_with(theta, e, mu);
        const Geometry g = make_geometry(p);
        for (const double x0 : {-0.999, -0.5, 0.0, 0.77}) {
          EventLog log;
          const Trajectory t = simulate_release(p, g, x0, &log);
          EXPECT_EQ(t.status, Status::Exited) << theta << " " << e << " " << mu << " " << x0;
          int same = 0, worst = 0;
          for (std::size_t i = 1; i < log.events.size(); ++i) {
            same = log.events[i].time == log.events[i - 1].time ? same + 1 : 0;
            worst = std::max(worst, same);
          }
          EXPECT_LT(worst, 3);
        }
      }
    }
  }
}

TEST(Engine, CapsEndTheRunAsTrapped) {
  Params p = params_with(60.0, 1.0, 1.0, 0.0, 0.0);
  p.t_max = 50.0;
  const Geometry g = make_geometry(p);
  const Trajectory t = simulate_release(p, g, 0.3);
  EXPECT_EQ(t.status, Status::Trapped);
  EXPECT_EQ(t.duration, 50.0);
  p.t_max = 1e5;
  p.max_collisions = 7;
  const Trajectory u = simulate_release(p, g, 0.3);
  EXPECT_EQ(u.status, Status::Trapped);
  EXPECT_EQ(u.collisions, 7);
}

TEST(Engine, ReleasedParticleFallsFreelyToTheFirstWall) {
  // First event: a fall from rest at (x0, y0) onto the right centre line, in closed form.
  const Params p = params_with(60.0, 0.99, 1.0);
  const Geometry g = make_geometry(p);
  EventLog log;
  simulate_release(p, g, 0.5, &log);
  ASSERT_FALSE(log.events.empty());
  const double x0 = 0.5 * g.half_width;
  const double drop = g.y_release - x0 * g.tan_t;
  EXPECT_TRUE(near(log.events[0].time, std::sqrt(2.0 * drop), 1e-15));
  EXPECT_EQ(*log.events[0].wall, Wall::Right);
}


/// Any collision or face-contact phase that slid, or any edge contact, in an event log.
class SlidingSeen final : public EventSink {
 public:
  void record(const Event& e) override {
    seen = seen || e.regime == Regime::Sliding || e.kind == EventKind::EdgeContactStart;
  }
  bool seen = false;
};

TEST(Engine, ATrajectoryThatDidNotSlideIsTheSameForEveryLargerMu) {
  // docs/model.md §4: without a sliding collision, a sliding phase of a face contact or an edge
  // contact, mu enters only through tests that a larger mu passes too. Sweeps over mu reuse such
  // trajectories (run_sweep), so this must hold bit for bit, on every kind of funnel.
  std::vector<Params> funnels;
  for (const double theta : {10.0, 30.0, 46.0, 60.0, 80.0}) {
    for (const double e : {0.99, 0.5}) {
      for (const double beta0 : {0.0, 0.31, -0.31}) funnels.push_back(params_with(theta, e, 1.0, beta0));
    }
  }
  Params spout = params_with(50.0, 0.9, 1.0);
  spout.spout_length = 0.2;
  Params asymmetric = params_with(50.0, 0.95, 1.0, 0.2);
  asymmetric.theta_left = 40.0;
  asymmetric.theta_right = 55.0;
  Params closed = params_with(60.0, 0.9, 1.0, 0.0, 0.0);
  closed.t_max = 200.0;
  Params hopper = params_with(60.0, 0.8, 1.0);
  ProfileSpec spec;  // a shallow section over a steep one on the left; a ledge on the right, its own mu
  spec.sides[0] = {{-2.0, 1.6}, {-0.5, 0.7340}, {-0.1, -0.3650}};
  spec.sides[1] = {{0.9, 1.6}, {0.6, 0.3}, {0.35, 0.3}, {0.1, -0.3650}};
  spec.mu[1] = 0.6;
  hopper.profile = std::make_shared<const ProfileSpec>(spec);
  funnels.insert(funnels.end(), {spout, asymmetric, closed, hopper});

  const std::pair<double, double> mus[] = {{0.0, 0.05}, {0.2, 1.0}, {1.0, 5.0}, {0.5, std::nextafter(0.5, 1.0)}};
  int reused = 0, slid = 0, changed = 0;
  for (const Params& base : funnels) {
    for (const auto& [mu_low, mu_high] : mus) {
      Params low = base, high = base;
      low.mu = mu_low;
      high.mu = mu_high;
      const Funnel f_low = make_funnel(low), f_high = make_funnel(high);
      for (int k = 0; k < 24; ++k) {
        // Releases along the line, some with a random velocity and spin.
        State s = release_state(low, f_low, (2.0 * k + 1.0 - 24.0) / 24.0);
        if (k % 3 == 0) {
          s.v = {0.3 * standard_normal(7, 0, static_cast<std::uint64_t>(k)), 0.3 * standard_normal(7, 1, static_cast<std::uint64_t>(k))};
          s.omega = 20.0 * standard_normal(7, 2, static_cast<std::uint64_t>(k));
        }
        SlidingSeen log;
        const Trajectory a = simulate(low, f_low, s, &log);
        const Trajectory b = simulate(high, f_high, s);
        if (log.seen) {
          EXPECT_TRUE(a.slid) << "theta " << low.theta << ", mu " << mu_low << ", release " << k;
        }
        if (a.slid) {
          ++slid;
          changed += !test::same_trajectory(a, b);
          continue;
        }
        ++reused;
        EXPECT_TRUE(test::same_trajectory(a, b)) << "theta " << low.theta << ", e " << low.e << ", beta0 " << low.beta0
                                                 << ", mu " << mu_low << " -> " << mu_high << ", release " << k;
      }
    }
  }
  // Both kinds occur, and the flag is needed: some trajectories that slid do change.
  EXPECT_GT(reused, 1000);
  EXPECT_GT(slid, 1000);
  EXPECT_GT(changed, 500);
}

TEST(Engine, RandomFunnelsAndReleasesThatDidNotSlideAreTheSameForALargerMu) {
  // The same claim over random funnels (V, closed, spout, asymmetric), materials, sizes and
  // releases with random velocity and spin: among them the rare runs whose only dependence on mu
  // is an edge contact (without its flag some of these change; Contact.* check the face
  // contact's flag directly).
  auto u = [](std::uint64_t stream, int i) { return uniform01(11, stream, static_cast<std::uint64_t>(i)); };
  int reused = 0, invalid = 0;
  for (int i = 0; i < 200000; ++i) {
    Params p = default_params();
    p.theta = 5.0 + 80.0 * u(0, i);
    p.e = u(1, i);
    p.beta0 = 2.0 * u(2, i) - 1.0;
    p.inertia = 0.1 + 0.9 * u(3, i);
    p.radius = 0.002 + 0.03 * u(4, i);
    const double shape = u(5, i);
    p.gap = shape < 0.1 ? 0.0 : p.radius * (2.05 + 8.0 * u(6, i));
    if (shape > 0.8) p.spout_length = 0.3 * u(7, i);
    if (shape > 0.6 && shape <= 0.8) p.theta_right = 5.0 + 80.0 * u(8, i);
    p.mu = u(9, i) < 0.05 ? 0.0 : std::exp(std::log(1e-2) + std::log(1e4) * u(10, i));
    p.t_max = 50.0;
    p.max_collisions = 20000;
    if (validate(p)) {
      ++invalid;
      continue;
    }
    const Funnel f = make_funnel(p);
    State s = release_state(p, f, 2.0 * u(11, i) - 1.0);
    if (i % 3 == 1) {
      s.v = {0.5 * (2.0 * u(12, i) - 1.0), 0.5 * (2.0 * u(13, i) - 1.0)};
      s.omega = 20.0 * (2.0 * u(14, i) - 1.0);
    }
    const Trajectory a = simulate(p, f, s);
    if (a.slid) continue;
    Params more = p;
    more.mu = 2.0 * p.mu + 1e-3;
    const Trajectory b = simulate(more, make_funnel(more), s);
    ++reused;
    ASSERT_TRUE(test::same_trajectory(a, b)) << "run " << i << ": theta " << p.theta << ", e " << p.e << ", beta0 " << p.beta0
                                             << ", mu " << p.mu;
  }
  EXPECT_EQ(invalid, 0);
  EXPECT_GT(reused, 50000);
}

}  // namespace
}  // namespace funnel
