// Sustained contact in the axisymmetric funnel off a meridian plane: the equations of motion on
// the cone face and on the rim torus, integrated with dense output (the closed forms of a motion
// in a meridian plane are in contact3d.cpp).
//
// Coordinates: the azimuth phi (right-handed about +y: e_rho = (cos phi, 0, -sin phi),
// e_phi = dr/dphi = (-sin phi, 0, -cos phi)), the surface's meridian coordinate q, its rate, the
// orbital angular momentum about the axis h = rho^2 phi' (rho: the centre's distance from the
// axis), and the spin vector omega. Per unit mass, with F the friction force (tangential):
//   face (q = l, the distance from the centre cone's apex along its generator; rho = l cos,
//   y = l sin; tangent e_s = cos e_rho + sin y_hat, normal n = -sin e_rho + cos y_hat):
//     l'' = rho phi'^2 cos - sin + F.e_s,   h' = rho F.e_phi,   N = cos + rho phi'^2 sin > 0
//   rim (q = psi, n = cos psi e_rho + sin psi y_hat from the rim point to the centre, rho =
//   R + a cos psi, tangent e_psi = -sin psi e_rho + cos psi y_hat):
//     a psi'' = -cos psi - rho phi'^2 sin psi + F.e_psi,   h' = rho F.e_phi,
//     N = sin psi - a psi'^2 - rho phi'^2 cos psi          (contact while N > 0)
//   spin: kappa a omega' = -n x F; slip s = v - a omega x n;
//   sliding F = -mu N s/|s|; rolling F = -kappa/(1 + kappa) P_t(g - a omega x n'), while
//   |F| <= mu N (static friction), which keeps s = 0.
#include "contact3d_integrate.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/math/tools/roots.hpp>
#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/dense_output_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>

namespace funnel {

namespace {

namespace odeint = boost::numeric::odeint;

/// The integrated state: q, phi, q', h, omega (3), integral of N dt, integral of sqrt(N^2 + F^2) dt.
using Y = std::array<double, 9>;
enum : std::size_t { Q = 0, PHI = 1, QD = 2, H = 3, WX = 4, WY = 5, WZ = 6, IN = 7, IF = 8 };

/// In a closed cone, a sustained contact has reached the vertex once its energy above the vertex
/// is below this many radii (times m g): it can never again rise further from the vertex than
/// that (docs/model.md §9). A ball that still turns about the axis spirals into the vertex ever
/// faster (h = rho^2 phi' is only slowly lost to friction): integrated until its energy is below
/// eps_rest, its steps would not end (20 million of them took a ball from 1.2e-9 to 3e-10 H of
/// the vertex). A ball that only passes near the axis keeps its energy and goes on.
constexpr double vertex_reach = 1e-4;
/// In a closed cone, a face contact has also reached the vertex once its centre is this many radii
/// from it (along the generator of the centre's cone), whatever its energy: a spin about a
/// horizontal axis keeps the energy above vertex_reach a (for ever with mu = 0), and a ball that
/// spirals in with a little angular momentum about the axis would be integrated ever more finely
/// (phi' = h / rho^2) until the step guard. A ball that passes close to the axis with its energy
/// comes far nearer than any such pass (1e-5 a in the tests) only by aiming at the vertex.
constexpr double vertex_close = 1e-9;
/// Phase changes after which a contact is ended as TimeCap: a guard against chattering between
/// rolling and sliding, never reached in the tests.
constexpr int max_phases = 100000;
/// Dense-output samples per step at which the event functions are checked for a sign change.
constexpr int samples_per_step = 4;
/// A slip below this fraction of |v| + a|omega| is zero: far above the integrator's error on it
/// (~1e-12) and far below any slip that matters. The onset of sliding ends above grown_slip (a
/// hysteresis, so that the two never alternate).
constexpr double zero_slip = 1e-10;
constexpr double grown_slip = 1e-9;

/// Everything about the motion at one state that the equations and the events need.
struct Kin {
  Vec3 r, v, n, e1, e_phi, n_dot;
  double rho = 0.0, phi_dot = 0.0, normal = 0.0;  // normal: N per unit mass
  double q_free = 0.0;   // q'' without friction
  double q_scale = 1.0;  // q'' += q_scale F.e1
};

/// Friction regimes: none (mu = 0), sliding, the onset of sliding from zero slip (the slip still
/// within rounding of 0, growing along the drive), rolling without slip.
enum class Mode { Free, Sliding, Onset, Rolling };

/// The surface of a contact (cone face or rim torus) and the material.
struct Surface {
  bool torus = false;
  double sin_t = 0.0, cos_t = 0.0, R = 0.0, y_b = 0.0, a = 0.0, kappa = 0.4, mu = 0.0;

