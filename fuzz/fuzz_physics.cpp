// libFuzzer target: Walton's collision law and whole trajectories over the valid parameter space.
//
// The fuzz bytes are mapped into valid ranges (docs/model.md §1), with extra weight on the ends of
// each range. Invariants checked (any violation aborts, which libFuzzer reports as a crash):
//  - collide: finite output; kinetic energy never increases; the closed-form energy loss equals
//    the loss computed from the states; |J_t| <= mu J_N; sliding has |J_t| = mu J_N; sticking
//    gives s' = -beta0 s.
//  - the edge quartic's root: the certified refinement gives the reference's double or declines,
//    and the reference the plain loop's, for circle approaches of every scale.
//  - edge_contact: finite output; the end on the edge circle, inside the arc; no energy gained;
//    |integral F dt| <= mu integral N dt; a take-off where the normal force has fallen to 0.
//  - simulate_release (max 20000 collisions, t_max <= 1e3, any release height, velocity and
//    spin): finite observables; a valid status; energy never increases; E_0 - E_end equals the
//    sum of the events' losses; the final state is inside the funnel; every free flight rebuilt
//    from the event log stays clear of the faces and the edges (funnel::audit_flights) and every
//    exit lies between the edges; the exit state balances the energy; the wear bins sum to the
//    totals; the Zeno guard never fires; the mirror release gives the mirror result bit for bit
//    (line ensembles rely on it); a V's releases run together on every SIMD path of the CPU
//    (simulate_many) give the scalar engine's results bit for bit, a closed V's with the orbit
//    watch of Figs. 11-12 too; a run that did not slide (Trajectory::slid) is the same for a
//    larger mu (sweeps over mu reuse it).
//  - the same for random wall profiles (ledges, spouts, wedges, corners, an outlet of any width
//    or closed, lower ends at different heights, a material per wall), and the mirror release in
//    the mirror profile.
#include <fuzzer/FuzzedDataProvider.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "funnel/audit.hpp"
#include "funnel/edge_contact.hpp"
#include "funnel/simd.hpp"
#include "funnel/watch.hpp"
#include "funnel/engine.hpp"
#include "funnel/funnel.hpp"
#include "funnel/geometry.hpp"
#include "funnel/observables.hpp"
#include "funnel/roots.hpp"
#include "funnel/wear.hpp"
#include "funnel/params.hpp"
#include "funnel/walton.hpp"
#include "../tests/plain_refinement.hpp"
#include "../tests/same_bits.hpp"

