// Sustained contact with an edge point, phase by phase (docs/model.md §5b).
//
// The centre moves on the circle r = E + a n, n = (cos psi, sin psi). Per unit mass, with the
// friction force F along t = (n_y, -n_x) and W = psi'^2:
//   normal force      N = sin(psi) - a W                    (contact while N > 0)
//   along the circle  a psi'' = -cos(psi) - F
//   spin              kappa a omega' = F
//   slip              s = a (omega - psi')
//   about E           a^2 psi' + kappa a^2 omega = L0 - a G,  G = integral of cos(psi) dt
// (the last is the angular momentum about the edge point, which only gravity's torque changes).
// Rolling (s = 0, F = -kappa cos(psi)/(1 + kappa)) conserves (1 + kappa) a^2 W / 2 + a sin(psi);
// sliding (F = -sigma mu N) gives the linear equation dW/dpsi + 2 sigma mu W =
// (2/a)(sigma mu sin(psi) - cos(psi)), solved in closed form. So W, N and the rolling friction
// limit are closed-form functions of psi; the time, G and the impulses are integrals over psi,
// evaluated by adaptive Gauss-Kronrod quadrature after a change of variable that removes the
// square-root singularity of dt = dpsi / psi' at turning points (W = 0).
#include "funnel/edge_contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/tools/roots.hpp>

namespace funnel {

namespace {

/// Phases (rolling/sliding, split at turning points) after which a contact is ended as a
/// take-off; a guard that no physical contact reaches (each phase changes the regime or the
/// direction of motion).
constexpr int max_phases = 64;
/// Samples of the closed-form event functions over a phase's range of angles.
constexpr int event_samples = 32;
/// At most this many geometric samples precede them in a fast-changing sliding phase.
constexpr int max_geometric_samples = 24;
/// At most this many geometric samples from a decelerating start's turning distance (enough to
/// go from one ulp of psi to the first uniform sample, factor 4 apart).
constexpr int max_turn_samples = 28;
/// Pieces of a sliding phase at whose ends the slip is checked for a zero.
constexpr int slip_pieces = 8;
/// Relative accuracy of every quadrature (of its L1 norm), below the 1e-13 the model asks for.
constexpr double quad_tol = 1e-14;

using Vec4 = std::array<double, 4>;  // time, G, integral of N dt, integral of sqrt(N^2 + F^2) dt

/// psi'^2 as a function of psi in one regime, and the forces that go with it.
struct Branch {
  Regime regime = Regime::Rolling;  // Rolling or Sliding
  double sigma = 0.0;               // sign of the slip while sliding
  double a = 0.0, kappa = 0.0, mu = 0.0;
  double k = 0.0, alpha = 0.0, beta = 0.0;  // sliding: W_p = alpha sin + beta cos, decay rate k

  Branch(Regime r, double sig, const Material& m) : regime(r), sigma(sig), a(m.radius), kappa(m.kappa), mu(m.mu) {
    if (regime == Regime::Sliding) {
      k = 2.0 * sigma * mu;
      const double c1 = 2.0 * sigma * mu / a;
      const double c2 = -2.0 / a;
      alpha = (k * c1 + c2) / (1.0 + k * k);
      beta = (k * c2 - c1) / (1.0 + k * k);
    }
  }

