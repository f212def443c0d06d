// Polynomial root isolation: known factors, multiple and grazing roots, first approach.
#include "funnel/poly.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <bit>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

/// The monic polynomial with the given roots.
Poly from_roots(const std::vector<double>& roots) {
  Poly p;
  p.degree = 0;
  p.c[0] = 1.0;
  for (const double r : roots) {
    Poly f;
    f.degree = 1;
    f.c[0] = -r;
    f.c[1] = 1.0;
    p = p * f;
  }
  return p;
}

TEST(Poly, RecoversTheRootsOfAProductOfFactors) {
  const std::vector<double> roots{-0.7, 0.013, 0.25, 0.31, 0.9, 1.7, 2.5, 3.0};
  const Poly p = from_roots(roots);
  ASSERT_EQ(p.degree, 8);
  std::array<double, 8> found{};
  ASSERT_EQ(real_roots(p, -1.0, 4.0, found), 8);
  for (std::size_t i = 0; i < roots.size(); ++i) EXPECT_TRUE(near(found[i], roots[i], 1e-12, 1e-14)) << i;
  // Only those inside the interval.
  EXPECT_EQ(real_roots(p, 0.2, 1.0, found), 3);
  EXPECT_TRUE(near(found[0], 0.25, 1e-12));
  // Two roots 1e-4 apart are separated (each known to its conditioning, ~1e-12 here).
  const Poly close = from_roots({-0.7, 0.013, 0.25, 0.2501, 0.9, 1.7, 2.5, 3.0});
  ASSERT_EQ(real_roots(close, 0.2, 0.3, found), 2);
  EXPECT_TRUE(near(found[0], 0.25, 1e-11));
  EXPECT_TRUE(near(found[1], 0.2501, 1e-11));
}

TEST(Poly, FindsADoubleRootWhereThePolynomialTouchesZero) {
  // (t - 0.3)^2 (t - 2)(t + 1) (t^2 + 1): a touch at 0.3 between a sign change at 2.
  Poly p = from_roots({0.3, 0.3, 2.0, -1.0});
  Poly q;
  q.degree = 2;
  q.c = {1.0, 0.0, 1.0};
  p = p * q;
  std::array<double, 8> found{};
  const int n = real_roots(p, 0.0, 3.0, found);
  ASSERT_GE(n, 2);
  EXPECT_NEAR(found[0], 0.3, 1e-7);  // a double root is known to about sqrt(eps)
  EXPECT_TRUE(near(found[n - 1], 2.0, 1e-13));
}

TEST(Poly, FirstDescendingRootIsTheFirstApproach) {
  // p > 0 outside the surface: (t - 0.5)(t - 1.5)(t - 3)(t - 4) is positive on (0, 0.5).
  const Poly p = from_roots({0.5, 1.5, 3.0, 4.0});
  EXPECT_TRUE(near(first_descending_root(p, 10.0), 0.5, 1e-14));
  EXPECT_EQ(first_descending_root(p, 0.4), std::numeric_limits<double>::infinity());
  // Starting on the surface (p(0) = 0) and moving out: the root at 0 is not found again.
  const Poly q = from_roots({0.0, -1.0, 2.0, 3.0});  // -> sign after 0 is that of c1
  ASSERT_EQ(q.c[0], 0.0);
  EXPECT_GT(q.c[1], 0.0);
  EXPECT_TRUE(near(first_descending_root(q, 10.0), 2.0, 1e-14));
}

TEST(Poly, GrazingApproachIsFoundAndAMissIsNot) {
  // p(t) = (t - 1)^2 - d: a parabola that dips just below zero (d > 0) or not (d < 0), scaled
  // to an octic by a positive factor (t^2 + 1)^3.
  Poly base;
  base.degree = 2;
  Poly s;
  s.degree = 2;
  s.c = {1.0, 0.0, 1.0};
  const Poly pos = s * s * s;
  for (const double d : {1e-10, 1e-12}) {
    base.c = {1.0 - d, -2.0, 1.0};
    const double t = first_descending_root(base * pos, 5.0);
    EXPECT_LE(t, 1.0) << d;  // the first of the two roots 1 -+ sqrt(d)
    EXPECT_GT(t, 1.0 - 2.0 * std::sqrt(d)) << d;
  }
  base.c = {1.0 + 1e-12, -2.0, 1.0};
  EXPECT_EQ(first_descending_root(base * pos, 5.0), std::numeric_limits<double>::infinity());
}