namespace {

using funnel::Collision;
using funnel::Geometry;
using funnel::Material;
using funnel::Params;
using funnel::State;
using funnel::Status;
using funnel::Trajectory;
using funnel::Vec2;

/// What the current input is (printed with a failure, so a crash can be reproduced by hand).
char context[512] = "";

/// Aborts with a message: libFuzzer records the input as a crash.
[[noreturn]] void fail(const char* what, double a = 0.0, double b = 0.0) {
  std::fprintf(stderr, "fuzz_physics: invariant violated: %s (%.17g, %.17g)\n  %s\n", what, a, b, context);
  std::abort();
}

void require(bool ok, const char* what, double a = 0.0, double b = 0.0) {
  if (!ok) fail(what, a, b);
}

double uniform(FuzzedDataProvider& f, double lo, double hi) {
  return lo + (hi - lo) * f.ConsumeProbability<double>();
}

/// 10^u with u uniform in [lo, hi].
double log_uniform(FuzzedDataProvider& f, double lo, double hi) { return std::pow(10.0, uniform(f, lo, hi)); }

double pick_theta(FuzzedDataProvider& f) {
  switch (f.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: return 90.0 * f.ConsumeProbability<double>();           // may hit 0 or 90: rejected
    case 1: return log_uniform(f, -310.0, 1.0);                      // nearly flat walls
    case 2: return 90.0 - log_uniform(f, -15.0, 1.0);                // nearly vertical walls
    default: return 45.0 + (f.ConsumeBool() ? 1.0 : -1.0) * log_uniform(f, -16.0, 0.0);  // the 45° threshold
  }
}

double pick_e(FuzzedDataProvider& f) {
  switch (f.ConsumeIntegralInRange<int>(0, 2)) {
    case 0: return f.ConsumeProbability<double>();
    case 1: return 1.0 - log_uniform(f, -17.0, 0.0);  // nearly elastic
    default: return f.ConsumeBool() ? 0.0 : 1.0;
  }
}

double pick_mu(FuzzedDataProvider& f) {
  switch (f.ConsumeIntegralInRange<int>(0, 2)) {
    case 0: return 0.0;
    case 1: return log_uniform(f, -8.0, 6.0);  // up to 1e6
    default: return uniform(f, 0.0, 2.0);
  }
}

double pick_beta0(FuzzedDataProvider& f) {
  switch (f.ConsumeIntegralInRange<int>(0, 1)) {
    case 0: return uniform(f, -1.0, 1.0);
    default: return static_cast<double>(f.ConsumeIntegralInRange<int>(-1, 1));
  }
}

Material pick_material(FuzzedDataProvider& f) {
  Material m;
  m.e = pick_e(f);
  m.mu = pick_mu(f);
  m.beta0 = pick_beta0(f);
  m.kappa = log_uniform(f, -3.0, 3.0);
  m.radius = log_uniform(f, -6.0, -1e-9);
  return m;
}

double kinetic(const State& s, const Material& m) {
  return 0.5 * funnel::dot(s.v, s.v) + 0.5 * m.kappa * m.radius * m.radius * s.omega * s.omega;
}

bool finite(const State& s) {
  return std::isfinite(s.r.x) && std::isfinite(s.r.y) && std::isfinite(s.v.x) && std::isfinite(s.v.y) &&
         std::isfinite(s.omega);
}

/// One collision with an arbitrary finite state and unit normal.
void check_collision(FuzzedDataProvider& f) {
  const Material m = pick_material(f);
  std::snprintf(context, sizeof context, "collide: e=%.17g mu=%.17g beta0=%.17g kappa=%.17g radius=%.17g", m.e, m.mu,
                m.beta0, m.kappa, m.radius);
  const double speed = log_uniform(f, -12.0, 6.0);
  State s;
  s.v = {speed * uniform(f, -1.0, 1.0), speed * uniform(f, -1.0, 1.0)};
  s.omega = speed * uniform(f, -1.0, 1.0) / m.radius;  // a omega comparable to the speed
  const double phi = uniform(f, 0.0, 2.0 * 3.141592653589793);
  const Vec2 n{std::cos(phi), std::sin(phi)};

  const Collision c = funnel::collide(s, n, m);
  require(finite(c.after) && std::isfinite(c.j_n) && std::isfinite(c.j_t) && std::isfinite(c.energy_lost),
          "collide: non-finite output");
  const double k0 = kinetic(s, m);
  const double k1 = kinetic(c.after, m);
  require(k1 <= k0 * (1.0 + 1e-12), "collide: kinetic energy increased", k0, k1);
  require(std::fabs(c.energy_lost - (k0 - k1)) <= 1e-9 * k0, "collide: closed-form loss != state loss",
          c.energy_lost, k0 - k1);
  require(c.j_n >= 0.0, "collide: negative normal impulse", c.j_n);
  require(std::fabs(c.j_t) <= m.mu * c.j_n * (1.0 + 1e-12), "collide: tangential impulse outside the Coulomb cone",
          c.j_t, m.mu * c.j_n);
  const Vec2 t{n.y, -n.x};
  const double slip_after = funnel::dot(c.after.v, t) + m.radius * c.after.omega;
  const double scale = std::fabs(c.q) + std::fabs(m.radius * s.omega) + std::fabs(c.p);
  if (c.regime == funnel::Regime::Sliding) {
    require(std::fabs(std::fabs(c.j_t) - m.mu * c.j_n) <= 1e-12 * m.mu * c.j_n, "collide: sliding |J_t| != mu J_N");
  } else {
    require(std::fabs(slip_after + m.beta0 * c.slip) <= 1e-9 * scale, "collide: sticking s' != -beta0 s",
            slip_after, c.slip);
  }
}

/// One sustained edge contact from an arbitrary start on the circle.
void check_edge_contact(FuzzedDataProvider& f) {
  Material m = pick_material(f);
  const double top = uniform(f, 0.0, 3.14159);
  const double psi = top - uniform(f, 0.0, top);
  const double rate = (f.ConsumeBool() ? 1.0 : -1.0) * std::sqrt(std::sin(psi) / m.radius) * f.ConsumeProbability<double>();
  const double omega = rate + uniform(f, -1.0, 1.0) * log_uniform(f, -6.0, 3.0) / m.radius;
  std::snprintf(context, sizeof context, "edge_contact: mu=%.17g kappa=%.17g radius=%.17g psi=%.17g rate=%.17g omega=%.17g top=%.17g",
                m.mu, m.kappa, m.radius, psi, rate, omega, top);
  State s;
  s.r = {m.radius * std::cos(psi), m.radius * std::sin(psi)};
  s.v = {-m.radius * rate * std::sin(psi), m.radius * rate * std::cos(psi)};
  s.omega = omega;
  if (!(funnel::edge_normal_force(s, {0.0, 0.0}, m.radius) > 0.0)) return;
  const funnel::EdgeContactResult r = funnel::edge_contact(s, {{0.0, 0.0}, top - 3.141592653589793, top}, m);
  require(finite(r.end) && std::isfinite(r.duration) && std::isfinite(r.impulse) && r.duration >= 0.0,
          "edge_contact: non-finite output");
  const double dist = std::hypot(r.end.r.x, r.end.r.y);
  require(std::fabs(dist - m.radius) <= 1e-12 * m.radius, "edge_contact: end off the circle", dist, m.radius);
  const double k0 = funnel::energy(s, m.kappa, m.radius);
  require(r.energy_lost >= -1e-12 * std::fmax(1.0, std::fabs(k0)), "edge_contact: energy gained", r.energy_lost);
  // The impulses are quadratures whose rounding floor is ~eps (1 + mu) times the duration (the
  // forces are O(1 + mu)): a contact that ends at once has impulses at that floor (found by the fuzzer).
  require(std::fabs(r.tangential_impulse) <=
                  m.mu * r.normal_impulse * (1.0 + 1e-9) + 1e-12 * (1.0 + m.mu) * r.duration + 1e-300 ||
              r.last_regime == funnel::Regime::Rolling || r.first_regime == funnel::Regime::Rolling,
          "edge_contact: friction outside the Coulomb cone", r.tangential_impulse, r.normal_impulse);
  if (r.exit == funnel::EdgeExit::TakeOff) {
    const double n = funnel::edge_normal_force(r.end, {0.0, 0.0}, m.radius);
    require(std::fabs(n) <= 1e-6 * std::fmax(1.0, funnel::dot(r.end.v, r.end.v) / m.radius) || r.phases >= 64,
            "edge_contact: take-off with a normal force", n);
  }
}

/// The edge quartic's root (funnel/roots.hpp): for circle approaches of every scale drawn from a
/// generator seeded by the input, the certified refinement gives the reference's double or
/// declines (NaN), and the reference gives the bits of the plain regula falsi loop.
void check_edge_roots(const std::uint8_t* data, std::size_t size) {
  std::uint64_t seed = 0x9e3779b97f4a7c15ULL;
  for (std::size_t i = 0; i < size; ++i) seed = (seed ^ data[i]) * 0x100000001b3ULL;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), expo(-6.0, 3.0);
  for (int k = 0; k < 16; ++k) {
    const double a = std::pow(10.0, expo(rng) / 3.0 - 1.0), speed = std::pow(10.0, expo(rng));
    const double dx = 4 * a * u(rng), dy = 4 * a * u(rng), vx = speed * u(rng), vy = speed * u(rng);
    const std::array<double, 5> c = funnel::test::edge_approach_quartic(dx, dy, vx, vy, a);
    if (!(c[0] > 0.0)) continue;
    const double t_end = std::pow(10.0, expo(rng));
    const auto b = funnel::detail::descending_bracket(c, t_end);
    if (!b) continue;
    std::snprintf(context, sizeof context, "edge root: c = {%a, %a, %a, %a, %a}, bracket [%a, %a]", c[0], c[1], c[2],
                  c[3], c[4], b->lo, b->hi);
    const double plain = funnel::test::plain_refinement(c, b->lo, b->hi, b->flo, b->fhi);
    const double reference = funnel::detail::refine_reference(c, b->lo, b->hi, b->flo, b->fhi);
    require(reference == plain, "edge root: the reference differs from the plain loop", reference, plain);
    const double certified = funnel::detail::refine_certified(c, b->lo, b->hi, b->flo, b->fhi);
    require(certified != certified || certified == reference, "edge root: certified != reference", certified,
            reference);
  }
}

