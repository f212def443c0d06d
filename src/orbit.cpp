// Period-2 orbit theory (paper Sec. IV and Appendix): maps F1, F2, their Jacobians and the orbit's stability.
#include "funnel/orbit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace funnel::orbit {
namespace {

constexpr double deg = std::numbers::pi / 180.0;

// Which wall the flight ends on: +1 for the right wall (F1), -1 for the left wall (F2).
enum class Target : int { Right = 1, Left = -1 };

double sigma_of(Target target) { return static_cast<double>(static_cast<int>(target)); }

// Walton's sticking collision with e = 1 (Eqs. 1, 10, 11) is linear in (u, v, omega) before the collision:
// p' = -p, q' = q + J_t, omega' = omega + J_t/(kappa a), J_t = -k (q + a omega), k = (1+beta0) kappa/(1+kappa).
// Target wall: inward normal n = (-sigma sin, cos), tangent t = (n_y, -n_x) = (cos, sigma sin).
Eigen::Matrix3d collision_matrix(Target target, const OrbitParams& params) {
  const double sigma = sigma_of(target);
  const double th = params.theta_deg * deg;
  const Eigen::Vector2d n(-sigma * std::sin(th), std::cos(th));
  const Eigen::Vector2d t(n.y(), -n.x());
  const double a = params.radius;
  const double k = (1.0 + params.beta0) * params.kappa / (1.0 + params.kappa);
  Eigen::Matrix3d m;
  // velocity' = q' t + p' n with q' = (1-k) q - k a omega, p' = -p.
  m.topLeftCorner<2, 2>() = (1.0 - k) * t * t.transpose() - n * n.transpose();
  m.topRightCorner<2, 1>() = -k * a * t;
  // omega' = -(k/(kappa a)) q + (1 - k/kappa) omega.
  m.bottomLeftCorner<1, 2>() = -(k / (params.kappa * a)) * t.transpose();
  m(2, 2) = 1.0 - k / params.kappa;
  return m;
}

// Flight from one centre line to the other, Eqs. (26)-(27) and (34): with sigma = +1 (to the right wall)
// t_f = B + sqrt(B^2 + 4y), B = v - sigma u tan(theta); landing height y_next = -y + sigma u tan(theta) t_f.
struct Flight {
  double b;       // B, velocity / sqrt(gH)
  double root;    // sqrt(B^2 + 4y), velocity / sqrt(gH)
  double time;    // t_f, units of sqrt(H/g)
  double y_next;  // landing height / H
};

Flight fly(const State& P, Target target, const OrbitParams& params) {
  const double sigma = sigma_of(target);
  const double tan_th = std::tan(params.theta_deg * deg);
  Flight f{};
  f.b = P(2) - sigma * P(1) * tan_th;
  f.root = std::sqrt(f.b * f.b + 4.0 * P(0));
  // Cancellation-free positive root of t^2/2 - B t - 2y = 0 (for B < 0, B + root loses digits).
  f.time = f.b >= 0.0 ? f.b + f.root : 4.0 * P(0) / (f.root - f.b);
  f.y_next = -P(0) + sigma * P(1) * tan_th * f.time;
  return f;
}

State flight_then_collision(const State& P, Target target, const OrbitParams& params) {
  const Flight f = fly(P, target, params);
  const Eigen::Vector3d before(P(1), P(2) - f.time, P(3));  // Eq. (28): u unchanged, v - t, omega unchanged
  const Eigen::Vector3d after = collision_matrix(target, params) * before;
  return State(f.y_next, after(0), after(1), after(2));
}

// Chain rule through flight and collision at any state.
Eigen::Matrix4d flight_then_collision_jacobian(const State& P, Target target, const OrbitParams& params) {
  const double sigma = sigma_of(target);
  const double tan_th = std::tan(params.theta_deg * deg);
  const Flight f = fly(P, target, params);
  // d(B)/dP and d(root)/dP, root^2 = B^2 + 4y.
  const Eigen::RowVector4d d_b(0.0, -sigma * tan_th, 1.0, 0.0);
  Eigen::RowVector4d d_root = (f.b / f.root) * d_b;
  d_root(0) += 2.0 / f.root;
  const Eigen::RowVector4d d_time = d_b + d_root;

  Eigen::Matrix4d jac;
  jac.row(0) = sigma * tan_th * P(1) * d_time;
  jac(0, 0) -= 1.0;
  jac(0, 1) += sigma * tan_th * f.time;

  // (u, v - t, omega) before the collision as functions of P.
  Eigen::Matrix<double, 3, 4> before = Eigen::Matrix<double, 3, 4>::Zero();
  before(0, 1) = 1.0;
  before.row(1) = -d_time;
  before(1, 2) += 1.0;
  before(2, 3) = 1.0;
  jac.bottomRows<3>() = collision_matrix(target, params) * before;
  return jac;
}

// The printed matrices differ between F1 and F2 only by signs; sign = +1 gives dF1/dP1, -1 gives dF2/dP2.
Eigen::Matrix4d paper_matrix(double y_star, const OrbitParams& params, double sign) {
  const double th = params.theta_deg * deg;
  const double s = std::sin(th), co = std::cos(th), tn = std::tan(th);
  const double s2 = std::sin(2 * th), c2 = std::cos(2 * th), s4 = std::sin(4 * th);
  const double r = std::sqrt(y_star);
  const double a = params.radius, kappa = params.kappa, beta0 = params.beta0;
  // The paper's c = (m a^2 - I beta0)/(I + m a^2); m a / I = 1/(kappa a).
  const double c = (1.0 - kappa * beta0) / (1.0 + kappa);
  const double ma_i = 1.0 / (kappa * a);
  const double g = co * co - c * s * s;
  Eigen::Matrix4d m;
  m << -c2, sign * 2 * r * co * co, r * s2, 0.0,
      -sign * (1 + c) * s2 * s2 / (2 * r), (1 + c) * s * s * c2 + c, -sign * 0.25 * (1 + c) * s4, -a * (1 - c) * co,
      g * s2 / r, sign * (-g * tn * c2 + c * tn), g * c2, -sign * a * (1 - c) * s,
      sign * ma_i * (1 - c) * s2 * s / r, -ma_i * (1 - c) / co * (1 + c2 * s * s), sign * ma_i * (1 - c) * s * c2,
      1 - c - beta0;
  return m;
}

// Strict weak order: decreasing modulus, then decreasing real part, then decreasing imaginary part.
// Conjugate pairs from EigenSolver have bit-identical moduli, so exact comparison gives a deterministic order.
bool precedes(const std::complex<double>& x, const std::complex<double>& y) {
  const double ax = std::abs(x), ay = std::abs(y);
  if (ax != ay) return ax > ay;
  if (x.real() != y.real()) return x.real() > y.real();
  return x.imag() > y.imag();
}

}  // namespace

