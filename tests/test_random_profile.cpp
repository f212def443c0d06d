// A seeded random campaign over the general 2D funnel (docs/model.md §2b): random wall profiles
// with the features that broke the engine before (ledges, spouts, nearly level and nearly
// vertical segments, segments about as long as the ball, lower ends at different heights and one
// under the other, slots barely wider than the ball, closed bottoms, a material per wall), and
// thrown and spinning releases. Every run must keep the invariants the model promises: no flight
// rebuilt from the event log enters a wall or an edge, and every exit is between the lower ends;
// every collision and contact starts and ends with the centre at least a from every wall; time
// advances; each event books the energy it takes, a contact's end what the contact took, and no
// event gains energy; the total loss is E0 - E_final and the events' sum; a run ends for a
// reason (an exit, rest, the time or collision cap), never at the Zeno guard but in a slot a few
// ulps of the clock wider than the ball. The fuzz target's profiles (fuzz/fuzz_physics.cpp) are
// simpler; this is the seeded, repeatable form of the random-profile audits of
// docs/robustness.md (findings 30-41).
//
// FUNNEL_RANDOM_PROFILE_CASES and FUNNEL_RANDOM_PROFILE_SEED make it a longer exploratory campaign:
//   FUNNEL_RANDOM_PROFILE_CASES=20000 FUNNEL_RANDOM_PROFILE_SEED=7 build/tests/funnel_tests --gtest_filter='RandomProfile.*'
// A failing case prints its geometry file and the `funnel trajectory` command that reruns it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "funnel/audit.hpp"
#include "funnel/engine.hpp"
#include "funnel/funnel.hpp"
#include "funnel/params.hpp"
#include "funnel/random.hpp"
#include "funnel/walton.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::env_integer;

/// One random case: a funnel (its profile in p) and the releases run in it.
struct Case {
  Params p;
  std::vector<double> releases;
  std::vector<Params> throws;  ///< p with each release's velocity and spin
};

/// Draws numbers for case k of the campaign `seed` from the counter-based generator (stream k).
class Draw {
 public:
  Draw(std::uint64_t seed, std::uint64_t k) : seed_(seed), k_(k) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(seed_, k_, index_++); }
  double log_uniform(double lo, double hi) { return std::pow(10.0, uniform(lo, hi)); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  template <class T>
  T pick(std::initializer_list<T> values) {
    const auto n = static_cast<double>(values.size());
    const auto i = std::min(static_cast<std::size_t>(uniform(0.0, n)), values.size() - 1);
    return *(values.begin() + i);
  }

 private:
  std::uint64_t seed_, k_, index_ = 0;
};

/// A segment's angle to the horizontal, degrees: level, vertical, nearly either, or between.
double segment_angle(Draw& d, bool allow_level) {
  const double r = d.uniform(0.0, 1.0);
  if (r < 0.12 && allow_level) return 0.0;
  if (r < 0.24) return 90.0;
  const double near = d.chance(0.5) ? d.uniform(0.01, 3.0) : d.log_uniform(-4.0, 0.0);
  if (r < 0.36) return near;
  if (r < 0.48) return 90.0 - near;
  return d.uniform(1.0, 89.0);
}

/// A segment's length: about the ball's size, short, or of order H.
double segment_length(Draw& d, double a) {
  const double r = d.uniform(0.0, 1.0);
  if (r < 0.25) return d.uniform(0.2, 3.0) * a;
  if (r < 0.40) return d.log_uniform(-3.0, -1.0);
  return d.log_uniform(-1.3, 0.2);
}

