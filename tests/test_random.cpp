// Counter-based random numbers: Philox4x32-10 known answers, ranges and moments of the draws.
#include "funnel/random.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace funnel {
namespace {

TEST(Random, Philox4x32MatchesTheReferenceKnownAnswers) {
  // Known-answer vectors of the reference implementation (Random123, kat_vectors: philox4x32 10):
  // the first two output words, word 1 in the high half.
  EXPECT_EQ(philox(0, 0, 0), 0xe169c58d6627e8d5ULL);
  const std::uint64_t f = ~0ULL;
  EXPECT_EQ(philox(f, f, f), 0x41c83b0e408f276dULL);
  EXPECT_EQ(philox(0x299f31d0a4093822ULL, 0x0370734413198a2eULL, 0x85a308d3243f6a88ULL), 0x94fdccebd16cfe09ULL);
}

TEST(Random, DrawsArePureFunctionsOfSeedStreamAndIndex) {
  EXPECT_EQ(uniform01(7, 1, 123), uniform01(7, 1, 123));
  EXPECT_NE(uniform01(7, 1, 123), uniform01(8, 1, 123));
  EXPECT_NE(uniform01(7, 1, 123), uniform01(7, 2, 123));
  EXPECT_NE(uniform01(7, 1, 123), uniform01(7, 1, 124));
  EXPECT_EQ(standard_normal(3, 0, 9), standard_normal(3, 0, 9));
}

TEST(Random, UniformAndNormalHaveTheirMoments) {
  // 200 000 draws: the sample moments lie within 5 standard errors of the exact ones.
  const int n = 200000;
  double su = 0.0, su2 = 0.0, sn = 0.0, sn2 = 0.0, sn4 = 0.0, cross = 0.0;
  double lo = 1.0, hi = 0.0;
  for (int k = 0; k < n; ++k) {
    const auto index = static_cast<std::uint64_t>(k);
    const double u = uniform01(42, 5, index);
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    su += u;
    su2 += u * u;
    const double x = standard_normal(42, 6, index);
    const double y = standard_normal(42, 7, index);
    sn += x;
    sn2 += x * x;
    sn4 += x * x * x * x;
    cross += x * y;
  }
  EXPECT_GT(lo, 0.0);
  EXPECT_LT(hi, 1.0);
  EXPECT_NEAR(su / n, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));
  EXPECT_NEAR(su2 / n, 1.0 / 3.0, 5.0 * std::sqrt(4.0 / 45.0 / n));
  EXPECT_NEAR(sn / n, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sn2 / n, 1.0, 5.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(sn4 / n, 3.0, 5.0 * std::sqrt(96.0 / n));
  EXPECT_NEAR(cross / n, 0.0, 5.0 / std::sqrt(n));  // two streams are independent
}

}  // namespace
}  // namespace funnel