State map_left_to_right(const State& P1, const OrbitParams& params) {
  return flight_then_collision(P1, Target::Right, params);
}

State map_right_to_left(const State& P2, const OrbitParams& params) {
  return flight_then_collision(P2, Target::Left, params);
}

State period_map(const State& P1, const OrbitParams& params) {
  return map_right_to_left(map_left_to_right(P1, params), params);
}

State fixed_point(double y_star, const OrbitParams& params) {
  const double r = std::sqrt(y_star);
  return State(y_star, r, r / std::tan(params.theta_deg * deg), 0.0);
}

State fixed_point_right(double y_star, const OrbitParams& params) {
  const double r = std::sqrt(y_star);
  return State(y_star, -r, r / std::tan(params.theta_deg * deg), 0.0);
}

State fixed_point_45(double y_star, double ratio, const OrbitParams& params) {
  // At 45 degrees cot(theta) = 1, so the landing condition u'v' = y* cot(theta) (Eq. 22) holds for any ratio;
  // the slip q + a omega = (u' - v')/sqrt(2) + a omega vanishes on both walls (Eqs. 16-17).
  const double u = std::sqrt(y_star * ratio), v = std::sqrt(y_star / ratio);
  return State(y_star, u, v, -(u - v) / (std::numbers::sqrt2 * params.radius));
}

Eigen::Vector4d state_scale(double y_star, const OrbitParams& params) {
  const double r = std::sqrt(y_star);
  return Eigen::Vector4d(y_star, r, r, r / params.radius);
}

Eigen::Matrix4d jacobian_left_to_right(const State& P, const OrbitParams& params) {
  return flight_then_collision_jacobian(P, Target::Right, params);
}

Eigen::Matrix4d jacobian_right_to_left(const State& P, const OrbitParams& params) {
  return flight_then_collision_jacobian(P, Target::Left, params);
}

Eigen::Matrix4d jacobian_exact(double y_star, const OrbitParams& params) {
  return jacobian_right_to_left(fixed_point_right(y_star, params), params) *
         jacobian_left_to_right(fixed_point(y_star, params), params);
}

Eigen::Matrix4d jacobian_paper_left_to_right(double y_star, const OrbitParams& params) {
  return paper_matrix(y_star, params, 1.0);
}

Eigen::Matrix4d jacobian_paper_right_to_left(double y_star, const OrbitParams& params) {
  return paper_matrix(y_star, params, -1.0);
}

Eigen::Matrix4d jacobian_paper(double y_star, const OrbitParams& params) {
  return jacobian_paper_right_to_left(y_star, params) * jacobian_paper_left_to_right(y_star, params);
}

Eigen::Matrix4d jacobian_fd(double y_star, const OrbitParams& params, double rel_step) {
  const State p_star = fixed_point(y_star, params);
  const Eigen::Vector4d scale = state_scale(y_star, params);
  Eigen::Matrix4d jac;
  for (int j = 0; j < 4; ++j) {
    const double h = rel_step * scale(j);
    auto at = [&](double steps) {
      State p = p_star;
      p(j) += steps * h;
      return period_map(p, params);
    };
    // Fourth-order central stencil: truncation O(h^4), so a large step keeps rounding error small.
    jac.col(j) = (8.0 * (at(1.0) - at(-1.0)) - (at(2.0) - at(-2.0))) / (12.0 * h);
  }
  return jac;
}

