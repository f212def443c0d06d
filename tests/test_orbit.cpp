// Tests of the period-2 orbit theory (paper Sec. IV and Appendix): maps, Jacobians, eigenvalues, stability.
#include "funnel/orbit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace {

using funnel::orbit::OrbitParams;
using funnel::orbit::State;
namespace orbit = funnel::orbit;

constexpr double deg = std::numbers::pi / 180.0;
const std::array<double, 3> kBeta0s{0.0, 0.31, -0.31};
const std::array<double, 6> kThetas{30.0, 46.0, 50.0, 60.0, 75.0, 85.0};
const std::array<double, 3> kHeights{0.05, 0.3, 0.9};

OrbitParams params_for(double theta_deg, double beta0) { return OrbitParams{theta_deg, beta0, 0.4, 0.01}; }

// Largest component-wise difference, each component measured in its natural scale (y*, sqrt y*, sqrt y*, sqrt y*/a).
double scaled_difference(const State& x, const State& y, double y_star, const OrbitParams& p) {
  return (x - y).cwiseQuotient(orbit::state_scale(y_star, p)).cwiseAbs().maxCoeff();
}

double max_abs(const Eigen::Matrix4d& m) { return m.cwiseAbs().maxCoeff(); }

// Eqs. (27)-(33) exactly as printed, with m = 1, I = kappa a^2 (an independent transcription of F1).
State printed_f1(const State& P, const OrbitParams& p) {
  const double th = p.theta_deg * deg, s = std::sin(th), co = std::cos(th), tn = std::tan(th);
  const double a = p.radius, I = p.kappa * a * a, m2 = a * a, b = p.beta0;
  const double y = P(0), u = P(1), v = P(2), w = P(3);
  const double root = std::sqrt((v - u * tn) * (v - u * tn) + 4 * y);
  const double t1 = v - u * tn + root;                                    // Eq. (27)
  const double q2 = u / co - s * root;
  return State(-y + u * t1 * tn,                                          // Eq. (28)
               (m2 - I * b) / (I + m2) * u - I * a / (I + m2) * (1 + b) * co * w -
                   (2 * m2 + I * (1 - b)) / (I + m2) * s * co * root,    // Eq. (31)
               (m2 - I * b) / (I + m2) * tn * u - I * a / (I + m2) * (1 + b) * s * w +
                   (1 - (2 * m2 + I * (1 - b)) / (I + m2) * s * s) * root,  // Eq. (32)
               -a * (1 + b) / (I + m2) * q2 + (I - m2 * b) / (I + m2) * w);  // Eq. (33)
}

// Eqs. (34)-(37) exactly as printed (F2).
State printed_f2(const State& P, const OrbitParams& p) {
  const double th = p.theta_deg * deg, s = std::sin(th), co = std::cos(th), tn = std::tan(th);
  const double a = p.radius, I = p.kappa * a * a, m2 = a * a, b = p.beta0;
  const double y = P(0), u = P(1), v = P(2), w = P(3);
  const double root = std::sqrt((v + u * tn) * (v + u * tn) + 4 * y);
  const double t2 = v + u * tn + root;
  return State(-y - u * tn * t2,                                                            // Eq. (34)
               (m2 - I * b) / (I + m2) * u - I * a * (1 + b) / (I + m2) * co * w +
                   (2 * m2 + I * (1 - b)) / (I + m2) * s * co * root,                      // Eq. (35)
               -(m2 - I * b) / (I + m2) * tn * u + I * a * (1 + b) / (I + m2) * s * w +
                   (1 - (2 * m2 + I * (1 - b)) / (I + m2) * s * s) * root,                 // Eq. (36)
               -a * (1 + b) / (I + m2) * (u / co + s * root) + (I - m2 * b) / (I + m2) * w);  // Eq. (37)
}

// Total energy E = (u^2 + v^2)/2 + kappa a^2 omega^2 / 2 + y (units mgH).
double energy(const State& P, const OrbitParams& p) {
  return 0.5 * (P(1) * P(1) + P(2) * P(2)) + 0.5 * p.kappa * p.radius * p.radius * P(3) * P(3) + P(0);
}