/// Valid parameters from the fuzz bytes, or false when validate() rejects them.
bool pick_params(FuzzedDataProvider& f, Params& p) {
  p = funnel::default_params();
  p.theta = pick_theta(f);
  p.e = pick_e(f);
  p.mu = pick_mu(f);
  p.beta0 = pick_beta0(f);
  p.inertia = log_uniform(f, -3.0, 3.0);
  p.radius = log_uniform(f, -6.0, 0.0);  // 1 itself is rejected
  p.gap = f.ConsumeBool() ? 0.0 : 2.0 * p.radius * (1.0 + log_uniform(f, -12.0, 4.0));
  p.t_max = log_uniform(f, -3.0, 3.0);
  p.max_collisions = f.ConsumeIntegralInRange<std::int64_t>(1, 20000);
  if (f.ConsumeBool()) {  // any 2D funnel's shortcuts: an asymmetric V, a spout
    if (f.ConsumeBool()) p.theta_left = pick_theta(f);
    if (f.ConsumeBool()) p.theta_right = pick_theta(f);
    if (p.gap != 0.0 && f.ConsumeBool()) p.spout_length = log_uniform(f, -6.0, 1.0);
  }
  if (f.ConsumeBool()) {  // a release of the designer's: height, velocity and spin
    p.release_height = log_uniform(f, -3.0, 1.0);
    p.release_u = uniform(f, -1.0, 1.0) * log_uniform(f, -6.0, 1.0);
    p.release_v = uniform(f, -1.0, 1.0) * log_uniform(f, -6.0, 1.0);
    p.release_spin = uniform(f, -1.0, 1.0) * log_uniform(f, -6.0, 1.0) / p.radius;
  }
  return !funnel::validate(p);
}