  Kin kin(const Y& y) const { return kin(y, std::cos(y[PHI]), std::sin(y[PHI])); }

  /// kin(y) given c = cos(y[PHI]) and s = sin(y[PHI]). Inlined into each caller, so that the
  /// parts a caller does not use are never computed (the events need the frame and the normal
  /// force, not the position): 7% of the costliest point of fig3d, the same values.
  [[gnu::always_inline]] Kin kin(const Y& y, double c, double s) const {
    Kin k;
    const Vec3 e_rho{c, 0.0, -s}, up{0.0, 1.0, 0.0};
    k.e_phi = {-s, 0.0, -c};
    if (!torus) {
      k.rho = y[Q] * cos_t;
      k.phi_dot = y[H] / (k.rho * k.rho);
      k.e1 = cos_t * e_rho + sin_t * up;
      k.n = -sin_t * e_rho + cos_t * up;
      k.r = k.rho * e_rho + (y[Q] * sin_t) * up;
      k.v = y[QD] * k.e1 + (k.rho * k.phi_dot) * k.e_phi;
      const double centripetal = k.rho * k.phi_dot * k.phi_dot;
      k.normal = cos_t + centripetal * sin_t;
      k.q_free = centripetal * cos_t - sin_t;
      k.q_scale = 1.0;
      k.n_dot = (-sin_t * k.phi_dot) * k.e_phi;
    } else {
      const double cp = std::cos(y[Q]), sp = std::sin(y[Q]);
      k.rho = R + a * cp;
      k.phi_dot = y[H] / (k.rho * k.rho);
      k.n = cp * e_rho + sp * up;
      k.e1 = -sp * e_rho + cp * up;
      k.r = R * e_rho + y_b * up + a * k.n;
      k.v = (a * y[QD]) * k.e1 + (k.rho * k.phi_dot) * k.e_phi;
      const double centripetal = k.rho * k.phi_dot * k.phi_dot;
      k.normal = sp - a * y[QD] * y[QD] - centripetal * cp;
      k.q_free = (-cp - centripetal * sp) / a;
      k.q_scale = 1.0 / a;
      k.n_dot = y[QD] * k.e1 + (cp * k.phi_dot) * k.e_phi;
    }
    return k;
  }

  static Vec3 omega(const Y& y) { return {y[WX], y[WY], y[WZ]}; }

  /// The centre's distance from the axis.
  double rho(const Y& y) const { return torus ? R + a * std::cos(y[Q]) : y[Q] * cos_t; }

  Vec3 slip(const Kin& k, const Y& y) const { return k.v - a * cross(omega(y), k.n); }

  /// Tangential part of g - a omega x n': the slip's rate without friction, per (1 + 1/kappa).
  Vec3 drive(const Kin& k, const Y& y) const {
    const Vec3 g = Vec3{0.0, -1.0, 0.0} - a * cross(omega(y), k.n_dot);
    return g - dot(g, k.n) * k.n;
  }

  Vec3 rolling_force(const Kin& k, const Y& y) const { return (-kappa / (1.0 + kappa)) * drive(k, y); }

  /// mu N - |F_rolling|: static friction holds rolling while > 0.
  double rolling_margin(const Kin& k, const Y& y) const { return mu * k.normal - norm(rolling_force(k, y)); }

  /// Friction force in a mode. Sliding uses s/|s| continued through s = 0 along the reference
  /// direction d (the slip's direction at the start of the step): past the zero the force keeps
  /// its direction, so the right-hand side stays continuous and a step can cross the zero, which
  /// is then located on the dense output. At the onset of sliding the slip's direction is not yet
  /// defined beyond rounding: the force acts against d, the direction the slip grows in.
  Vec3 friction(const Kin& k, const Y& y, Mode mode, Vec3 d) const {
    if (mode == Mode::Free) return {};
    if (mode == Mode::Rolling) return rolling_force(k, y);
    const Vec3 s = slip(k, y);
    const double size = norm(s);
    const Vec3 dir = mode == Mode::Sliding && size > 0.0 ? (dot(s, d) >= 0.0 ? 1.0 : -1.0) / size * s
                                                         : d - dot(d, k.n) * k.n;
    return (-mu * k.normal) * dir;
  }