// A few states near (not on) the orbit, perturbed in every component by up to 20% of its scale.
std::vector<State> states_near_orbit(double y_star, const OrbitParams& p) {
  const State base = orbit::fixed_point(y_star, p);
  const Eigen::Vector4d scale = orbit::state_scale(y_star, p);
  std::vector<State> out;
  for (const Eigen::Vector4d& d : {Eigen::Vector4d(0.1, -0.2, 0.15, 0.05), Eigen::Vector4d(-0.2, 0.1, -0.1, -0.2),
                                   Eigen::Vector4d(0.05, 0.05, -0.2, 0.1)}) {
    out.push_back(base + d.cwiseProduct(scale));
  }
  return out;
}

std::vector<double> sorted_moduli(const Eigen::Vector4cd& values) {
  std::vector<double> m;
  for (const auto& x : values) m.push_back(std::abs(x));
  std::sort(m.begin(), m.end());
  return m;
}

TEST(OrbitMaps, FixedPointIsInvariantUnderPeriodMap) {
  for (double th : kThetas)
    for (double b : kBeta0s)
      for (double ys : kHeights) {
        const OrbitParams p = params_for(th, b);
        const State star = orbit::fixed_point(ys, p);
        EXPECT_LE(scaled_difference(orbit::period_map(star, p), star, ys, p), 1e-12)
            << "theta " << th << " beta0 " << b << " y* " << ys;
      }
}

TEST(OrbitMaps, FortyFiveDegreeFamilyIsPeriodTwoWithSpin) {
  for (double b : kBeta0s) {
    const OrbitParams p = params_for(45.0, b);
    for (const double ratio : {0.5, 1.0, 1.6, 3.0}) {
      const State star = orbit::fixed_point_45(0.4, ratio, p);
      EXPECT_LE(scaled_difference(orbit::period_map(star, p), star, 0.4, p), 1e-12) << "ratio " << ratio;
      // After the right-wall collision the velocity is turned by 90 degrees: (u, v) -> (-v, u).
      const State right = orbit::map_left_to_right(star, p);
      EXPECT_NEAR(right[1], -star[2], 1e-12);
      EXPECT_NEAR(right[2], star[1], 1e-12);
      EXPECT_NEAR(right[3], star[3], 1e-9 * std::fabs(star[3]) + 1e-12);
    }
    EXPECT_NE(orbit::fixed_point_45(0.4, 1.6, p)[3], 0.0);  // it spins unless u' = v'
  }
}

TEST(OrbitMaps, LeftCollisionStateMapsToItsMirrorImageOnTheRightWall) {
  for (double th : kThetas)
    for (double b : kBeta0s) {
      const OrbitParams p = params_for(th, b);
      const double ys = 0.3;
      EXPECT_LE(scaled_difference(orbit::map_left_to_right(orbit::fixed_point(ys, p), p),
                                  orbit::fixed_point_right(ys, p), ys, p),
                1e-12);
    }
}

TEST(OrbitMaps, FirstPrinciplesMapsAgreeWithPrintedEquations27To37) {
  for (double th : kThetas)
    for (double b : kBeta0s) {
      const OrbitParams p = params_for(th, b);
      const double ys = 0.3;
      for (const State& P : states_near_orbit(ys, p)) {
        EXPECT_LE(scaled_difference(orbit::map_left_to_right(P, p), printed_f1(P, p), ys, p), 1e-12);
        State mirror = P;
        mirror(1) = -P(1);
        EXPECT_LE(scaled_difference(orbit::map_right_to_left(mirror, p), printed_f2(mirror, p), ys, p), 1e-12);
      }
    }
}