void check_trajectory(const Params& p, const funnel::Funnel& fn, const State& release, const Trajectory& t,
                      const std::vector<funnel::Event>& events, const funnel::Wear& wear) {
  // The V's own numbers (for an asymmetric V or a spout only what holds for any funnel is checked).
  const Geometry g = funnel::make_geometry(p);
  const bool plain = p.plain_v();
  require(t.status == Status::Exited || t.status == Status::Rest || t.status == Status::Trapped, "bad status");
  require(std::isfinite(t.duration) && std::isfinite(t.impulse) && std::isfinite(t.normal_impulse) &&
              std::isfinite(t.energy_loss) && std::isfinite(t.energy_loss_events) &&
              std::isfinite(t.contact_time) && finite(t.final_state),
          "non-finite observable or final state");
  require(t.duration >= 0.0 && t.duration <= p.t_max, "duration outside [0, t_max]", t.duration, p.t_max);
  require(t.contact_time >= 0.0 && t.contact_time <= t.duration * (1.0 + 1e-12) + 1e-300,
          "contact time outside [0, duration]", t.contact_time, t.duration);
  require(t.collisions >= 0 && t.collisions <= p.max_collisions && t.edge_collisions >= 0 &&
              t.edge_collisions <= t.collisions && t.contacts >= 0 && t.contacts <= t.collisions,
          "collision counts inconsistent");
  require(t.normal_impulse >= 0.0 && t.impulse >= t.normal_impulse * (1.0 - 1e-12), "impulses inconsistent",
          t.impulse, t.normal_impulse);
  if (fn.closed) require(t.status != Status::Exited, "closed funnel exited");
  // An open funnel's particle rests only on a level face (a ledge; here a wall whose angle is
  // so small that its down-slope acceleration underflows), stopped.
  if (!fn.closed && t.status == Status::Rest) {
    require(t.final_state.v.x == 0.0 && t.final_state.v.y == 0.0, "open funnel at rest while moving",
            t.final_state.v.x, t.final_state.v.y);
  }
  // The Zeno guard should never fire (in a closed funnel a pile-up of events at the vertex is
  // rest); trapped is otherwise the time or the collision cap. The exception is a resolution
  // limit, not a bug: in a slot a few ulps of the clock wider than the sphere (d - 2a below
  // ~1e-12, e.g. d = 2a (1 + 1e-12) with a = 1e-6) it bounces between the edges faster than
  // the clock (|t| ~ 1, ulp 2e-16) can tell the collisions apart.
  const Vec2 left_end = fn.sides[0].corners[0].point, right_end = fn.sides[1].corners[0].point;
  const double slot = fn.closed ? 1.0 : 0.5 * std::hypot(right_end.x - left_end.x, right_end.y - left_end.y) - p.radius;
  require(!t.stalled || slot < 1e-12 * std::fmax(1.0, t.duration), "Zeno guard fired", t.duration, slot);
  if (t.status == Status::Trapped && !t.stalled) {
    require(t.duration == p.t_max || t.collisions == p.max_collisions, "trapped before the caps", t.duration,
            static_cast<double>(t.collisions));
  }

  // Energies are of order max(1, |y|): the potential energy is measured from the vertex.
  const double scale = std::fmax(1.0, std::fmax(std::fabs(fn.y_exit), std::fabs(fn.y_release)));
  require(t.energy_loss >= -1e-9 * scale, "energy increased", t.energy_loss, scale);
  require(std::fabs(t.energy_loss - t.energy_loss_events) <= 1e-9 * scale,
          "energy loss != sum of the events' losses", t.energy_loss, t.energy_loss_events);

  const State& s = t.final_state;
  const double e0 = funnel::energy(release, p.inertia, p.radius);
  const double tol = 1e-9 * std::fmax(std::fmax(scale, std::fabs(e0)), fn.half_width);
  require(s.r.y <= e0 + tol, "final state above the height its energy allows", s.r.y, e0);
  // Every free flight, rebuilt from the event log, stays clear of the faces and the edges, and
  // every exit is between the edges (docs/model.md §5b).
  const funnel::FlightAudit audit = funnel::audit_flights(fn, release, events);
  require(audit.edge_overlaps == 0, "a flight came closer than a to an edge point", audit.min_edge_distance);
  require(audit.face_crossings == 0, "a flight went behind a face", audit.max_face_depth);
  require(audit.exits_outside == 0, "an exit outside the gap");
  require(audit.missed_exits == 0, "a flight left the funnel and went on");
  // The wear record sums to the totals.
  double wear_normal = 0.0, wear_collisions = 0.0;
  for (const funnel::WallWear& ww : wear.walls) {
    for (const double x : ww.normal_impulse) wear_normal += x;
    for (const double x : ww.collisions) wear_collisions += x;
    wear_normal += ww.edge_normal_impulse;
    wear_collisions += ww.edge_collisions;
  }
  require(wear_collisions == static_cast<double>(t.collisions), "wear collisions != collisions", wear_collisions);
  require(std::fabs(wear_normal - t.normal_impulse) <= 1e-9 * std::fmax(1.0, t.normal_impulse),
          "wear normal impulse != normal impulse", wear_normal, t.normal_impulse);
  if (t.status == Status::Exited) {
    require(s.r.y == fn.y_exit, "exited off the exit level", s.r.y, fn.y_exit);
    if (!p.profile) {  // a profile's outlet: the audit's exit check above
      // With the audit's tolerance for this funnel: a release line thousands of H long places
      // the particle only to its rounding, far more than a slot's clearance can hold.
      const double exit_tol = funnel::audit_tolerance_for(p.radius, funnel::audit_size(fn));
      require(std::fabs(s.r.x) <= 0.5 * p.gap - p.radius * (1.0 - exit_tol), "exited outside the gap", s.r.x, p.gap);
    }
    // The exit state balances the energy.
    const double at_exit = funnel::energy(t.exit_state, p.inertia, p.radius);
    require(std::fabs(at_exit - (e0 - t.energy_loss)) <= 1e-9 * std::fmax(1.0, std::fabs(e0)),
            "exit state does not balance the energy", at_exit, e0 - t.energy_loss);
  } else if (!plain) {
    // an asymmetric V or a spout: the audit above covers the walls
  } else if (t.status == Status::Rest && fn.closed) {
    // At the vertex: exactly after a sustained contact, else within the energy eps_rest above it.
    require(s.r.y >= -tol && s.r.y <= p.eps_rest + tol, "rest away from the vertex", s.r.x, s.r.y);
  } else if (g.closed || s.r.y >= g.y_face_end) {
    for (const funnel::Wall wall : {funnel::Wall::Left, funnel::Wall::Right}) {
      require(funnel::face_distance(g, wall, s.r) >= -tol, "final state behind a centre line", s.r.x, s.r.y);
    }
  } else {
    require(s.r.y >= g.y_bottom - tol && std::fabs(s.r.x) <= g.half_gap, "final state outside the throat",
            s.r.x, s.r.y);
  }
}