  /// W at psi_r + delta on the solution through (psi_r, w_r); written with half-angle products
  /// and expm1 of the offset delta (not of psi - psi_r, which loses the offset's digits), so that
  /// it keeps its relative accuracy near the reference point (e.g. a turning point, W = 0).
  ///
  /// With `noise`, also a bound on its rounding, to a constant factor: of its terms, which cancel
  /// where W is far below them (e.g. near a small least value of W), and of the sine and cosine
  /// of mid = psi_r + delta/2 through mid's own rounding (ill-conditioned near psi = pi/2 for the
  /// cosine, where the particle passes over the edge's top). For the sliding W = d_particular +
  /// w_r + h E (h = w_r - particular_r, E = expm1(arg)): the rounding of each term, of h (times E)
  /// and of arg (times e^arg), and of the sums.
  double W(double psi_r, double w_r, double delta, double* noise = nullptr) const {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double half = 0.5 * delta;
    const double mid = psi_r + half;
    const double s_half = std::sin(half), c_mid = std::cos(mid);
    if (regime == Regime::Rolling) {
      if (noise != nullptr) {
        const double scale = 4.0 / (a * (1.0 + kappa));
        *noise = eps * (std::fabs(w_r) + scale * std::fabs(s_half) * (3.0 * std::fabs(c_mid) + std::fabs(mid)));
      }
      return w_r - 4.0 * c_mid * s_half / (a * (1.0 + kappa));
    }
    const double s_mid = std::sin(mid);
    const double d_particular = 2.0 * s_half * (alpha * c_mid - beta * s_mid);
    const double s_r = std::sin(psi_r), c_r = std::cos(psi_r);
    const double particular_r = alpha * s_r + beta * c_r;
    // Beyond the end of a sliding phase the homogeneous part may grow without bound (large mu);
    // the cap keeps it finite (the phase ends long before).
    const double arg = std::fmin(-k * delta, 700.0);
    const double grow = std::expm1(arg);
    const double w = d_particular + w_r + (w_r - particular_r) * grow;
    if (noise != nullptr) {
      const double g = std::fabs(grow), h = std::fabs(w_r - particular_r);
      const double terms = 2.0 * std::fabs(s_half) * (std::fabs(alpha * c_mid) + std::fabs(beta * s_mid));
      const double d_mid = 2.0 * std::fabs(s_half) * (std::fabs(alpha * s_mid) + std::fabs(beta * c_mid)) * std::fabs(mid);
      *noise = eps * (3.0 * terms + d_mid + std::fabs(w_r) + 2.0 * g * (std::fabs(w_r) + std::fabs(alpha * s_r) + std::fabs(beta * c_r)) +
                      h * (3.0 * g + (g + 1.0) * std::fabs(arg)));
    }
    return std::clamp(w, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  }

  double normal(double psi, double w) const { return std::sin(psi) - a * w; }

  /// Friction force along t for the normal force n.
  double friction(double psi, double n) const {
    return regime == Regime::Rolling ? -kappa * std::cos(psi) / (1.0 + kappa) : -sigma * mu * n;
  }

  /// psi'' at psi with normal force n.
  double accel(double psi, double n) const { return (-std::cos(psi) - friction(psi, n)) / a; }
};

/// Static friction can hold rolling at psi with normal force n: kappa |cos| <= mu (1 + kappa) N.
double rolling_margin(double psi, double n, const Material& m) {
  return m.mu * (1.0 + m.kappa) * n - m.kappa * std::fabs(std::cos(psi));
}

/// The regime that follows zero slip at psi: rolling if friction can hold it, else sliding in
/// the direction the slip then grows (the sign of cos psi).
Branch zero_slip_branch(double psi, double n, const Material& m) {
  if (rolling_margin(psi, n, m) >= 0.0) return Branch(Regime::Rolling, 0.0, m);
  return Branch(Regime::Sliding, std::cos(psi) >= 0.0 ? 1.0 : -1.0, m);
}

/// The integrand at a point of the phase's variable x: (dt, cos(psi) dt, N dt,
/// sqrt(N^2 + F^2) dt) per unit of x, and a bound on the relative rounding each carries from
/// W's (each is proportional to dt, so to 1/sqrt(W)).
struct Sample {
  Vec4 v{};
  double noise = 0.0;
};

/// Adaptive Gauss-Kronrod quadrature (15 points, Gauss 7 embedded) of the vector integrand
/// (a Sample) on an interval of the phase's variable x.
template <class F>
class Quadrature {
 public:
  Quadrature(const F& f, double friction) : f_(f), bound_(2.0 + friction) {}

  Vec4 operator()(double x0, double x1) {
    evaluations_ = 0;
    return integrate(x0, x1, 0);
  }

 private:
  /// Evaluations after which no interval is split any further: a guard, never reached by the
  /// smooth integrands of a phase (a few hundred evaluations each).
  static constexpr long budget = 200000;