  /// The equations of motion at y, given c = cos(y[PHI]) and s = sin(y[PHI]).
  void rhs(const Y& y, Y& dy, Mode mode, Vec3 d, double c, double s) const {
    const Kin k = kin(y, c, s);
    const Vec3 f = friction(k, y, mode, d);
    dy[Q] = y[QD];
    dy[PHI] = k.phi_dot;
    dy[QD] = k.q_free + k.q_scale * dot(f, k.e1);
    dy[H] = k.rho * dot(f, k.e_phi);
    const Vec3 w_dot = (-1.0 / (kappa * a)) * cross(k.n, f);
    dy[WX] = w_dot.x;
    dy[WY] = w_dot.y;
    dy[WZ] = w_dot.z;
    dy[IN] = k.normal;
    dy[IF] = std::sqrt(k.normal * k.normal + dot(f, f));
  }

  State3 state(const Y& y) const {
    const Kin k = kin(y);
    return {k.r, k.v, omega(y)};
  }
};

/// The integrator's error test: odeint's, |error| <= abs + rel (|x| + |dt x'|) for every
/// component, with two guards for the motion near the axis, where the azimuth's rate h / rho^2 and
/// the centripetal acceleration h^2 / rho^3 grow without bound:
/// - the absolute tolerance of the meridian coordinate q and of the angular momentum h never
///   exceeds rel times the centre's distance rho from the axis, the scale of the motion there (the
///   energy h^2 / 2 rho^2 depends on both relative to rho; measured, a small gain: passes 1e-11 to
///   1e-9 H from the axis kept their energy to 5.2e-11 instead of 5.7e-11);
/// - on a closed cone's face, a step may cover at most half the distance to the vertex
///   (|q'| dt + |q''| dt^2 / 2 <= q / 2), else it is rejected as if its error were too large (and
///   shortened to about that distance): a ball with a tiny angular momentum passes the axis at
///   rho ~ h / v, and a long step of a smooth descent stepped over that pass, through the vertex
///   into the cone's mirror image, where the stages never sampled the centrifugal barrier
///   (docs/robustness.md, finding 28).
/// Beyond rho = abs / rel (1e-2 H) and that distance the test is odeint's, bit for bit.
class AxisErrorChecker {
 public:
  AxisErrorChecker(double abs_tol, double rel_tol, const Surface& sf, bool closed)
      : abs_(abs_tol),
        rel_(rel_tol),
        sf_(&sf),
        closed_face_(closed && !sf.torus),
        far_(sf.torus && rel_tol * (sf.R - sf.a) >= abs_tol) {}

  template <class Algebra>
  double error(Algebra& /*algebra*/, const Y& x_old, const Y& dxdt_old, Y& x_err, double dt) const {
    // (A rim torus whose inner edge is 1e-2 H or more from the axis is never near it.)
    const double near = far_ ? abs_ : std::fmin(abs_, rel_ * std::fabs(sf_->rho(x_old)));
    const double step = std::fabs(dt);
    double worst = 0.0;
    for (std::size_t i = 0; i < x_err.size(); ++i) {
      const double abs_i = i == Q || i == H ? near : abs_;
      x_err[i] = std::fabs(x_err[i]) / (abs_i + rel_ * (std::fabs(x_old[i]) + step * std::fabs(dxdt_old[i])));
      worst = std::fmax(worst, x_err[i]);
    }
    if (closed_face_) {
      const double reach = std::fabs(x_old[QD]) * step + 0.5 * std::fabs(dxdt_old[QD]) * step * step;
      const double ratio = reach / (0.5 * x_old[Q]);
      // Cubed: the controller then shortens the step by about the ratio (dopri5's error ~ dt^5
      // is shrunk with the power -1/3 of a rejected step's error).
      if (ratio > 1.0) worst = std::fmax(worst, ratio * ratio * ratio);
    }
    return worst;
  }