void check_mirror(const Trajectory& a, const Trajectory& b) {
  require(a.status == b.status && a.duration == b.duration && a.impulse == b.impulse &&
              a.normal_impulse == b.normal_impulse && a.energy_loss == b.energy_loss &&
              a.collisions == b.collisions && a.edge_collisions == b.edge_collisions &&
              a.contacts == b.contacts && a.contact_time == b.contact_time,
          "mirror release gives a different result", a.duration, b.duration);
  require(a.final_state.r.x == -b.final_state.r.x && a.final_state.r.y == b.final_state.r.y &&
              a.final_state.v.x == -b.final_state.v.x && a.final_state.v.y == b.final_state.v.y &&
              a.final_state.omega == -b.final_state.omega,
          "mirror release ends in a non-mirror state", a.final_state.r.x, b.final_state.r.x);
  require(a.edge_contacts == b.edge_contacts && a.exit_state.r.x == -b.exit_state.r.x &&
              a.exit_state.v.x == -b.exit_state.v.x && a.exit_state.v.y == b.exit_state.v.y &&
              a.exit_state.omega == -b.exit_state.omega,
          "mirror release exits in a non-mirror state", a.exit_state.r.x, b.exit_state.r.x);
}

using funnel::test::identical;

/// The releases `fractions` of p run together on every SIMD path give the scalar engine's
/// trajectories bit for bit (the batched path of src/batch.cpp; funnels it cannot take run one at
/// a time).
void check_paths(const Params& p, const std::vector<double>& fractions) {
  const funnel::Funnel g = funnel::make_funnel(p);
  std::vector<funnel::State> initial;
  std::vector<Trajectory> expected;
  for (const double x : fractions) {
    initial.push_back(funnel::release_state(p, g, x));
    expected.push_back(funnel::simulate(p, g, initial.back()));
  }
  // A closed funnel's runs also carry the orbit watch of Figs. 11-12 (a short window, so that
  // the periodic orbit is also recognised within the caps).
  const bool watched = p.gap == 0.0;
  const funnel::OrbitTest test{3, 1e-3, 1e-3};
  std::vector<funnel::OrbitWatch> expected_watches(initial.size(), funnel::OrbitWatch(test));
  if (watched) {
    for (std::size_t k = 0; k < initial.size(); ++k) expected[k] = funnel::simulate(p, g, initial[k], &expected_watches[k]);
  }
  static const std::vector<std::string> paths = funnel::simd_paths();
  for (const std::string& path : paths) {
    if (path == "scalar") continue;
    funnel::set_simd_path(path);
    std::vector<Trajectory> got(initial.size());
    std::vector<funnel::OrbitWatch> watches(initial.size(), funnel::OrbitWatch(test));
    if (watched) {
      funnel::simulate_many(p, g, initial, got, watches);
    } else {
      funnel::simulate_many(p, g, initial, got);
    }
    for (std::size_t k = 0; k < got.size(); ++k) {
      const Trajectory& a = got[k];
      const Trajectory& b = expected[k];
      require(identical(a, b), "a SIMD path gives another result than the scalar engine", a.duration, b.duration);
      if (watched) {
        const funnel::OrbitWatch::Memory& m = watches[k].memory();
        const funnel::OrbitWatch::Memory& e = expected_watches[k].memory();
        require(a.stopped == b.stopped && m.streak == e.streak && m.have_last == e.have_last &&
                    m.last_wall == e.last_wall && m.last.x == e.last.x && m.last.y == e.last.y &&
                    m.prev.x == e.prev.x && m.prev.y == e.prev.y,
                "a SIMD path watches the orbit differently from the scalar engine", m.last.y, e.last.y);
      }
    }
  }
  funnel::set_simd_path(paths.back());
}

