// Counter-based random numbers: Philox4x64-10 known answers, ranges and moments of the draws.
#include "funnel/random.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace funnel {
namespace {

TEST(Random, Philox4x64MatchesTheReferenceKnownAnswers) {
  // Known-answer vectors of the reference implementation (Random123, kat_vectors: philox4x64 10).
  using A4 = std::array<std::uint64_t, 4>;
  using A2 = std::array<std::uint64_t, 2>;
  EXPECT_EQ(philox4x64(A4{0, 0, 0, 0}, A2{0, 0}),
            (A4{0x16554d9eca36314cULL, 0xdb20fe9d672d0fdcULL, 0xd7e772cee186176bULL, 0x7e68b68aec7ba23bULL}));
  const std::uint64_t f = ~0ULL;
  EXPECT_EQ(philox4x64(A4{f, f, f, f}, A2{f, f}),
            (A4{0x87b092c3013fe90bULL, 0x438c3c67be8d0224ULL, 0x9cc7d7c69cd777b6ULL, 0xa09caebf594f0ba0ULL}));
  EXPECT_EQ(philox4x64(A4{0x243f6a8885a308d3ULL, 0x13198a2e03707344ULL, 0xa4093822299f31d0ULL, 0x082efa98ec4e6c89ULL},
                       A2{0x452821e638d01377ULL, 0xbe5466cf34e90c6cULL}),
            (A4{0xa528f45403e61d95ULL, 0x38c72dbd566e9788ULL, 0xa5a1610e72fd18b5ULL, 0x57bd43b5e52b7fe6ULL}));
}

TEST(Random, DrawsArePureFunctionsOfSeedStreamIndexAndLane) {
  EXPECT_EQ(uniform(7, 1, 123, 2), uniform(7, 1, 123, 2));
  EXPECT_NE(uniform(7, 1, 123, 0), uniform(7, 1, 123, 1));
  EXPECT_NE(uniform(7, 1, 123), uniform(8, 1, 123));
  EXPECT_NE(uniform(7, 1, 123), uniform(7, 2, 123));
  EXPECT_NE(uniform(7, 1, 123), uniform(7, 1, 124));
  EXPECT_EQ(normal(3, 0, 9, 1), normal(3, 0, 9, 1));
}

TEST(Random, UniformAndNormalHaveTheirMoments) {
  // 200 000 draws: the sample moments lie within 5 standard errors of the exact ones.
  const int n = 200000;
  double su = 0.0, su2 = 0.0, sn = 0.0, sn2 = 0.0, sn4 = 0.0, cross = 0.0;
  double lo = 1.0, hi = 0.0;
  for (int k = 0; k < n; ++k) {
    const double u = uniform(42, 5, static_cast<std::uint64_t>(k), k % 4);
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    su += u;
    su2 += u * u;
    const double x = normal(42, 6, static_cast<std::uint64_t>(k), 0);
    const double y = normal(42, 6, static_cast<std::uint64_t>(k), 1);
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
  EXPECT_NEAR(cross / n, 0.0, 5.0 / std::sqrt(n));  // the two lanes of a pair are independent
}

}  // namespace
}  // namespace funnel