/// One wall's surface from its lower end `end` up, `segments` segments, the top one reaching
/// at least height `top`; `sign` -1 builds a left wall, +1 a right one. Returned top down.
std::vector<Vec2> wall(Draw& d, Vec2 end, double sign, double a, int segments, double top) {
  std::vector<Vec2> up{end};
  double previous = -1.0;
  for (int k = 0; k < segments; ++k) {
    const bool last = k == segments - 1;
    double angle = segment_angle(d, !last);
    for (int tries = 0; tries < 20 && angle == previous; ++tries) angle = segment_angle(d, !last);
    double length = segment_length(d, a);
    const Vec2 from = up.back();
    if (last) {
      const double s = std::sin(angle * std::numbers::pi / 180.0);
      length = std::min(std::max(length, (top - from.y) / s + d.uniform(0.0, 0.5)), 1e4);
    }
    Vec2 to;
    if (angle == 90.0) {
      to = {from.x, from.y + length};
    } else if (angle == 0.0) {
      to = {from.x + sign * length, from.y};
    } else {
      const double r = angle * std::numbers::pi / 180.0;
      to = {from.x + sign * length * std::cos(r), from.y + length * std::sin(r)};
    }
    up.push_back(to);
    previous = angle;
  }
  return {up.rbegin(), up.rend()};
}

struct MaterialDraw {
  double e, mu, beta0;
};

MaterialDraw material(Draw& d) {
  MaterialDraw m;
  m.e = d.pick({0.0, 1.0, 0.99, d.uniform(0.0, 1.0), d.uniform(0.8, 1.0), 0.5});
  m.mu = d.pick({0.0, 0.0, 1e-3, 0.05, d.uniform(0.0, 1.5), 5.0, 100.0, 1.0});
  m.beta0 = d.pick({0.0, -1.0, 1.0, d.uniform(-1.0, 1.0), 0.31, -0.31});
  return m;
}

/// Draws case k of the campaign `seed`, again with the next numbers until the profile is valid;
/// `rejected` counts the profiles that validate() refused.
Case draw_case(std::uint64_t seed, std::uint64_t k, int releases, std::int64_t& rejected) {
  Draw d(seed, k);
  for (;;) {
    Case c;
    Params& p = c.p;
    p = default_params();
    const double r_a = d.uniform(0.0, 1.0);
    p.radius = r_a < 0.6 ? d.log_uniform(-3.0, -1.3) : r_a < 0.9 ? d.log_uniform(-1.3, -0.7) : d.uniform(0.2, 0.3);
    const double a = p.radius;
    Vec2 left_end{0.0, 0.0}, right_end{0.0, 0.0};
    const bool closed = d.chance(0.15);
    if (!closed) {
      const double r_gap = d.uniform(0.0, 1.0);
      const double gap = r_gap < 0.25   ? 2.0 * a * (1.0 + d.log_uniform(-6.0, -1.0))  // a slot barely wider
                         : r_gap < 0.5 ? 2.0 * a * d.uniform(1.1, 3.0)
                                       : 2.0 * a + d.uniform(0.0, 0.6);
      const double r_dy = d.uniform(0.0, 1.0);
      double dy = r_dy < 0.35 ? 0.0 : r_dy < 0.55 ? d.log_uniform(-6.0, -1.0) : d.uniform(0.05, 1.5);
      if (d.chance(0.5)) dy = -dy;
      if (dy != 0.0 && d.chance(0.25)) {  // one lower end nearly under the other
        const double xl = -d.uniform(0.0, 1.2 * a);
        left_end = {xl, dy / 2};
        right_end = {xl + d.uniform(1e-3, 1.5) * a, -dy / 2};
      } else {
        left_end = {-gap / 2, dy / 2};
        right_end = {gap / 2, -dy / 2};
      }
    }
    p.release_height = d.chance(0.5) ? 1.0 : d.uniform(0.2, 2.0);
    const double top = std::max(left_end.y, right_end.y) + p.release_height + d.uniform(0.0, 1.0);
    auto segments = [&] { return d.pick({1, 1, 2, 3, 4, 5, 8, 12}); };
    auto spec = std::make_shared<ProfileSpec>();
    const int n_left = segments(), n_right = segments();
    spec->sides[0] = wall(d, left_end, -1.0, a, n_left, top);
    spec->sides[1] = wall(d, right_end, 1.0, a, n_right, top);
    if (!closed && left_end.y == right_end.y && left_end.x == -right_end.x && d.chance(0.1)) {
      *spec = mirrored_profile(spec->sides[0]);
    }
    const MaterialDraw m = material(d);
    p.e = m.e;
    p.mu = m.mu;
    p.beta0 = m.beta0;
    if (d.chance(0.3)) {  // a material of its own for the right wall
      const MaterialDraw r = material(d);
      spec->e[1] = r.e;
      spec->mu[1] = r.mu;
      spec->beta0[1] = r.beta0;
    }
    if (d.chance(0.2)) p.inertia = d.pick({2.0 / 3.0, 0.5, d.uniform(0.05, 3.0)});
    spec->source = "random profile";
    p.profile = spec;
    p.theta_left = Params::unset;
    p.theta_right = Params::unset;
    p.t_max = 30.0;
    p.max_collisions = 4000;
    if (validate(p)) {
      ++rejected;
      continue;
    }
    for (int j = 0; j < releases; ++j) {
      const double r_x = d.uniform(0.0, 1.0);
      const double x = r_x < 0.5    ? d.uniform(-1.0, 1.0)
                       : r_x < 0.75 ? (d.chance(0.5) ? -1.0 : 1.0) * (1.0 - d.log_uniform(-9.0, -1.0))
                                    : 0.0;
      Params q = p;
      const double r_v = d.uniform(0.0, 1.0);
      if (r_v < 0.3) {
        q.release_u = d.uniform(-3.0, 3.0);
        q.release_v = d.uniform(-3.0, 3.0);
      } else if (r_v < 0.4) {
        q.release_u = d.uniform(-0.3, 0.3);
      }
      if (d.chance(0.25)) q.release_spin = d.chance(0.5) ? d.uniform(-100.0, 100.0) : d.uniform(-3000.0, 3000.0);
      if (validate(q) || !(x > -1.0 && x < 1.0)) continue;
      c.releases.push_back(x);
      c.throws.push_back(q);
    }
    return c;
  }
}

