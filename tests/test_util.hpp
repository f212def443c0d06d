// Shared helpers of the test suite.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "funnel/engine.hpp"

namespace funnel::test {

/// |a - b| <= rel * max(|a|, |b|) + abs: the one tolerance check of the suite.
inline ::testing::AssertionResult near(double a, double b, double rel, double abs = 0.0) {
  const double tol = rel * std::max(std::fabs(a), std::fabs(b)) + abs;
  if (std::fabs(a - b) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << " differ by " << std::fabs(a - b)
                                       << " > tolerance " << tol;
}

/// The same double, bit for bit (a NaN equals itself, +0 differs from -0).
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline bool same_state(const State& a, const State& b) {
  return same_bits(a.r.x, b.r.x) && same_bits(a.r.y, b.r.y) && same_bits(a.v.x, b.v.x) && same_bits(a.v.y, b.v.y) &&
         same_bits(a.omega, b.omega);
}

/// Every field of two trajectories the same, bit for bit.
inline ::testing::AssertionResult same_trajectory(const Trajectory& a, const Trajectory& b) {
  const bool same = a.status == b.status && same_bits(a.duration, b.duration) && same_bits(a.impulse, b.impulse) &&
                    same_bits(a.normal_impulse, b.normal_impulse) && same_bits(a.energy_loss, b.energy_loss) &&
                    same_bits(a.energy_loss_events, b.energy_loss_events) && a.collisions == b.collisions &&
                    a.edge_collisions == b.edge_collisions && a.contacts == b.contacts &&
                    a.edge_contacts == b.edge_contacts && same_bits(a.contact_time, b.contact_time) &&
                    a.stopped == b.stopped && a.stalled == b.stalled && same_state(a.final_state, b.final_state) &&
                    same_state(a.exit_state, b.exit_state) && a.slid == b.slid;
  if (same) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "duration " << a.duration << " vs " << b.duration << ", collisions "
                                       << a.collisions << " vs " << b.collisions << ", impulse " << a.impulse
                                       << " vs " << b.impulse << ", slid " << a.slid << " vs " << b.slid;
}

}  // namespace funnel::test
