// Shared helpers of the test suite.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace funnel::test {

/// |a - b| <= rel * max(|a|, |b|) + abs: the one tolerance check of the suite.
inline ::testing::AssertionResult near(double a, double b, double rel, double abs = 0.0) {
  const double tol = rel * std::max(std::fabs(a), std::fabs(b)) + abs;
  if (std::fabs(a - b) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << " differ by " << std::fabs(a - b)
                                       << " > tolerance " << tol;
}

}  // namespace funnel::test