  Vec4 integrate(double x0, double x1, int depth) {
    using K = boost::math::quadrature::gauss_kronrod<double, 15>;
    using G = boost::math::quadrature::gauss<double, 7>;
    const double mid = 0.5 * (x0 + x1);
    const double half = 0.5 * (x1 - x0);
    Vec4 kron{}, gauss{}, l1{}, noise{};
    auto add = [&](const Sample& s, double wk, double wg) {
      for (int c = 0; c < 4; ++c) {
        kron[c] += wk * s.v[c];
        gauss[c] += wg * s.v[c];
        l1[c] += wk * std::fabs(s.v[c]);
        noise[c] += wk * std::fabs(s.v[c]) * s.noise;
      }
    };
    add(f_(mid), K::weights()[0], G::weights()[0]);
    for (std::size_t i = 1; i < K::abscissa().size(); ++i) {
      const double dx = half * K::abscissa()[i];
      const double wg = i % 2 == 0 ? G::weights()[i / 2] : 0.0;
      add(f_(mid + dx), K::weights()[i], wg);
      add(f_(mid - dx), K::weights()[i], wg);
    }
    evaluations_ += 15;
    // Converged when the embedded rules agree to quad_tol of each component's L1 norm, or to
    // the rounding floor of the integrands: each is a bounded function (|cos|, N <= 1,
    // sqrt(N^2 + F^2) <= 2 + mu) times dt, and N = sin(psi) - a W is computed with
    // absolute error ~eps, so no component is known better than ~eps times the time.
    // Nor better than the rounding of the integrand itself (the samples' noise): where W is
    // computed with cancellation (a small least value of W, far below its size elsewhere: a
    // sphere passing slowly over the edge's top) the rules cannot agree to quad_tol, and
    // refining on spent the whole evaluation budget depth first on the first stretch, leaving
    // the rest of the phase unrefined: its contact time was 10^-7 to 1.3 times off
    // (docs/robustness.md, finding 21).
    const double floor = 64.0 * std::numeric_limits<double>::epsilon() * bound_ * l1[0];
    bool converged = true;
    for (int c = 0; c < 4; ++c) {
      if (std::fabs(kron[c] - gauss[c]) > std::fmax(std::fmax(quad_tol * l1[c], floor), 8.0 * noise[c])) converged = false;
    }
    if (converged || depth >= 50 || evaluations_ > budget || !(x0 < mid && mid < x1)) {
      for (double& v : kron) v *= half;
      return kron;
    }
    Vec4 left = integrate(x0, mid, depth + 1);
    const Vec4 right = integrate(mid, x1, depth + 1);
    for (int c = 0; c < 4; ++c) left[c] += right[c];
    return left;
  }

  const F& f_;
  double bound_;
  long evaluations_ = 0;
};

/// Root of f on [lo, hi] (f(lo) > 0 >= f(hi)) to the last bit.
template <class F>
double refine_root(const F& f, double lo, double hi, double f_lo, double f_hi) {
  if (f_hi == 0.0) return hi;
  std::uintmax_t iterations = 200;
  const auto bracket = boost::math::tools::toms748_solve(
      f, lo, hi, f_lo, f_hi, boost::math::tools::eps_tolerance<double>(std::numeric_limits<double>::digits),
      iterations);
  // The end of the bracket on the side where f <= 0: the event has happened there.
  return bracket.second;
}

/// Why a phase ended.
enum class PhaseEnd { Limit, TakeOff, Turning, SlipOnset, SlipZero };

/// First root of f between `from` (where f > 0) and `to` (where f <= 0), on either side.
template <class F>
double refine_between(const F& f, double from, double to, double f_from, double f_to) {
  if (from < to) return refine_root(f, from, to, f_from, f_to);
  auto mirrored = [&](double x) { return f(-x); };
  return -refine_root(mirrored, -from, -to, f_from, f_to);
}

/// The running contact: angle, W = psi'^2, direction of motion, spin, and the result so far.
class Contact {
 public:
  Contact(const State& start, const EdgeArc& arc, const Material& m) : arc_(arc), m_(m), a_(m.radius) {
    const Vec2 d = start.r - arc.point;
    psi_ = std::clamp(std::atan2(d.y, d.x), arc.psi_low, arc.psi_high);
    const double rate = (-std::sin(psi_) * start.v.x + std::cos(psi_) * start.v.y) / a_;  // psi'
    w_ = rate * rate;
    dir_ = rate >= 0.0 ? 1.0 : -1.0;
    omega_ = start.omega;
    e_start_ = energy(start, m.kappa, m.radius);
  }