TEST(OrbitMaps, ElasticStickingCollisionLosesExactlyTheSlipEnergy) {
  // Delta E_2 of Sec. II with e = 1: (1/2) m I (1 - beta0^2)/(I + m a^2) (q + a omega)^2.
  for (double th : kThetas)
    for (double b : kBeta0s) {
      const OrbitParams p = params_for(th, b);
      const double s = std::sin(th * deg), co = std::cos(th * deg);
      for (const State& P : states_near_orbit(0.3, p)) {
        const State after = orbit::map_left_to_right(P, p);
        // Velocity just before the right-wall collision: u unchanged, v from energy conservation in flight.
        const double u = P(1);
        const double v = -std::sqrt(P(2) * P(2) + 2 * (P(0) - after(0)));
        const double slip = u * co + v * s + p.radius * P(3);
        const double loss = 0.5 * p.kappa / (1 + p.kappa) * (1 - b * b) * slip * slip;
        EXPECT_NEAR(energy(P, p) - energy(after, p), loss, 1e-13 * energy(P, p));
        EXPECT_GT(slip * slip, 1e-6);  // the test states really slip
      }
      // On the orbit the slip is zero: energy is conserved.
      const State star = orbit::fixed_point(0.3, p);
      EXPECT_NEAR(energy(orbit::period_map(star, p), p), energy(star, p), 1e-14);
    }
}

TEST(OrbitJacobian, ChainRuleJacobianOfEachMapMatchesFiniteDifferencesAwayFromOrbit) {
  for (double th : kThetas)
    for (double b : kBeta0s) {
      const OrbitParams p = params_for(th, b);
      const double ys = 0.3;
      const Eigen::Vector4d scale = orbit::state_scale(ys, p);
      for (const State& P : states_near_orbit(ys, p)) {
        Eigen::Matrix4d fd;
        for (int j = 0; j < 4; ++j) {
          const double h = 1e-3 * scale(j);
          auto at = [&](double k) {
            State q = P;
            q(j) += k * h;
            return orbit::map_left_to_right(q, p);
          };
          fd.col(j) = (8.0 * (at(1) - at(-1)) - (at(2) - at(-2))) / (12.0 * h);
        }
        const Eigen::Matrix4d exact = orbit::jacobian_left_to_right(P, p);
        EXPECT_LE(max_abs(orbit::scaled_jacobian(fd - exact, ys, p)), 1e-11) << "theta " << th << " beta0 " << b;
      }
    }
}

TEST(OrbitJacobian, ExactJacobianAtOrbitMatchesFiniteDifferencesOfPeriodMap) {
  // Achieved: max |scaled FD - scaled exact| = 4.3e-12 over this grid (rel_step 1e-3, fourth-order stencil).
  for (double th : kThetas)
    for (double b : kBeta0s)
      for (double ys : kHeights) {
        const OrbitParams p = params_for(th, b);
        const Eigen::Matrix4d diff = orbit::jacobian_fd(ys, p) - orbit::jacobian_exact(ys, p);
        EXPECT_LE(max_abs(orbit::scaled_jacobian(diff, ys, p)), 1e-11)
            << "theta " << th << " beta0 " << b << " y* " << ys;
      }
}

TEST(OrbitJacobian, PrintedJacobianMatricesAgreeWithExactDerivatives) {
  // Both printed 4x4 matrices of Sec. IV are correct with the paper's c = (m a^2 - I beta0)/(I + m a^2).
  for (double th : kThetas)
    for (double b : kBeta0s)
      for (double ys : kHeights) {
        const OrbitParams p = params_for(th, b);
        const Eigen::Matrix4d d1 = orbit::jacobian_paper_left_to_right(ys, p) -
                                   orbit::jacobian_left_to_right(orbit::fixed_point(ys, p), p);
        const Eigen::Matrix4d d2 = orbit::jacobian_paper_right_to_left(ys, p) -
                                   orbit::jacobian_right_to_left(orbit::fixed_point_right(ys, p), p);
        EXPECT_LE(max_abs(orbit::scaled_jacobian(d1, ys, p)), 1e-13);
        EXPECT_LE(max_abs(orbit::scaled_jacobian(d2, ys, p)), 1e-13);
        const Eigen::Matrix4d d = orbit::jacobian_paper(ys, p) - orbit::jacobian_exact(ys, p);
        EXPECT_LE(max_abs(orbit::scaled_jacobian(d, ys, p)), 1e-13);
      }
}

TEST(OrbitStability, EigenvaluesDoNotDependOnOrbitHeightOrRadius) {
  const OrbitParams p = params_for(60.0, 0.31);
  const Eigen::Vector4cd ref = orbit::orbit_eigenvalues(p);
  for (double ys : kHeights)
    for (double a : {0.001, 0.01, 0.1}) {
      OrbitParams q = p;
      q.radius = a;
      const Eigen::Vector4cd ev = orbit::eigenvalues(orbit::jacobian_exact(ys, q));
      EXPECT_LE((ev - ref).cwiseAbs().maxCoeff(), 1e-12) << "y* " << ys << " a " << a;
    }
}