 private:
  double abs_, rel_;
  const Surface* sf_;
  bool closed_face_, far_;
};

using Dopri5 = odeint::runge_kutta_dopri5<Y>;
using Controlled = odeint::controlled_runge_kutta<Dopri5, AxisErrorChecker>;
using DenseOutput = odeint::dense_output_runge_kutta<Controlled>;

/// Coordinates of a 3D state on a surface.
Y coordinates(const Surface& sf, const State3& s) {
  Y y{};
  const double rho = axis_distance(s.r);
  y[PHI] = std::atan2(-s.r.z, s.r.x);
  const Vec3 e_rho{std::cos(y[PHI]), 0.0, -std::sin(y[PHI])};
  const Vec3 e_phi{-std::sin(y[PHI]), 0.0, -std::cos(y[PHI])};
  const Vec3 up{0.0, 1.0, 0.0};
  if (!sf.torus) {
    y[Q] = rho / sf.cos_t;
    y[QD] = dot(s.v, sf.cos_t * e_rho + sf.sin_t * up);
    y[H] = rho * dot(s.v, e_phi);
  } else {
    const double psi = std::atan2(s.r.y - sf.y_b, rho - sf.R);
    y[Q] = psi;
    y[QD] = dot(s.v, -std::sin(psi) * e_rho + std::cos(psi) * up) / sf.a;
    y[H] = (sf.R + sf.a * std::cos(psi)) * dot(s.v, e_phi);
  }
  y[WX] = s.omega.x;
  y[WY] = s.omega.y;
  y[WZ] = s.omega.z;
  return y;
}

/// Why an integrated phase ended.
enum class Stop { Grown, End, RimTop, TakeOff, Exit, Rest, Cap, SlipZero, RollLimit, Minimum };

/// A conservative phase's last radial minimum (q' from < 0 to >= 0) and the radial extent since:
/// a second minimum with the same radial state closes a period of the reduced motion, which then
/// repeats forever (energy and the conserved quantities fix it).
struct LastMinimum {
  bool have = false;
  double t = 0.0, q = 0.0, h = 0.0, wn = 0.0, in = 0.0, f = 0.0, phi = 0.0;
  double q_max = -std::numeric_limits<double>::infinity(), q_low = std::numeric_limits<double>::infinity();

  /// Whether a minimum at `time` in state x (omega.n = wn) repeats this one, to 1e-8 relative. A
  /// circular orbit (no amplitude) is not a period. Rolling also needs the spin about the normal
  /// to repeat; without friction (`spin_free`) the spin never acts on the motion (a spin about a
  /// horizontal axis changes omega.n round the cone, and its contacts were integrated to the
  /// budget).
  bool repeated_by(double time, const Y& x, double wn_now, bool spin_free) const {
    const double tol = 1e-8;
    return have && std::fabs(x[Q] - q) <= tol * std::fabs(q) && std::fabs(x[H] - h) <= tol * (std::fabs(h) + 1e-12) &&
           (spin_free || std::fabs(wn_now - wn) <= tol * (std::fabs(wn) + 1.0)) && q_max - q_low > 1e-7 * std::fabs(q) &&
           time > t;
  }

  void record(double time, const Y& x, double wn_now) {
    have = true;
    t = time;
    q = x[Q];
    h = x[H];
    wn = wn_now;
    in = x[IN];
    f = x[IF];
    phi = x[PHI];
    q_max = x[Q];
    q_low = x[Q];
  }

  void extend(double q_now) {
    q_max = std::max(q_max, q_now);
    q_low = std::min(q_low, q_now);
  }
};

/// The running integrated contact.
class Integrated {
 public:
  Integrated(const Surface& sf, const Cone& cone, const Material& m, const Contact3Options& opt)
      : sf_(sf), cone_(cone), m_(m), opt_(opt) {
    // The face's lower end: C* in an open cone, the vertex (the apex of the centre's cone, l = 0,
    // within vertex_close a) in a closed one, where the contact ends at rest (docs/model.md §5).
    q_end_ = cone.g.closed ? vertex_close * m.radius : cone.g.x_face_end / cone.g.cos_t;
    psi_top_ = 0.5 * std::numbers::pi + std::atan2(cone.g.sin_t, cone.g.cos_t);
  }