  EdgeContactResult run() {
    const double s0 = a_ * (omega_ - rate());
    // A slip within rounding of zero is zero (e.g. arriving from rolling on a face).
    const double eps = std::numeric_limits<double>::epsilon();
    const bool no_slip = std::fabs(s0) <= 8.0 * eps * a_ * (std::fabs(omega_) + std::fabs(rate()));
    Branch branch = no_slip ? zero_slip_branch(psi_, std::sin(psi_) - a_ * w_, m_)
                            : Branch(Regime::Sliding, s0 > 0.0 ? 1.0 : -1.0, m_);
    if (no_slip && branch.regime == Regime::Rolling) omega_ = rate();
    res_.first_regime = branch.regime;
    for (;;) {
      if (w_ == 0.0) dir_ = branch.accel(psi_, std::sin(psi_)) >= 0.0 ? 1.0 : -1.0;  // from rest
      res_.last_regime = branch.regime;
      const PhaseEnd end = phase(branch);
      ++res_.phases;
      if (end == PhaseEnd::Limit || end == PhaseEnd::TakeOff || res_.phases >= max_phases) {
        res_.exit = end == PhaseEnd::Limit ? (dir_ > 0.0 ? EdgeExit::High : EdgeExit::Low) : EdgeExit::TakeOff;
        break;
      }
      const double n = branch.normal(psi_, w_);
      if (end == PhaseEnd::Turning) {
        dir_ = branch.accel(psi_, n) >= 0.0 ? 1.0 : -1.0;
      } else if (end == PhaseEnd::SlipOnset) {
        branch = Branch(Regime::Sliding, std::cos(psi_) >= 0.0 ? 1.0 : -1.0, m_);
      } else {  // SlipZero
        branch = zero_slip_branch(psi_, n, m_);
        omega_ = rate();
      }
    }
    res_.end = state();
    res_.energy_lost = e_start_ - energy(res_.end, m_.kappa, m_.radius);
    return res_;
  }

 private:
  double rate() const { return dir_ * std::sqrt(w_); }

  State state() const {
    State s;
    const double c = std::cos(psi_), sn = std::sin(psi_);
    s.r = arc_.point + a_ * Vec2{c, sn};
    s.v = (a_ * rate()) * Vec2{-sn, c};
    s.omega = omega_;
    return s;
  }