/// A segment's angle to the horizontal, degrees: ledges, spouts, and everything between.
double pick_segment_angle(FuzzedDataProvider& f) {
  switch (f.ConsumeIntegralInRange<int>(0, 4)) {
    case 0: return 0.0;   // a ledge
    case 1: return 90.0;  // a spout
    case 2: return log_uniform(f, -6.0, 1.0);
    case 3: return 90.0 - log_uniform(f, -6.0, 1.0);
    default: return 90.0 * f.ConsumeProbability<double>();
  }
}

/// One wall's surface from its lower end `end` up: 1 to 4 segments of random angles (0 to 90
/// degrees, no overhang) and lengths; `sign` -1 builds a left wall, +1 a right one. Returned
/// from the top down, as a geometry file lists it.
std::vector<Vec2> pick_wall(FuzzedDataProvider& f, Vec2 end, double sign) {
  std::vector<Vec2> up{end};
  const int segments = f.ConsumeIntegralInRange<int>(1, 4);
  for (int k = 0; k < segments; ++k) {
    const double angle = pick_segment_angle(f) * 3.141592653589793 / 180.0;
    const double length = log_uniform(f, -4.0, 0.5);
    const Vec2 last = up.back();
    up.push_back({last.x + sign * length * std::cos(angle), last.y + length * std::sin(angle)});
  }
  return {up.rbegin(), up.rend()};
}