  Contact3Result run(const State3& start) {
    Y y = coordinates(sf_, start);
    const double e_start = energy(start, m_.kappa, m_.radius);
    double t = 0.0;
    if (!sf_.torus && cone_.g.closed && !(y[Q] > q_end_)) {
      // A face contact that starts at the vertex (within vertex_close a: e.g. after a collapse
      // onto it) has reached it: at rest there. (The azimuth's rate h / rho^2 is undefined at
      // rho = 0.)
      res_.how = Contact3End::Rest;
      res_.end = start;
      return res_;
    }
    Mode mode = initial_mode(y);
    res_.first_regime = regime(mode);
    double dt = 1e-4;
    for (;;) {
      res_.last_regime = regime(mode);
      if (++res_.phases > max_phases) {
        res_.how = Contact3End::TimeCap;
        break;
      }
      const Stop why = phase(y, t, mode, dt);
      if (why == Stop::SlipZero) {
        if (mode == Mode::Onset) {
          // Static friction can hold rolling again, but the slip may no longer be zero (it grows
          // during the onset, whose end is checked only at the start of each step): then the
          // ball slides, and friction must take that slip away. Rolling at once would discard it,
          // and with it its energy, of either sign (docs/robustness.md, finding 25: a ball crossing
          // a narrow ring's rim gained 9e-7 m g H at each pass).
          const Kin k = sf_.kin(y);
          const Vec3 s = sf_.slip(k, y);
          if (norm(s) > zero_slip * slip_scale(k, y)) {
            reference_ = unit(s);
            mode = Mode::Sliding;
            continue;
          }
        }
        mode = zero_slip_mode(y);
        continue;
      }
      if (why == Stop::Grown) {
        mode = Mode::Sliding;
        continue;
      }
      if (why == Stop::RollLimit) {
        mode = Mode::Onset;
        reference_ = unit(sf_.drive(sf_.kin(y), y));
        continue;
      }
      {
        // A closed cone's face ends at the vertex, where the contact ends at rest.
        res_.how = why == Stop::End       ? (cone_.g.closed ? Contact3End::Rest : Contact3End::FaceEnd)
                   : why == Stop::RimTop  ? Contact3End::RimTop
                   : why == Stop::TakeOff ? Contact3End::TakeOff
                   : why == Stop::Exit    ? Contact3End::Exit
                   : why == Stop::Rest    ? Contact3End::Rest
                   : why == Stop::Minimum ? Contact3End::Periodic
                                          : Contact3End::TimeCap;
        break;
      }
    }
    if (res_.how != Contact3End::Periodic) {
      res_.duration = t;
      res_.normal_impulse = y[IN];
      res_.impulse = y[IF];
      res_.swept = y[PHI] - phi_start_;
    }
    if (res_.how == Contact3End::Rest && !sf_.torus && !(y[Q] > q_end_)) {
      // At the vertex (within vertex_close a of it): the centre placed there, as the 2D contact
      // ends exactly at the corner, with its velocity along the generator (rho phi' = h / rho is
      // undefined at rho = 0).
      const double c = std::cos(y[PHI]), s = std::sin(y[PHI]);
      res_.end = {Vec3{}, y[QD] * Vec3{sf_.cos_t * c, sf_.sin_t, -sf_.cos_t * s}, Surface::omega(y)};
    } else {
      res_.end = sf_.state(y);
    }
    res_.contact_impulse = res_.end.v - start.v + Vec3{0.0, res_.duration, 0.0};
    res_.energy_lost = e_start - energy(res_.end, m_.kappa, m_.radius);
    return res_;
  }

 private:
  static Regime regime(Mode m) { return m == Mode::Rolling ? Regime::Rolling : Regime::Sliding; }

  /// Near the axis: closer to it than abs_tol / rel_tol (1e-2 H), where the error test of q and h
  /// becomes relative (AxisErrorChecker) and the motion's scale is the distance itself.
  bool near_axis(const Y& y) const { return sf_.rho(y) * opt_.rel_tol < opt_.abs_tol; }

  /// The scale of slip velocities: |v| + a |omega|.
  double slip_scale(const Kin& k, const Y& y) const { return norm(k.v) + m_.radius * norm(Surface::omega(y)); }


  static Vec3 unit(Vec3 v) {
    const double size = norm(v);
    return size > 0.0 ? (1.0 / size) * v : Vec3{};
  }

  Mode initial_mode(Y& y) {
    if (m_.mu == 0.0) return Mode::Free;
    const Kin k = sf_.kin(y);
    const Vec3 s = sf_.slip(k, y);
    // A slip within the integrator's error of zero is zero (e.g. after a sticking collision with
    // beta0 = 0, or handed over from rolling).
    if (norm(s) <= zero_slip * slip_scale(k, y)) return zero_slip_mode(y);
    reference_ = unit(s);
    return Mode::Sliding;
  }