TEST(OrbitStability, OneEigenvalueEqualsOneForEveryAngle) {
  for (double b : kBeta0s)
    for (int th = 5; th <= 85; ++th) {
      const Eigen::Vector4cd ev = orbit::orbit_eigenvalues(params_for(th, b));
      EXPECT_LE((ev.array() - 1.0).abs().minCoeff(), 1e-12) << "theta " << th << " beta0 " << b;
    }
}

TEST(OrbitStability, OrbitIsStableAboveFortyFiveDegreesAndUnstableBelow) {
  for (double b : kBeta0s) {
    for (int th = 46; th <= 85; ++th) {
      const Eigen::Vector4cd ev = orbit::orbit_eigenvalues(params_for(th, b));
      EXPECT_TRUE(orbit::is_stable(ev)) << "theta " << th << " beta0 " << b;
      EXPECT_LT(std::abs(ev(1)), 1.0);  // sorted: ev(0) is the neutral 1, the others are inside the unit circle
    }
    for (int th = 5; th <= 44; ++th) {
      const Eigen::Vector4cd ev = orbit::orbit_eigenvalues(params_for(th, b));
      EXPECT_FALSE(orbit::is_stable(ev)) << "theta " << th << " beta0 " << b;
      EXPECT_GT(std::abs(ev(0)), 1.0);
    }
  }
}

TEST(OrbitStability, EigenvaluesAreSortedByDecreasingModulus) {
  for (double b : kBeta0s)
    for (double th : kThetas) {
      const Eigen::Vector4cd ev = orbit::orbit_eigenvalues(params_for(th, b));
      for (int i = 0; i + 1 < 4; ++i) EXPECT_GE(std::abs(ev(i)), std::abs(ev(i + 1)));
    }
}

TEST(OrbitStability, DeterminantOfPeriodJacobianIsBeta0Squared) {
  // At the orbit det dF1/dP1 = det dF2/dP2 = beta0: the collision maps p -> -p and slip -> -beta0 slip (docs/theory.md).
  for (double b : kBeta0s)
    for (double th : kThetas) {
      const OrbitParams p = params_for(th, b);
      EXPECT_NEAR(orbit::jacobian_exact(0.3, p).determinant(), b * b, 1e-12);
    }
}

TEST(OrbitAppendix, AppendixEigenvalueModuliMatchJacobianForBeta0Zero) {
  for (double kappa : {0.4, 2.0 / 3.0, 0.5})
    for (int th = 5; th <= 85; ++th) {
      if (th == 45) continue;  // double eigenvalue 1 with a Jordan block: computed only to ~sqrt(machine epsilon)
      const OrbitParams p{static_cast<double>(th), 0.0, kappa, 0.01};
      const auto lam = orbit::appendix_lambda(th, kappa);
      // Eq. (A1): lambda_3 = 0, lambda_4 = 1.
      const std::vector<double> expected = sorted_moduli(Eigen::Vector4cd(lam[0], lam[1], 0.0, 1.0));
      const std::vector<double> got = sorted_moduli(orbit::orbit_eigenvalues(p));
      for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(got[i], expected[i], 1e-12 * std::max(1.0, expected[i])) << "theta " << th << " kappa " << kappa;
      }
    }
}

TEST(OrbitAppendix, AppendixInequalitiesHoldOnEveryAngle) {
  for (double kappa : {0.4, 2.0 / 3.0, 0.5, 0.01, 100.0})
    for (int tenth = 1; tenth < 900; ++tenth) {
      const double th = tenth / 10.0;
      const auto [A, B] = orbit::appendix_ab(th, kappa);
      const double eta = std::pow(std::sin(th * deg), 2), c = 1 / (1 + kappa);
      const double x = 1 - 2 * (1 - c) * eta * (2 * eta - 1);
      EXPECT_NEAR(B, -x * x, 1e-13);   // B = -(1 - 2(1-c) eta (2 eta - 1))^2
      EXPECT_GT(A + 1, 0.0);           // Eq. (A8)
      EXPECT_LT(B - 2 * A, 1.0);       // Eq. (A9)
      if (th != 45.0) {
        EXPECT_EQ(A < 1, th > 45);          // Eq. (A10)
        EXPECT_EQ(B + 2 * A < 1, th > 45);  // Eq. (A11)
      }
    }
}