/// The geometry file of a case and the command line that reruns one of its releases.
std::string rerun(const Params& q, double x) {
  std::string toml = "  # case.toml\n";
  const char* names[2] = {"left", "right"};
  for (int s = 0; s < 2; ++s) {
    toml += std::string("  [") + names[s] + "]\n  vertices = [";
    for (std::size_t i = 0; i < q.profile->sides[s].size(); ++i) {
      const Vec2 v = q.profile->sides[s][i];
      toml += (i ? ", [" : "[") + format_number(v.x) + ", " + format_number(v.y) + "]";
    }
    toml += "]\n";
    if (q.profile->e[s]) toml += "  e = " + format_number(*q.profile->e[s]) + "\n";
    if (q.profile->mu[s]) toml += "  mu = " + format_number(*q.profile->mu[s]) + "\n";
    if (q.profile->beta0[s]) toml += "  beta0 = " + format_number(*q.profile->beta0[s]) + "\n";
  }
  std::string cmd = "  funnel trajectory --geometry case.toml --events";
  const Params defaults = default_params();
  for (const ParameterInfo& info : parameters()) {
    const std::string name(info.name);
    if (!info.option || name == "theta" || name == "gap" || name == "theta-left" || name == "theta-right") continue;
    if (info.get(q) != info.get(defaults)) cmd += " --" + name + " " + format_number(info.get(q));
  }
  return toml + cmd + " --release " + format_number(x);
}

/// The distance from point r to the nearest wall surface of the profile.
double wall_distance(const ProfileSpec& spec, Vec2 r) {
  double best = HUGE_VAL;
  for (const auto& side : spec.sides) {
    for (std::size_t i = 0; i + 1 < side.size(); ++i) best = std::min(best, segment_distance(r, side[i], side[i + 1]));
  }
  return best;
}