  /// At zero slip: rolling if static friction can hold it (the slip is then made exactly 0),
  /// else sliding in the direction the slip grows.
  Mode zero_slip_mode(Y& y) {
    if (m_.mu == 0.0) return Mode::Free;
    const Kin k = sf_.kin(y);
    if (sf_.rolling_margin(k, y) >= 0.0) {
      // omega = (omega.n) n + (n x v)/a makes s = v - a omega x n vanish.
      const Vec3 w = Surface::omega(y);
      const Vec3 rolled = dot(w, k.n) * k.n + (1.0 / m_.radius) * cross(k.n, k.v);
      y[WX] = rolled.x;
      y[WY] = rolled.y;
      y[WZ] = rolled.z;
      return Mode::Rolling;
    }
    reference_ = unit(sf_.drive(k, y));
    return Mode::Onset;
  }

  /// Event functions, each positive while the phase goes on; the phase stops at the first to
  /// reach <= 0.
  struct Events {
    std::array<double, 8> f{};
  };
  static constexpr std::array<Stop, 8> kinds{Stop::End,  Stop::RimTop,    Stop::TakeOff,  Stop::Exit,
                                            Stop::Rest, Stop::SlipZero,  Stop::RollLimit, Stop::Minimum};

  Events events(const Y& y, Mode mode) const {
    constexpr double off = 1.0;  // the value of an event function that does not apply
    Events e;
    e.f.fill(off);
    const Kin k = kin_at(y);
    if (!sf_.torus) {
      e.f[0] = y[Q] - q_end_;
    } else {
      e.f[1] = y[Q] - psi_top_;
      e.f[2] = k.normal;
      e.f[3] = std::numbers::pi - y[Q];
    }
    // A closed cone's contact ends at rest when the energy above the vertex is below eps_rest or
    // below vertex_reach a: the centre can then never rise more than vertex_reach a above the
    // vertex again (a contact only loses energy, and so do collisions), so it has reached it.
    // Without friction the spin is never exchanged with the motion of the centre: its energy
    // does not count towards the vertex_reach test (a spinning ball that orbited 4e-9 a from the
    // vertex went on to the step guard).
    if (cone_.g.closed) {
      const State3 st = sf_.state(y);
      const double e_all = energy(st, m_.kappa, m_.radius);
      e.f[4] = e_all - std::fmax(opt_.eps_rest, vertex_reach * m_.radius);
      if (m_.mu == 0.0) {
        const double spin = 0.5 * m_.kappa * m_.radius * m_.radius * dot(st.omega, st.omega);
        e.f[4] = std::fmin(e.f[4], (e_all - spin) - vertex_reach * m_.radius);
      }
    }
    // Sliding: the slip's zero. Onset: static friction becoming able to hold rolling again (the
    // slip is still 0 within rounding), which also goes to the zero-slip decision.
    if (mode == Mode::Sliding) e.f[5] = dot(sf_.slip(k, y), reference_);
    if (mode == Mode::Onset) e.f[5] = -sf_.rolling_margin(k, y);
    if (mode == Mode::Rolling) e.f[6] = sf_.rolling_margin(k, y);
    if (opt_.detect_periodic && (mode == Mode::Free || mode == Mode::Rolling)) e.f[7] = -y[QD];
    return e;
  }

  /// kin(y), with the sine and cosine of the azimuth of the last evaluation of the equations of
  /// motion when that was at y's azimuth (compared as bits): the state at the end of a step, whose
  /// equations the stepper evaluates last (first same as last), is scanned for events and, while
  /// sliding, checked for the slip's size at the next step's start.
  [[gnu::always_inline]] Kin kin_at(const Y& y) const {
    const bool same = have_last_ && std::bit_cast<std::uint64_t>(y[PHI]) == std::bit_cast<std::uint64_t>(last_phi_);
    const double c = same ? last_cos_ : std::cos(y[PHI]);
    const double s = same ? last_sin_ : std::sin(y[PHI]);
    return sf_.kin(y, c, s);
  }

  /// The step-size controlled Dormand-Prince stepper with this contact's error test.
  Controlled controlled() const {
    return Controlled(AxisErrorChecker(opt_.abs_tol, opt_.rel_tol, sf_, cone_.g.closed),
                      odeint::default_step_adjuster<double, double>(), Dopri5());
  }