Eigen::Matrix4d scaled_jacobian(const Eigen::Matrix4d& jacobian, double y_star, const OrbitParams& params) {
  const Eigen::Vector4d scale = state_scale(y_star, params);
  return scale.cwiseInverse().asDiagonal() * jacobian * scale.asDiagonal();
}

Eigen::Vector4cd eigenvalues(const Eigen::Matrix4d& matrix) {
  const Eigen::EigenSolver<Eigen::Matrix4d> solver(matrix, false);
  Eigen::Vector4cd values = solver.eigenvalues();
  std::sort(values.begin(), values.end(), precedes);
  return values;
}

Eigen::Vector4cd orbit_eigenvalues(const OrbitParams& params) {
  // The scaled Jacobian has O(1) entries; the raw one mixes 1/(a sqrt(y*)) with a sqrt(y*).
  return eigenvalues(scaled_jacobian(jacobian_exact(1.0, params), 1.0, params));
}

AppendixAB appendix_ab(double theta_deg, double kappa) {
  const double s = std::sin(theta_deg * deg);
  const double eta = s * s;
  const double c = 1.0 / (1.0 + kappa);
  const double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta;
  const double pc = (1 + c) * (1 + c), mc = (1 - c) * (1 - c);
  AppendixAB ab{};
  ab.A = 8 * pc * e4 - 8 * pc * e3 - 2 * (1 - c * c + 4 * c) * e2 + 2 * (1 + 3 * c) * eta + 1;  // Eq. (A2)
  ab.B = -16 * mc * e4 + 16 * mc * e3 + 4 * (1 - c * c) * e2 - 4 * (1 - c) * eta - 1;          // Eq. (A3)
  return ab;
}

std::array<std::complex<double>, 2> appendix_lambda(double theta_deg, double kappa) {
  const AppendixAB ab = appendix_ab(theta_deg, kappa);
  const std::complex<double> root = std::sqrt(std::complex<double>(ab.A * ab.A + ab.B, 0.0));
  return {ab.A + root, ab.A - root};  // Eq. (A1)
}

CharacteristicCubic characteristic_cubic(const OrbitParams& params) {
  const double s = std::sin(params.theta_deg * deg);
  const double eta = s * s;
  const double w = 2.0 * eta * (2.0 * eta - 1.0);
  const double b = params.beta0;
  const double c = (1.0 - params.kappa * b) / (1.0 + params.kappa);
  const double x = (1.0 - c) * w;
  CharacteristicCubic cubic{};
  cubic.p2 = -(1 + c) * (1 + c) * w * w + 2 * (1 + 3 * c) * w - 2 - b * b + 2 * b * x;
  cubic.p1 = (1 - x) * (1 - x) - 2 * b * x * (2 * w - 3) + 2 * b * b * (2 * w * w - 4 * w + 1);
  cubic.p0 = -b * b;
  return cubic;
}

std::array<std::complex<double>, 3> cubic_eigenvalues(const OrbitParams& params) {
  const CharacteristicCubic cubic = characteristic_cubic(params);
  Eigen::Matrix3d companion;
  companion << -cubic.p2, -cubic.p1, -cubic.p0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0;
  const Eigen::EigenSolver<Eigen::Matrix3d> solver(companion, false);
  std::array<std::complex<double>, 3> roots{};
  for (int i = 0; i < 3; ++i) roots[static_cast<std::size_t>(i)] = solver.eigenvalues()(i);
  std::sort(roots.begin(), roots.end(), precedes);
  return roots;
}

bool is_stable(const Eigen::Vector4cd& eigenvalues, double unit_tol) {
  Eigen::Index unit = 0;
  (eigenvalues.array() - 1.0).abs().minCoeff(&unit);
  if (std::abs(eigenvalues(unit) - 1.0) > unit_tol) return false;
  for (Eigen::Index i = 0; i < eigenvalues.size(); ++i) {
    if (i != unit && !(std::abs(eigenvalues(i)) < 1.0)) return false;
  }
  return true;
}

bool is_stable(const OrbitParams& params) {
  // |beta0| = 1: no energy is lost (the cubic's constant term is -beta0^2 = -1, so the three roots'
  // moduli multiply to 1): marginal at best, and rounding would decide "< 1".
  if (std::fabs(params.beta0) == 1.0) return false;
  const auto roots = cubic_eigenvalues(params);
  return std::all_of(roots.begin(), roots.end(), [](std::complex<double> r) { return std::abs(r) < 1.0; });
}

OrbitAnalysis analyse(const OrbitParams& params, double y_star) {
  OrbitAnalysis a;
  a.eigenvalues = orbit_eigenvalues(params);
  a.stable = is_stable(params);
  const Eigen::Matrix4d paper = scaled_jacobian(jacobian_paper(y_star, params), y_star, params);
  const Eigen::Matrix4d fd = scaled_jacobian(jacobian_fd(y_star, params), y_star, params);
  a.jacobian_max_rel_diff = (paper - fd).cwiseAbs().maxCoeff() / paper.cwiseAbs().maxCoeff();
  return a;
}

}  // namespace funnel::orbit
