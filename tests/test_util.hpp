// Shared helpers of the test suite.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "funnel/cone.hpp"
#include "funnel/engine.hpp"
#include "same_bits.hpp"

namespace funnel::test {

/// An integer or a number from the environment variable `name`, or `fallback` when it is unset
/// or empty (the random campaigns' case counts and seeds).
inline std::int64_t env_integer(const char* name, std::int64_t fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::strtoll(v, nullptr, 10) : fallback;
}

inline double env_double(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::strtod(v, nullptr) : fallback;
}

/// |a - b| <= rel * max(|a|, |b|) + abs: the one tolerance check of the suite.
inline ::testing::AssertionResult near(double a, double b, double rel, double abs = 0.0) {
  const double tol = rel * std::max(std::fabs(a), std::fabs(b)) + abs;
  if (std::fabs(a - b) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << " differ by " << std::fabs(a - b)
                                       << " > tolerance " << tol;
}

/// Every field of two trajectories the same, bit for bit (identical), with a message if not.
inline ::testing::AssertionResult same_trajectory(const Trajectory& a, const Trajectory& b) {
  if (identical(a, b)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "duration " << a.duration << " vs " << b.duration << ", collisions "
                                       << a.collisions << " vs " << b.collisions << ", impulse " << a.impulse
                                       << " vs " << b.impulse << ", slid " << a.slid << " vs " << b.slid;
}

/// Every field of two 3D trajectories the same, bit for bit (identical), with a message if not.
inline ::testing::AssertionResult same_trajectory(const Trajectory3& a, const Trajectory3& b) {
  if (identical(a, b)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "duration " << a.duration << " vs " << b.duration << ", collisions "
                                       << a.collisions << " vs " << b.collisions << ", impulse " << a.impulse
                                       << " vs " << b.impulse << ", ode steps " << a.ode_steps << " vs " << b.ode_steps;
}

/// Rotation by `angle` about the vertical axis (right-handed about +y).
inline Vec3 rotate(Vec3 v, double angle) {
  return {v.x * std::cos(angle) + v.z * std::sin(angle), v.y, -v.x * std::sin(angle) + v.z * std::cos(angle)};
}
/// A 3D state rotated by `angle` about the vertical axis: position, velocity and spin.
inline State3 rotate(const State3& s, double angle) {
  return {rotate(s.r, angle), rotate(s.v, angle), rotate(s.omega, angle)};
}

}  // namespace funnel::test