/// One release of p (with `bins` wear bins): the invariants of check_trajectory; then, unless
/// it is on the axis, the mirror release -fraction in `mirror` (p's mirror funnel, set by the
/// caller) with the horizontal velocity and spin negated gives the mirror result. A release on
/// the axis at rest is its own mirror image; a tie between the walls goes to the left one.
void check_release(const Params& p, Params mirror, double fraction, int bins) {
  const funnel::Funnel g = funnel::make_funnel(p);
  funnel::EventLog log;
  funnel::Wear wear = funnel::Wear::make(g, bins);
  const Trajectory t = funnel::simulate_release(p, g, fraction, &log, &wear);
  check_trajectory(p, g, funnel::release_state(p, g, fraction), t, log.events, wear);
  mirror.release_u = 0.0 - p.release_u;
  mirror.release_spin = 0.0 - p.release_spin;
  if (fraction != 0.0) check_mirror(t, funnel::simulate_release(mirror, funnel::make_funnel(mirror), -fraction));
  if (!t.slid) {
    // A run that did not slide is the same for every larger mu (docs/model.md §4; sweeps over mu
    // reuse it): here at the next double, twice and a thousand times p's mu.
    for (const double mu : {std::nextafter(p.mu, 1e300), 2.0 * p.mu + 1e-3, 1e3 * p.mu + 1.0}) {
      Params more = p;
      more.mu = mu;
      const Trajectory u = funnel::simulate_release(more, funnel::make_funnel(more), fraction);
      require(identical(t, u), "a run that did not slide changes with a larger mu", p.mu, mu);
    }
  }
}