/// The failures of one run (empty when every invariant holds).
std::vector<std::string> check_run(const Params& q, const Funnel& f, double x, const Trajectory& t,
                                   const std::vector<Event>& events) {
  std::vector<std::string> failures;
  auto fail = [&](const std::string& what) {
    if (std::find(failures.begin(), failures.end(), what) == failures.end()) failures.push_back(what);
  };
  const State initial = release_state(q, f, x);
  const double e0 = energy(initial, q.inertia, q.radius);
  const double scale = std::max({1.0, std::fabs(f.y_exit), std::fabs(f.y_release), std::fabs(e0)});
  const double etol = 1e-9 * scale;
  const double ptol = audit_tolerance_for(q.radius, audit_size(f));
  // The flights, rebuilt from the log.
  const FlightAudit audit = audit_flights(f, initial, events);
  if (audit.edge_overlaps > 0) fail("a flight comes " + format_number(1.0 - audit.min_edge_distance) + " a into an edge");
  if (audit.face_crossings > 0) fail("a flight goes " + format_number(audit.max_face_depth) + " a behind a face");
  if (audit.exits_outside > 0) fail("an exit outside the outlet");
  if (audit.missed_exits > 0) fail("a flight leaves the funnel and goes on");
  // The events.
  double time = 0.0, after = e0;
  bool in_contact = false;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    if (!(std::isfinite(e.time) && std::isfinite(e.position.x) && std::isfinite(e.position.y) &&
          std::isfinite(e.velocity_after.x) && std::isfinite(e.velocity_after.y) && std::isfinite(e.omega_after) &&
          std::isfinite(e.energy_lost))) {
      fail("an event that is not finite");
      continue;
    }
    if (e.time < time) fail("time goes back");
    time = e.time;
    if (e.kind != EventKind::Exit) {
      const double gap = wall_distance(*q.profile, e.position) / q.radius;
      if (gap < 1.0 - ptol) fail("an event with the centre " + format_number(1.0 - gap) + " a inside a wall");
    }
    const double before_e = energy({e.position, e.velocity_before, e.omega_before}, q.inertia, q.radius);
    const double after_e = energy({e.position, e.velocity_after, e.omega_after}, q.inertia, q.radius);
    const double since = before_e - after;
    const double booked = e.energy_lost - (before_e - after_e);
    if (e.kind == EventKind::ContactEnd || e.kind == EventKind::EdgeContactEnd) {
      if (!in_contact) fail("a contact's end without its start");
      if (since > etol) fail("a contact gains energy");
      if (std::fabs(-since - booked) > etol) fail("a contact's end books another loss than its energy drop");
      in_contact = false;
    } else {
      if (in_contact && e.kind != EventKind::Exit) fail("an event inside a contact");
      if (std::fabs(since) > etol) fail("a flight changes the energy");
      if (std::fabs(booked) > etol) fail("an event books another loss than its energy drop");
    }
    if (e.energy_lost < -etol) fail("an event gains energy");
    if (e.kind == EventKind::ContactStart || e.kind == EventKind::EdgeContactStart) in_contact = true;
    after = after_e;
  }
  // The run as a whole.
  if (!(std::isfinite(t.duration) && std::isfinite(t.energy_loss) && std::isfinite(t.final_state.r.x) &&
        std::isfinite(t.final_state.r.y))) {
    fail("a result that is not finite");
  }
  if (t.duration < time - 1e-12 * (1.0 + time) || t.duration > q.t_max) fail("the duration is outside [last event, t_max]");
  if (std::fabs((e0 - energy(t.final_state, q.inertia, q.radius)) - t.energy_loss) > etol) fail("the loss is not E0 - E_final");
  if (std::fabs(t.energy_loss - t.energy_loss_events) > etol) fail("the loss is not the events' sum");
  if (t.energy_loss < -etol) fail("the run gains energy");
  if (f.closed && t.status == Status::Exited) fail("a closed funnel's ball exits");
  // The Zeno guard: only in a slot a few ulps of the clock wider than the ball.
  const Vec2 l = f.sides[0].corners[0].point, r = f.sides[1].corners[0].point;
  const double slot = f.closed ? 1.0 : 0.5 * std::hypot(r.x - l.x, r.y - l.y) - q.radius;
  if (t.stalled && slot >= 1e-12 * std::max(1.0, t.duration)) fail("ended by the Zeno guard (stalled)");
  if (t.status == Status::Trapped && !t.stalled && t.duration < q.t_max && t.collisions < q.max_collisions) {
    fail("trapped before the caps");
  }
  return failures;
}

