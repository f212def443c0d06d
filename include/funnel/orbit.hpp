// Period-2 orbit of an elastic frictional sphere in the funnel: maps, Jacobians, stability (paper Sec. IV, Appendix).
#pragma once

#include <array>
#include <complex>

#include <Eigen/Dense>

// Pure mathematics, independent of the simulation engine. Units: H = g = m = 1, e = 1 throughout.
// Frame: origin where the two centre lines meet; left centre line y = -x tan(theta), right y = x tan(theta);
// omega counter-clockwise. Every collision is elastic (p' = -p) and in Walton's sticking regime (Eqs. 10, 11).
// The walls are taken as infinite: no edge, exit or same-wall collision is considered.
namespace funnel::orbit {

/// Parameters of the orbit theory; theta in degrees, the rest dimensionless (H = g = m = 1).
struct OrbitParams {
  double theta_deg = 60;   ///< wall angle to the horizontal, degrees, 0 < theta < 90
  double beta0 = 0;        ///< Walton's maximum tangential restitution, -1 <= beta0 <= 1
  double kappa = 0.4;      ///< I/(m a^2), > 0 (2/5 solid sphere)
  double radius = 0.01;    ///< particle radius a / H, > 0
};

/// State just after a wall collision, P = (y, u', v', omega'): centre height / H, velocity / sqrt(gH), spin / sqrt(g/H).
using State = Eigen::Vector4d;

/// F1, Eqs. (27)-(33): from just after a left-wall collision to just after the next right-wall collision; needs y > 0.
State map_left_to_right(const State& P1, const OrbitParams& params);

/// F2, Eqs. (34)-(37): from just after a right-wall collision to just after the next left-wall collision; needs y > 0.
State map_right_to_left(const State& P2, const OrbitParams& params);

/// F = F2 o F1: one period, from just after a left-wall collision to just after the second next one.
State period_map(const State& P1, const OrbitParams& params);

/// P1* = (y*, sqrt(y*), sqrt(y*) cot(theta), 0): the orbit just after its left-wall collision at height y* > 0.
State fixed_point(double y_star, const OrbitParams& params);

/// P2* = F1(P1*) = (y*, -sqrt(y*), sqrt(y*) cot(theta), 0): the orbit just after its right-wall collision.
State fixed_point_right(double y_star, const OrbitParams& params);

/// At theta = 45 degrees only (Fig. 9b): the state just after the left-wall collision of a period-2 orbit at
/// height y* > 0 with u'/v' = ratio > 0, u' v' = y*, and the spin that makes the slip zero at both walls,
/// omega' = -(u' - v')/(sqrt(2) a); the right-wall collision rotates the velocity by 90 degrees. At other angles
/// the state is returned too but is not periodic.
State fixed_point_45(double y_star, double ratio, const OrbitParams& params);

/// Natural scale of each component near the orbit: (y*, sqrt(y*), sqrt(y*), sqrt(y*)/a), in the state's units.
Eigen::Vector4d state_scale(double y_star, const OrbitParams& params);

/// Exact dF1/dP at any state P (chain rule through Eqs. 27-33); row i, column j = dF1_i/dP_j.
Eigen::Matrix4d jacobian_left_to_right(const State& P, const OrbitParams& params);

/// Exact dF2/dP at any state P (chain rule through Eqs. 34-37).
Eigen::Matrix4d jacobian_right_to_left(const State& P, const OrbitParams& params);

/// Exact dF/dP1 at P1* = dF2/dP2(P2*) . dF1/dP1(P1*), from the chain-rule Jacobians above.
Eigen::Matrix4d jacobian_exact(double y_star, const OrbitParams& params);

/// The paper's printed dF1/dP1 at P1* (Sec. IV), with c = (m a^2 - I beta0)/(I + m a^2) = (1 - kappa beta0)/(1 + kappa).
Eigen::Matrix4d jacobian_paper_left_to_right(double y_star, const OrbitParams& params);

/// The paper's printed dF2/dP2 at P2* (Sec. IV), same c.
Eigen::Matrix4d jacobian_paper_right_to_left(double y_star, const OrbitParams& params);

/// dF2/dP2 . dF1/dP1 at P1* from the printed matrices (checked entry by entry: they need no correction, docs/theory.md).
Eigen::Matrix4d jacobian_paper(double y_star, const OrbitParams& params);

/// dF/dP1 at P1* by fourth-order central differences of period_map; step of component j = rel_step * state_scale_j.
Eigen::Matrix4d jacobian_fd(double y_star, const OrbitParams& params, double rel_step = 1e-3);

/// S^-1 J S with S = diag(state_scale): the dimensionless Jacobian, same eigenvalues, independent of y* and a.
Eigen::Matrix4d scaled_jacobian(const Eigen::Matrix4d& jacobian, double y_star, const OrbitParams& params);

/// Eigenvalues of a 4x4 real matrix (Eigen::EigenSolver), sorted by decreasing modulus, then real part, then imaginary part.
Eigen::Vector4cd eigenvalues(const Eigen::Matrix4d& matrix);

/// Eigenvalues of dF/dP1 at the orbit (exact Jacobian, scaled for accuracy; they do not depend on y* or a), sorted as above.
Eigen::Vector4cd orbit_eigenvalues(const OrbitParams& params);

/// Appendix Eqs. (A2)-(A3) for beta0 = 0: eta = sin^2(theta), c = m a^2/(I + m a^2) = 1/(1 + kappa).
struct AppendixAB {
  double A;  ///< Eq. (A2), dimensionless
  double B;  ///< Eq. (A3), dimensionless; equals -(1 - 2(1-c) eta (2 eta - 1))^2 <= 0
};

/// A and B of the Appendix for beta0 = 0; theta in degrees (0, 90), kappa > 0.
AppendixAB appendix_ab(double theta_deg, double kappa);

/// The Appendix's lambda_{1,2} = A +- sqrt(A^2 + B) (complex square root), beta0 = 0; lambda_3 = 0, lambda_4 = 1.
std::array<std::complex<double>, 2> appendix_lambda(double theta_deg, double kappa);

/// det(lambda - dF/dP1) = (lambda - 1)(lambda^3 + p2 lambda^2 + p1 lambda + p0), for any beta0 (own derivation).
struct CharacteristicCubic {
  double p2;  ///< coefficient of lambda^2, dimensionless
  double p1;  ///< coefficient of lambda, dimensionless
  double p0;  ///< constant term, = -beta0^2
};

/// Closed-form cubic factor of the characteristic polynomial (docs/theory.md): c = (1 - kappa beta0)/(1 + kappa),
/// w = 2 sin^2(theta)(2 sin^2(theta) - 1); p2 = -(1+c)^2 w^2 + 2(1+3c) w - 2 - beta0^2 + 2 beta0 (1-c) w,
/// p1 = (1 - (1-c) w)^2 - 2 beta0 (1-c) w (2w - 3) + 2 beta0^2 (2w^2 - 4w + 1), p0 = -beta0^2.
CharacteristicCubic characteristic_cubic(const OrbitParams& params);

/// The three roots of characteristic_cubic (companion matrix), sorted by decreasing modulus, then real, then imaginary part.
std::array<std::complex<double>, 3> cubic_eigenvalues(const OrbitParams& params);

/// Largest distance |lambda - 1| accepted for the neutral eigenvalue lambda_4 = 1 (it is found to ~1e-15).
inline constexpr double unit_eigenvalue_tolerance = 1e-8;

/// True if one eigenvalue lies within unit_tol of 1 and the three others have modulus < 1 (linear stability).
bool is_stable(const Eigen::Vector4cd& eigenvalues, double unit_tol = unit_eigenvalue_tolerance);

/// Linear stability of the period-2 orbit: the three roots of characteristic_cubic (the
/// eigenvalues besides the neutral 1) have modulus < 1. Not is_stable(orbit_eigenvalues(params)):
/// next to 90 degrees (and at 45) a second eigenvalue comes within 1e-8 of 1, and the Jacobian's
/// eigensolver, which resolves such a pair only to about 4e-8, then misses the neutral one
/// (89.999 degrees was called unstable); the cubic has 1 factored out and resolves it. False for
/// |beta0| = 1, where the roots' moduli multiply to 1 (no loss: marginal at best).
bool is_stable(const OrbitParams& params);

/// What `funnel orbit` reports for one parameter set.
struct OrbitAnalysis {
  Eigen::Vector4cd eigenvalues;        ///< of dF/dP1 at the orbit, sorted as eigenvalues()
  bool stable = false;                 ///< is_stable(params)
  double jacobian_max_rel_diff = 0.0;  ///< max |printed - finite differences| / max |printed|, scaled form
};

/// Eigenvalues, stability and the agreement of the printed Jacobian with finite differences at y*.
OrbitAnalysis analyse(const OrbitParams& params, double y_star);

}  // namespace funnel::orbit