/// A release in a random wall profile (docs/model.md §2b): walls of ledges, spouts, wedges and
/// corners, an outlet of any width (or closed), lower ends at different heights, a material per
/// wall; profiles that validate() rejects are skipped. The invariants of any funnel, and the
/// mirror release in the mirror profile gives the mirror result.
void check_profile(FuzzedDataProvider& f, Params p) {
  p.theta_left = Params::unset;
  p.theta_right = Params::unset;
  p.spout_length = 0.0;
  auto spec = std::make_shared<funnel::ProfileSpec>();
  const bool closed = f.ConsumeBool();
  const double half = closed ? 0.0 : p.radius * (1.0 + log_uniform(f, -12.0, 2.0));
  const double drop = f.ConsumeBool() ? 0.0 : uniform(f, -0.3, 0.3);  // the right lower end's height
  std::vector<Vec2> left = pick_wall(f, {-half, 0.0}, -1.0);
  if (f.ConsumeBool()) {
    *spec = funnel::mirrored_profile(std::move(left));
  } else {
    spec->sides[0] = std::move(left);
    spec->sides[1] = pick_wall(f, {half, closed ? 0.0 : drop}, 1.0);
  }
  if (f.ConsumeBool()) {  // a material of its own for the right wall
    spec->e[1] = pick_e(f);
    spec->mu[1] = pick_mu(f);
    spec->beta0[1] = pick_beta0(f);
  }
  spec->source = "fuzz";
  p.profile = spec;
  if (funnel::validate(p)) return;
  const double fraction = uniform(f, -1.0, 1.0);
  if (!(fraction > -1.0 && fraction < 1.0)) return;
  char walls[192];
  std::snprintf(walls, sizeof walls, " profile: left %zu, right %zu vertices, top-left (%.17g, %.17g), closed %d",
                spec->sides[0].size(), spec->sides[1].size(), spec->sides[0][0].x, spec->sides[0][0].y, closed);
  std::snprintf(context, sizeof context,
                "--e %.17g --mu %.17g --beta0 %.17g --inertia %.17g --radius %.17g --t-max %.17g "
                "--max-collisions %lld --release %.17g --release-height %.17g%s",
                p.e, p.mu, p.beta0, p.inertia, p.radius, p.t_max, static_cast<long long>(p.max_collisions),
                fraction, p.release_height, walls);
  Params mirror = p;
  mirror.profile = std::make_shared<funnel::ProfileSpec>(funnel::mirror_image(*spec));
  check_release(p, mirror, fraction, 5);
  // The lanes take the flights between the top faces of a profile whose corners are all edges
  // (src/engine.cpp batchable): the same bits as the scalar engine's, on every path.
  check_paths(p, {fraction, 0.0 - fraction, 0.5 * fraction, 0.5 - 0.25 * fraction});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider f(data, size);
  check_collision(f);
  check_edge_contact(f);
  check_edge_roots(data, size);

  Params p;
  if (!pick_params(f, p)) return 0;
  const double fraction = f.ConsumeBool() ? uniform(f, -1.0, 1.0)
                                          : (f.ConsumeBool() ? 1.0 : -1.0) * (1.0 - log_uniform(f, -16.0, 0.0));
  if (!(fraction > -1.0 && fraction < 1.0)) return 0;
  std::snprintf(context, sizeof context,
                "--theta %.17g --e %.17g --mu %.17g --beta0 %.17g --inertia %.17g --radius %.17g --gap %.17g "
                "--t-max %.17g --max-collisions %lld --release %.17g --release-height %.17g --release-u %.17g "
                "--release-v %.17g --release-spin %.17g --theta-left %.17g --theta-right %.17g --spout-length %.17g",
                p.theta, p.e, p.mu, p.beta0, p.inertia, p.radius, p.gap, p.t_max,
                static_cast<long long>(p.max_collisions), fraction, p.release_height, p.release_u, p.release_v,
                p.release_spin, p.left_angle(), p.right_angle(), p.spout_length);
  // The mirror funnel of an asymmetric V swaps its walls' angles.
  Params mirror = p;
  mirror.theta_left = p.theta_right;
  mirror.theta_right = p.theta_left;
  check_release(p, mirror, fraction, 7);
  check_paths(p, {fraction, 0.0 - fraction, 0.5 * fraction, 0.5 - 0.25 * fraction});
  // Inputs with bytes left over run a random wall profile too (consumed last, so that the
  // seeds of the V keep their meaning).
  if (f.remaining_bytes() > 0 && f.ConsumeBool()) check_profile(f, p);
  return 0;
}