  /// One phase from the current state in the current direction: finds where it ends, then
  /// integrates over it; updates the state, the clock and the impulses.
  PhaseEnd phase(const Branch& b) {
    const double psi_a = psi_, w_a = w_;
    const double limit = dir_ > 0.0 ? arc_.psi_high : arc_.psi_low;
    auto w_of = [&](double psi) { return b.W(psi_a, w_a, psi - psi_a); };
    auto n_of = [&](double psi) { return b.normal(psi, w_of(psi)); };
    auto roll_of = [&](double psi) { return rolling_margin(psi, n_of(psi), m_); };

    // The closed-form events (take-off, turning point, loss of rolling): sample the range
    // towards the arc's end and refine the first bracket of each function.
    // A sliding phase with a large |k (limit - psi_a)| (large mu) changes on the scale 1/|k|:
    // geometric samples at |k| offset = 1/4, 1/2, 1, ... come before the uniform ones, so that
    // its events are bracketed where the exponential is still finite.
    // A slow start that decelerates turns within ~W / |dW/dpsi| of it, which may fall between
    // two uniform samples with W < 0 only there (found by the fuzzer: a missed turning point
    // let the particle drift uphill): geometric samples from that distance on catch it.
    std::array<double, event_samples + max_geometric_samples + max_turn_samples> fractions{};
    int samples = 0;
    const double range = std::fabs(limit - psi_a);
    const double k_span = std::fabs(b.k * range);
    for (double q = 0.25; q < k_span / event_samples && samples < max_geometric_samples; q *= 2.0) {
      fractions[samples++] = q / k_span;
    }
    const double acc = b.accel(psi_a, b.normal(psi_a, w_a));
    if (w_a > 0.0 && dir_ * acc < 0.0 && range > 0.0) {
      // From the first sample that moves psi at all: a start at rest within rounding (W ~ 1e-37)
      // turns below one ulp of psi, and W may be positive again at the uniform samples when the
      // friction overcomes gravity further on (found by the fuzzer: the particle slid uphill).
      const double ulp_fraction = 4.0 * std::numeric_limits<double>::epsilon() * std::fmax(1.0, std::fabs(psi_a)) / range;
      const double turn = std::fmax(w_a / (2.0 * std::fabs(acc)) / range, ulp_fraction);  // fraction of the range
      int added = 0;
      for (double q = turn; q < 1.0 / event_samples && added < max_turn_samples; q *= 4.0, ++added) {
        fractions[samples++] = q;
      }
    }
    std::sort(fractions.begin(), fractions.begin() + samples);
    for (int j = 1; j <= event_samples; ++j) fractions[samples++] = static_cast<double>(j) / event_samples;
    PhaseEnd why = PhaseEnd::Limit;
    double psi_b = limit;
    double prev = psi_a;
    // Ends the phase at `root` with `kind`, if that comes before the end found so far.
    auto take = [&](double root, PhaseEnd kind) {
      if (why == PhaseEnd::Limit || (root - psi_b) * dir_ < 0.0) {
        psi_b = root;
        why = kind;
      }
    };
    // dW/dpsi = 2 psi'' along the motion, at psi where W = w (for W's dips between samples).
    auto w_rise = [&](double psi, double w) { return dir_ * 2.0 * b.accel(psi, b.normal(psi, w)); };
    double w_prev = w_of(psi_a), rise_prev = w_rise(psi_a, w_prev);
    for (int j = 0; j < samples && why == PhaseEnd::Limit; ++j) {
      const double psi = j == samples - 1 ? limit : psi_a + (limit - psi_a) * fractions[j];
      // A fraction too small to move psi (or two equal fractions) brackets nothing (found by
      // the fuzzer: an empty bracket at psi = pi aborted the root finder).
      if (psi == prev) continue;
      auto check = [&](const auto& f, PhaseEnd kind) {
        const double f_to = f(psi);
        if (!(f_to <= 0.0)) return;
        // Positive at prev: at the phase's start by construction, at later samples by the scan.
        const double f_from = std::fmax(f(prev), std::numeric_limits<double>::min());
        take(refine_between(f, prev, psi, f_from, f_to), kind);
      };
      check(n_of, PhaseEnd::TakeOff);
      check(w_of, PhaseEnd::Turning);
      if (b.regime == Regime::Rolling) check(roll_of, PhaseEnd::SlipOnset);
      // W may dip to zero and rise again between two samples where it is positive: a turning
      // point the signs at the samples miss (found by the fuzzer: sliding up an edge with
      // mu = 286, W fell below 0 over 0.1% of the arc between samples 0.2% apart, and the
      // quadrature of dt = dpsi / sqrt(W) then ran to its budget through the region the particle
      // cannot reach). Where W falls along the motion at prev and rises at psi, its least value
      // between them is where W' = 2 psi'' = 0; a turning point lies before it if W <= 0 there.
      // (N = sin psi - a W could dip to 0 between samples in the same way where W peaks: none
      // was seen, in the fuzzer's runs or among 200 000 random starts, so it is not sought.)
      const double w_psi = w_of(psi), rise_psi = w_rise(psi, w_psi);
      if (w_prev > 0.0 && w_psi > 0.0 && rise_prev < 0.0 && rise_psi > 0.0) {
        auto falling = [&](double q) { return -w_rise(q, w_of(q)); };
        const double least = refine_between(falling, prev, psi, -rise_prev, -rise_psi);
        const double w_least = w_of(least);
        if (w_least <= 0.0) take(refine_between(w_of, prev, least, w_prev, w_least), PhaseEnd::Turning);
      }
      w_prev = w_psi;
      rise_prev = rise_psi;
      prev = psi;
    }
    const double w_b = why == PhaseEnd::Turning ? 0.0 : std::fmax(w_of(psi_b), 0.0);

    // psi(x) = psi_a + (psi_b - psi_a)(1 - cos(pi x))/2 on x in [0, 1]: dpsi/dx vanishes like
    // sqrt(W) at both ends, so dt/dx stays finite at turning points. Near a turning point at
    // the end, W is taken from the solution through it (W = 0 there exactly), where the closed
    // form keeps its relative accuracy; but only where the sliding solution's exponential does
    // not amplify the rounding of that end (|k (psi - psi_b)| <= 1): elsewhere from the start.
    const double span = psi_b - psi_a;
    const double pi = std::numbers::pi;
    // Offsets from both ends, each computed without cancellation: psi = psi_a + span sin^2(pi x/2)
    // = psi_b - span cos^2(pi x/2).
    auto offset_a = [&](double x) { const double s = std::sin(0.5 * pi * x); return span * s * s; };
    auto offset_b = [&](double x) { const double c = std::cos(0.5 * pi * x); return -span * c * c; };
    auto psi_at = [&](double x) { return x < 0.5 ? psi_a + offset_a(x) : psi_b + offset_b(x); };
    auto w_at = [&](double x, double* noise = nullptr) {
      const bool from_end = why == PhaseEnd::Turning && x >= 0.5 && std::fabs(b.k * offset_b(x)) <= 1.0;
      return from_end ? b.W(psi_b, w_b, offset_b(x), noise) : b.W(psi_a, w_a, offset_a(x), noise);
    };
    auto integrand = [&](double x) -> Sample {
      const double psi = psi_at(x);
      double w_noise = 0.0;
      const double w = w_at(x, &w_noise);
      if (!(w > 0.0)) return {};
      const double dt = span * 0.5 * pi * std::sin(pi * x) / (dir_ * std::sqrt(w));
      const double n = b.normal(psi, w);
      const double f = b.friction(psi, n);
      return {{dt, std::cos(psi) * dt, n * dt, std::hypot(n, f) * dt}, 0.5 * w_noise / w};
    };

    Quadrature<decltype(integrand)> integrate(integrand, m_.mu);
    Vec4 total{};
    double x_end = 1.0;
    // While sliding the friction torque is the only one: kappa a omega' = F = -sigma mu N, so the
    // spin follows from the normal impulse (exactly unchanged when mu = 0).
    const double omega_a = omega_;
    auto spin_after = [&](const Vec4& acc) { return omega_a - b.sigma * m_.mu * acc[2] / (m_.kappa * a_); };
    auto slip = [&](const Vec4& acc, double x) {
      const double w = x == 1.0 ? w_b : std::fmax(w_at(x), 0.0);
      return a_ * (spin_after(acc) - dir_ * std::sqrt(w));
    };
    if (span != 0.0) {
      const int pieces = b.regime == Regime::Sliding ? slip_pieces : 1;
      for (int j = 1; j <= pieces; ++j) {
        const double x0 = static_cast<double>(j - 1) / pieces, x1 = static_cast<double>(j) / pieces;
        const Vec4 piece = integrate(x0, x1);
        Vec4 next = total;
        for (int c = 0; c < 4; ++c) next[c] += piece[c];
        // The slip (times sigma) at x in this piece, integrating from the piece's start.
        auto signed_slip = [&](double x) {
          Vec4 acc = total;
          const Vec4 part = integrate(x0, x);
          for (int c = 0; c < 4; ++c) acc[c] += part[c];
          return b.sigma * slip(acc, x);
        };
        const double s_start = b.sigma * slip(total, x0);
        double s_end = b.regime == Regime::Sliding ? b.sigma * slip(next, x1) : 1.0;
        double x_dip = x1;
        if (b.regime == Regime::Sliding && s_end > 0.0) {
          // The slip may vanish and come back between the piece's ends, positive at both (found
          // by comparing with a brute-force integration: a slip that reversed and vanished again
          // within one piece was slid through). sigma s' = sigma cos psi - mu N (1 + kappa) /
          // kappa is closed-form: where sigma s falls at x0 and rises at x1, its least value is
          // where s' = 0, and the slip's first zero lies before it if it is <= 0 there.
          auto rise = [&](double x) {
            const double psi = psi_at(x);
            const double n = b.normal(psi, std::fmax(w_at(x), 0.0));
            return b.sigma * std::cos(psi) - m_.mu * n * (1.0 + m_.kappa) / m_.kappa;
          };
          const double r0 = rise(x0), r1 = rise(x1);
          if (r0 < 0.0 && r1 > 0.0 && s_start > 0.0) {
            const double x_least = refine_root([&](double x) { return -rise(x); }, x0, x1, -r0, -r1);
            const double s_least = signed_slip(x_least);
            if (s_least <= 0.0) {
              s_end = s_least;
              x_dip = x_least;
            }
          }
        }
        if (s_end <= 0.0) {
          // The slip vanishes in this piece (before x_dip): find where.
          // A phase that starts at zero slip (sliding after a slip zero, where rolling cannot
          // hold) has a slip that grows from exactly 0: next to x0 it still evaluates to 0, and
          // the root finder, whose first guess lands there, would stop at once. The phase then
          // made no progress, and the next one the same, until the phase cap ended the contact
          // as a take-off with N > 0 (found by the fuzzer: a flight then crossed the wall). The
          // bracket starts at the first of x0 + (x1 - x0) 2^-k, k = 52 .. 1, where the slip is
          // positive beyond the rounding of a (omega - psi') (16 eps a (|omega| + |psi'|)):
          // closer to x0 its value is that rounding, of either sign, and a negative one made
          // the search give up there (found by comparing with a brute-force integration: a
          // sphere rolling up an edge at psi' = 94 lost its grip, slid with a slip that grew to
          // 3e-5 of a psi' and vanished again, and ended after 64 empty phases as a take-off
          // with N = 0.03 > 0; docs/robustness.md, finding 21).
          const double noise = 16.0 * std::numeric_limits<double>::epsilon() * a_ * (std::fabs(omega_a) + std::sqrt(w_a));
          double lo = x0;
          double s_lo = s_start;
          for (int k = 52; !(s_lo > noise) && k >= 1; --k) {
            const double x = x0 + (x1 - x0) * std::ldexp(1.0, -k);
            const double sx = signed_slip(x);
            if (sx < -noise) break;  // it does not grow: a zero at the start
            if (sx > noise) {
              lo = x;
              s_lo = sx;
            }
          }
          const double s_from = std::fmax(s_lo, std::numeric_limits<double>::min());
          x_end = refine_root(signed_slip, lo, x_dip, s_from, s_end);
          const Vec4 part = integrate(x0, x_end);
          for (int c = 0; c < 4; ++c) total[c] += part[c];
          why = PhaseEnd::SlipZero;
          break;
        }
        total = next;
      }
    }

    // The state at the end of the phase.
    const double psi_end = x_end == 1.0 ? psi_b : psi_at(x_end);
    const double w_end = x_end == 1.0 ? w_b : std::fmax(w_at(x_end), 0.0);
    psi_ = psi_end;
    w_ = w_end;
    res_.duration += total[0];
    res_.normal_impulse += total[2];
    res_.impulse += total[3];
    if (b.regime == Regime::Rolling) {
      res_.tangential_impulse += -m_.kappa / (1.0 + m_.kappa) * total[1];
      omega_ = rate();
    } else {
      res_.tangential_impulse += -b.sigma * m_.mu * total[2];
      omega_ = spin_after(total);
    }
    return why;
  }

  const EdgeArc& arc_;
  const Material& m_;
  double a_;
  double psi_ = 0.0, w_ = 0.0, dir_ = 1.0, omega_ = 0.0;
  double e_start_ = 0.0;
  EdgeContactResult res_;
};

}  // namespace

double edge_normal_force(const State& s, Vec2 point, double radius) {
  const Vec2 d = s.r - point;
  return d.y / std::hypot(d.x, d.y) - dot(s.v, s.v) / radius;
}

EdgeContactResult edge_contact(const State& start, const EdgeArc& arc, const Material& m) {
  return Contact(start, arc, m).run();
}

}  // namespace funnel