  /// Integrates one phase from (y, t) in `mode` until a stopping event or the budget; returns why.
  Stop phase(Y& y, double& t, Mode mode, double& dt) {
    DenseOutput stepper(controlled());
    auto system = [&](const Y& x, Y& dx, double) {
      have_last_ = true;
      last_phi_ = x[PHI];
      last_cos_ = std::cos(last_phi_);
      last_sin_ = std::sin(last_phi_);
      sf_.rhs(x, dx, mode, reference_, last_cos_, last_sin_);
    };
    // The state at a time inside the last step at which the contact ends (a period's second
    // minimum, the budget). Near the axis it is integrated over [t0, time] from the step's start
    // with the same error test rather than read off the dense output, whose error is not
    // controlled: there the energy is so sensitive to q that an interpolated minimum moved it by
    // 3e-9 (docs/robustness.md, finding 28).
    auto land = [&](double t0, double time) {
      if (time == stepper.current_time()) return stepper.current_state();
      Y x;
      stepper.calc_state(time, x);
      if (!near_axis(x)) return x;
      x = stepper.previous_state();
      if (time > t0) {
        Controlled over = controlled();
        odeint::integrate_adaptive(over, system, x, t0, time, time - t0);
      }
      return x;
    };
    stepper.initialize(y, t, dt);
    Events prev = events(y, mode);
    // A boundary of the surface (C*, the outlet's level) that the contact starts on, within
    // rounding, counts as not yet reached: e.g. a contact handed over at C* moving away from it.
    // Any other function that starts negative ends the phase at once (e.g. a rim contact without
    // normal force, rolling that static friction cannot hold); one that starts at 0 goes on.
    constexpr std::array<bool, 8> boundary{true, true, false, true, false, false, false, false};
    for (std::size_t i = 0; i + 1 < kinds.size(); ++i) {
      if (boundary[i] && prev.f[i] <= 1e-12) prev.f[i] = std::numeric_limits<double>::min();
      if (prev.f[i] < 0.0) return kinds[i];
      if (prev.f[i] == 0.0) prev.f[i] = std::numeric_limits<double>::min();
    }
    LastMinimum last;
    for (;;) {
      if (mode != Mode::Free && mode != Mode::Rolling) {
        const Y& x = stepper.current_state();
        const Kin k = kin_at(x);
        const Vec3 s = sf_.slip(k, x);
        const double size = norm(s);
        if (mode == Mode::Onset) {
          // The onset ends once the slip has grown beyond rounding (at the rolling limit it grows
          // quadratically); its direction is then defined and sliding proper begins.
          if (size > grown_slip * slip_scale(k, x)) {
            y = x;
            t = stepper.current_time();
            reference_ = unit(s);
            return Stop::Grown;
          }
        } else if (size <= zero_slip * slip_scale(k, x)) {
          // Down to the integrator's error without a located zero (its direction is then noise):
          // the slip has vanished.
          y = x;
          t = stepper.current_time();
          return Stop::SlipZero;
        } else {
          // The reference direction follows the slip from step to step (the force is the same).
          reference_ = unit(s);
          prev.f[5] = size;
        }
      }
      const auto [t0, t1] = stepper.do_step(system);
      ++res_.steps;
      // The next phase starts with the step just taken. A step shorter than an ulp of the time
      // (near the axis, at a kink of the friction) takes none: a step size of 0 would then never
      // grow again, and the next phase made 20 million steps of no length until the step guard;
      // the stepper's own next step size is positive.
      dt = t1 > t0 ? t1 - t0 : stepper.current_time_step();
      // Scan the step at a few dense-output points for the first event function to reach <= 0.
      double ta = t0;
      Events ea = prev;
      int which = -1;
      double root = 0.0;
      bool restarted = false;  // at a radial minimum away from the axis
      for (int j = 1; j <= samples_per_step && which < 0; ++j) {
        const double tb = j == samples_per_step ? t1 : t0 + (t1 - t0) * j / samples_per_step;
        Y xb;
        if (j == samples_per_step) xb = stepper.current_state(); else stepper.calc_state(tb, xb);
        Events eb = events(xb, mode);
        for (std::size_t i = 0; i < kinds.size(); ++i) {
          if (!(ea.f[i] > 0.0 && eb.f[i] <= 0.0)) continue;
          auto f = [&](double tt) {
            Y xx;
            stepper.calc_state(tt, xx);
            return events(xx, mode).f[i];
          };
          // A step near the axis can be shorter than four ulps of the time: its samples then
          // coincide, and a sign change between two of them is at that time.
          const double r = tb > ta ? locate(f, ta, tb, ea.f[i], eb.f[i]) : tb;
          if (which < 0 || r < root) {
            which = static_cast<int>(i);
            root = r;
          }
        }
        // The time budget ends the contact like an event.
        if (tb >= opt_.t_budget && (which < 0 || opt_.t_budget < root)) {
          which = 100;
          root = opt_.t_budget;
        }
        if (which >= 0 && which < 100 && kinds[static_cast<std::size_t>(which)] == Stop::Minimum) {
          // A radial minimum: at a period's second one, extrapolate to the budget.
          Y xm;
          stepper.calc_state(root, xm);
          const double wn = dot(Surface::omega(xm), sf_.kin(xm).n);
          if (last.repeated_by(root, xm, wn, mode == Mode::Free)) {
            y = land(t0, root);
            t = root;
            const double periods = (opt_.t_budget - t) / (t - last.t);
            res_.duration = opt_.t_budget;
            res_.normal_impulse = y[IN] + periods * (y[IN] - last.in);
            res_.impulse = y[IF] + periods * (y[IF] - last.f);
            res_.swept = y[PHI] - phi_start_ + periods * (y[PHI] - last.phi);
            return Stop::Minimum;
          }
          last.record(root, xm, wn);
          // Go on from the minimum; its function is now <= 0 and fires again only after the next
          // maximum. Near the axis the step itself is kept and the rest of this sample's interval
          // scanned: restarting the integration from the interpolated state at each minimum put
          // the dense output's error into the path, 6e-7 of the energy over a contact whose
          // minima were 1e-11 H from the axis (docs/robustness.md, finding 28). Elsewhere the
          // integration restarts there, as it always has.
          if (!near_axis(xm)) {
            y = xm;
            t = root;
            stepper.initialize(y, t, dt);
            prev = events(y, mode);
            restarted = true;
            break;
          }
          which = -1;
          if (root < tb) {
            ea = events(xm, mode);
            ta = root;
            --j;  // the same sample again, from the minimum
            continue;
          }
          // At the sample itself: no other event came first, so none is left in the interval.
        }
        ta = tb;
        ea = eb;
      }
      if (restarted) continue;
      if (which < 0) {
        y = stepper.current_state();
        t = t1;
        prev = ea;
        last.extend(y[Q]);
        if (res_.steps >= opt_.max_steps) return Stop::Cap;
        if ((res_.steps & 1023) == 0 && opt_.cancel != nullptr && opt_.cancel->load(std::memory_order_relaxed)) return Stop::Cap;
        continue;
      }
      t = root;
      if (which == 100) {
        y = land(t0, root);
        return Stop::Cap;
      }
      // At an event that changes the phase the state is the dense output's at the located root,
      // where the event's function is <= 0 by construction: the next phase must start past the
      // event (an integrated state can fall on its near side, and rolling that static friction
      // can no longer hold then began again and ended at once, 100 000 times at the same time).
      stepper.calc_state(root, y);
      return kinds[static_cast<std::size_t>(which)];
    }
  }