TEST(OrbitAppendix, ClosedFormCubicGivesTheNontrivialEigenvaluesForAnyBeta0) {
  for (double b : {-0.9, -0.31, 0.0, 0.31, 0.9})
    for (int th = 5; th <= 85; th += 5) {
      if (th == 45) continue;  // defective double eigenvalue; covered by AtFortyFiveDegreesTwoEigenvaluesMeetAtOne
      const OrbitParams p = params_for(th, b);
      const auto roots = orbit::cubic_eigenvalues(p);
      const Eigen::Vector4cd ev = orbit::orbit_eigenvalues(p);
      const std::vector<double> expected = sorted_moduli(Eigen::Vector4cd(roots[0], roots[1], roots[2], 1.0));
      const std::vector<double> got = sorted_moduli(ev);
      for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(got[i], expected[i], 1e-12) << "theta " << th << " beta0 " << b;
    }
}

TEST(OrbitAppendix, AtFortyFiveDegreesTwoEigenvaluesMeetAtOne) {
  // Sec. IV: lambda_1 = lambda_2 = 1 at 45 degrees for any beta0; the cubic is (lambda - 1)^2 (lambda - beta0^2).
  for (double b : kBeta0s) {
    const auto cubic = orbit::characteristic_cubic(params_for(45.0, b));
    EXPECT_NEAR(cubic.p2, -(2 + b * b), 1e-14);
    EXPECT_NEAR(cubic.p1, 1 + 2 * b * b, 1e-14);
    EXPECT_EQ(cubic.p0, -b * b);
  }
}

TEST(OrbitStability, TheOrbitIsStableUpTo90DegreesAndUnstableBelow45) {
  // Next to 90 degrees a second eigenvalue comes within 1e-8 of 1 (0.999999987 at 89.999), which
  // the Jacobian's eigensolver resolved only to 4e-8: it missed the neutral eigenvalue and called
  // the orbit unstable (found by an audit). The closed-form cubic has the neutral 1 factored out.
  for (const double b : kBeta0s) {
    for (const double th : {45.001, 60.0, 89.99, 89.996, 89.999, 89.9999}) {
      EXPECT_TRUE(orbit::is_stable(params_for(th, b))) << "theta " << th << " beta0 " << b;
      EXPECT_TRUE(orbit::analyse(params_for(th, b), 1.0).stable) << "theta " << th << " beta0 " << b;
    }
    for (const double th : {0.001, 30.0, 44.999, 45.0}) {
      EXPECT_FALSE(orbit::is_stable(params_for(th, b))) << "theta " << th << " beta0 " << b;
    }
  }
  // |beta0| = 1 loses no energy: the roots' moduli multiply to 1, marginal (rounding decided it:
  // about 800 of 9000 angles above 45 degrees were called stable).
  for (const double b : {-1.0, 1.0}) {
    for (double th = 0.5; th < 90.0; th += 0.5) EXPECT_FALSE(orbit::is_stable(params_for(th, b))) << th << " " << b;
  }
  const auto roots = orbit::cubic_eigenvalues(params_for(89.999, 0.0));
  EXPECT_NEAR(std::abs(roots[0]), 0.999999987206, 1e-12);  // an exact 40-digit computation's
}

TEST(OrbitStability, IsStableRequiresANeutralEigenvalue) {
  EXPECT_TRUE(orbit::is_stable(Eigen::Vector4cd(1.0, 0.5, 0.2, 0.0)));
  EXPECT_FALSE(orbit::is_stable(Eigen::Vector4cd(0.9, 0.5, 0.2, 0.0)));  // no eigenvalue at 1
  EXPECT_FALSE(orbit::is_stable(Eigen::Vector4cd(1.0, 1.2, 0.2, 0.0)));
  EXPECT_FALSE(orbit::is_stable(Eigen::Vector4cd(1.0, std::complex<double>(0.0, 1.0), 0.2, 0.0)));
}

}  // namespace