/// Random polynomials of degree 2..8 whose roots crowd [0, hi] and its ends (double roots, pairs a
/// few ulps apart, roots just outside), times a positive quadratic sometimes: the hard cases for
/// a proof that a polynomial keeps its sign.
struct HardPolys {
  std::mt19937_64 rng;
  explicit HardPolys(std::uint64_t seed) : rng(seed) {}
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  Poly next(double hi, std::vector<double>& roots) {
    roots.clear();
    const int degree = 2 + static_cast<int>(rng() % 7);
    while (static_cast<int>(roots.size()) < degree) {
      const int kind = static_cast<int>(rng() % 6);
      double r = kind == 0   ? uniform(-hi, 2.0 * hi)
                 : kind == 1 ? hi * (1.0 + std::ldexp(uniform(-1.0, 1.0), -static_cast<int>(rng() % 50)))  // next to hi
                 : kind == 2 ? hi * std::ldexp(uniform(-1.0, 1.0), -static_cast<int>(rng() % 50))  // next to 0
                 : kind == 3 && !roots.empty() ? roots.back()  // a double root
                 : kind == 4 && !roots.empty() ? roots.back() * (1.0 + std::ldexp(uniform(-1.0, 1.0), -48))
                                               : uniform(1.5 * hi, 3.0 * hi);
      roots.push_back(r);
    }
    Poly p = from_roots(roots);
    if (degree <= 6 && rng() % 2 == 0) {
      Poly q;  // (t - m)^2 + w^2 > 0
      q.degree = 2;
      const double m = uniform(0.0, hi), w = hi * std::ldexp(1.0, -static_cast<int>(rng() % 40));
      q.c = {m * m + w * w, -2.0 * m, 1.0};
      p = p * q;
    }
    const double scale = std::ldexp(uniform(0.5, 1.0) * (rng() % 2 == 0 ? 1.0 : -1.0), static_cast<int>(rng() % 40) - 20);
    for (int k = 0; k <= p.degree; ++k) p.c[static_cast<std::size_t>(k)] *= scale;
    return p;
  }
};

double step_ulps(double t, std::int64_t k) {
  return std::bit_cast<double>(std::bit_cast<std::int64_t>(t) + k);
}

TEST(Poly, OneSignFromZeroHoldsAtEveryDoubleItClaims) {
  // Wherever the Bernstein proof says p keeps one sign on [0, hi], Horner's value must have that
  // sign, nonzero, at the doubles where it is most likely not to: next to each root of p (in
  // and just beyond [0, hi]), at both ends and at random points; and real_roots (without the
  // shortcut) must find no root there. The proof must also say yes often, or it would be worth
  // nothing (and this test would test nothing).
  HardPolys gen(20261125);
  std::vector<double> roots;
  int proved = 0, refused = 0;
  for (int n = 0; n < 20000; ++n) {
    const double hi = std::ldexp(gen.uniform(0.5, 1.0), static_cast<int>(gen.rng() % 60) - 30);
    const Poly p = gen.next(hi, roots);
    if (!detail::one_sign_from_zero(p, hi)) {
      ++refused;
      continue;
    }
    ++proved;
    const bool positive = p(0.0) > 0.0;
    std::vector<double> ts{0.0, hi, std::nextafter(hi, 0.0)};
    for (const double r : roots) {
      const double t0 = std::clamp(r, 0.0, hi);
      for (std::int64_t k = -40; k <= 40; ++k) {
        const double t = t0 > 0.0 ? step_ulps(t0, k) : std::ldexp(static_cast<double>(std::abs(k)), -1074);
        if (t >= 0.0 && t <= hi) ts.push_back(t);
      }
    }
    for (int k = 0; k < 64; ++k) ts.push_back(gen.uniform(0.0, hi));
    for (const double t : ts) {
      const double v = p(t);
      ASSERT_TRUE(positive ? v > 0.0 : v < 0.0) << "n " << n << " t " << t << " p(t) " << v;
    }
    std::array<double, 8> found{};
    ASSERT_EQ(detail::real_roots_reference(p, 0.0, hi, found), 0) << n;
  }
  EXPECT_GT(proved, 2000);
  EXPECT_GT(refused, 2000);
}

TEST(Poly, TheRootsAreTheSameBitsWithAndWithoutTheOneSignShortcut) {
  // The shortcut skips the search of a derivative's roots where it has none: the knots, and so
  // every root, must be the very same doubles as the full search's.
  HardPolys gen(77);
  std::vector<double> roots;
  int differing_paths = 0;
  for (int n = 0; n < 20000; ++n) {
    const double hi = std::ldexp(gen.uniform(0.5, 1.0), static_cast<int>(gen.rng() % 20) - 10);
    const Poly p = gen.next(hi, roots);
    const double t = first_descending_root(p, hi), t_ref = detail::first_descending_root_reference(p, hi);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(t), std::bit_cast<std::uint64_t>(t_ref)) << n;
    std::array<double, 8> a{}, b{};
    const int na = real_roots(p, 0.0, hi, a), nb = detail::real_roots_reference(p, 0.0, hi, b);
    ASSERT_EQ(na, nb) << n;
    for (int k = 0; k < na; ++k) {
      ASSERT_EQ(std::bit_cast<std::uint64_t>(a[static_cast<std::size_t>(k)]), std::bit_cast<std::uint64_t>(b[static_cast<std::size_t>(k)])) << n;
    }
    differing_paths += p.degree >= 3 && detail::one_sign_from_zero(p.derivative(), hi);
  }
  EXPECT_GT(differing_paths, 1000);  // the shortcut was taken, not only the full search
}

}  // namespace
}  // namespace funnel