/// What a campaign reached, and how many of its runs failed.
struct Tally {
  std::int64_t profiles = 0, rejected = 0, runs = 0, failing = 0;
  std::int64_t exited = 0, rests = 0, capped = 0, contacts = 0, edge_contacts = 0, side_exits = 0;
};

Tally campaign(std::uint64_t seed, std::int64_t cases) {
  Tally n;
  for (std::int64_t k = 0; k < cases; ++k) {
    const Case c = draw_case(seed, static_cast<std::uint64_t>(k), 4, n.rejected);
    ++n.profiles;
    const Funnel f = make_funnel(c.p);
    for (std::size_t j = 0; j < c.releases.size(); ++j) {
      const Params& q = c.throws[j];
      EventLog log;
      const Trajectory t = simulate_release(q, f, c.releases[j], &log);
      ++n.runs;
      n.exited += t.status == Status::Exited;
      n.rests += t.status == Status::Rest;
      n.capped += t.capped;
      n.contacts += t.contacts > 0;
      n.edge_contacts += t.edge_contacts > 0;
      n.side_exits += t.status == Status::Exited && t.exit_state.r.y > f.y_exit;
      const std::vector<std::string> failures = check_run(q, f, c.releases[j], t, log.events);
      if (!failures.empty()) {
        ++n.failing;
        std::string all;
        for (const std::string& s : failures) all += "\n  " + s;
        ADD_FAILURE() << "case " << k << " of seed " << seed << ", release " << j << ":" << all << "\n"
                      << rerun(q, c.releases[j]);
      }
    }
  }
  std::printf("random profile campaign (seed %llu): %lld profiles (%lld drawn and refused), %lld runs: %lld exited "
              "(%lld sideways), %lld at rest, %lld at the collision cap; %lld with face contacts, %lld with edge "
              "contacts; %lld failing\n",
              static_cast<unsigned long long>(seed), static_cast<long long>(n.profiles),
              static_cast<long long>(n.rejected), static_cast<long long>(n.runs), static_cast<long long>(n.exited),
              static_cast<long long>(n.side_exits), static_cast<long long>(n.rests), static_cast<long long>(n.capped),
              static_cast<long long>(n.contacts), static_cast<long long>(n.edge_contacts),
              static_cast<long long>(n.failing));
  return n;
}

TEST(RandomProfile, EveryInvariantHoldsOverRandomProfilesAndThrownSpinningReleases) {
  const std::int64_t cases = env_integer("FUNNEL_RANDOM_PROFILE_CASES", 10000);
  const auto seed = static_cast<std::uint64_t>(env_integer("FUNNEL_RANDOM_PROFILE_SEED", 2026));
  const Tally n = campaign(seed, cases);
  // Seven more seeds of 50 000 profiles (1.4 M runs, seeds 1 and 4-9) ended 15 runs at the Zeno
  // guard: collisions piling up in no time in a concave corner, 13 of them "superballs" (beta0 =
  // 1 with mu = 100: every collision sticks and reverses the slip) that lost only 1% of their
  // speed at each (docs/robustness.md, finding 42, fixed: they all pass now).
  if (cases >= 1000) {
    // It reaches what it tests (10 000 profiles: 58% of the runs exit, a quarter of them sideways,
    // 7.5% rest, 45% have face contacts and 3.6% edge contacts).
    EXPECT_GT(n.exited, n.runs / 4);
    EXPECT_GT(n.rests, n.runs / 50);
    EXPECT_GT(n.contacts, n.runs / 10);
    EXPECT_GT(n.edge_contacts, n.runs / 100);
    EXPECT_GT(n.side_exits, n.runs / 100);
  }
}

}  // namespace
}  // namespace funnel
