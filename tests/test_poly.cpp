// Polynomial root isolation: known factors, multiple and grazing roots, first approach.
#include "funnel/poly.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

}  // namespace
}  // namespace funnel