  /// Root of f on [a, b] with f(a) > 0 >= f(b), to the last bits (TOMS 748); the end where f <= 0.
  template <class F>
  static double locate(const F& f, double a, double b, double fa, double fb) {
    if (fb == 0.0) return b;
    std::uintmax_t iterations = 100;
    const auto bracket = boost::math::tools::toms748_solve(
        f, a, b, fa, fb, boost::math::tools::eps_tolerance<double>(std::numeric_limits<double>::digits), iterations);
    return bracket.second;
  }

 public:
  double phi_start_ = 0.0;

 private:
  const Surface& sf_;
  const Cone& cone_;
  const Material& m_;
  const Contact3Options& opt_;
  double q_end_ = 0.0, psi_top_ = 0.0;
  Vec3 reference_;
  // The azimuth of the last evaluation of the equations of motion, its cosine and sine.
  bool have_last_ = false;
  double last_phi_ = 0.0, last_cos_ = 0.0, last_sin_ = 0.0;
  Contact3Result res_;
};

Surface make_surface(bool torus, const Cone& cone, const Material& m) {
  Surface sf;
  sf.torus = torus;
  sf.sin_t = cone.g.sin_t;
  sf.cos_t = cone.g.cos_t;
  sf.R = cone.rim_radius;
  sf.y_b = cone.g.y_bottom;
  sf.a = m.radius;
  sf.kappa = m.kappa;
  sf.mu = m.mu;
  return sf;
}

}  // namespace

namespace detail {

Contact3Result integrate_contact(bool torus, const State3& start, const Cone& cone, const Material& m,
                                 const Contact3Options& opt) {
  const Surface sf = make_surface(torus, cone, m);
  Integrated run(sf, cone, m, opt);
  run.phi_start_ = coordinates(sf, start)[PHI];
  return run.run(start);
}

}  // namespace detail

}  // namespace funnel
