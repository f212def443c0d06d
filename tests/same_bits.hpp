// Bit-for-bit comparison of doubles, states and trajectories (test and fuzz support, not the
// library; no GoogleTest, so that the fuzz targets use the same comparison as the tests).
#pragma once

#include <cstring>

#include "funnel/engine.hpp"
#include "funnel/engine3d.hpp"

namespace funnel::test {

/// The same double, bit for bit (a NaN equals itself, +0 differs from -0).
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline bool same_state(const State& a, const State& b) {
  return same_bits(a.r.x, b.r.x) && same_bits(a.r.y, b.r.y) && same_bits(a.v.x, b.v.x) && same_bits(a.v.y, b.v.y) &&
         same_bits(a.omega, b.omega);
}

/// Every field of two trajectories the same, bit for bit.
inline bool identical(const Trajectory& a, const Trajectory& b) {
  return a.status == b.status && same_bits(a.duration, b.duration) && same_bits(a.impulse, b.impulse) &&
         same_bits(a.normal_impulse, b.normal_impulse) && same_bits(a.energy_loss, b.energy_loss) &&
         same_bits(a.energy_loss_events, b.energy_loss_events) && a.collisions == b.collisions &&
         a.edge_collisions == b.edge_collisions && a.contacts == b.contacts && a.edge_contacts == b.edge_contacts &&
         same_bits(a.contact_time, b.contact_time) && a.stopped == b.stopped && a.stalled == b.stalled &&
         same_state(a.final_state, b.final_state) && same_state(a.exit_state, b.exit_state) && a.slid == b.slid;
}

inline bool same_vec(Vec3 a, Vec3 b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }

inline bool same_state(const State3& a, const State3& b) {
  return same_vec(a.r, b.r) && same_vec(a.v, b.v) && same_vec(a.omega, b.omega);
}

/// Every field of two 3D trajectories the same, bit for bit.
inline bool identical(const Trajectory3& a, const Trajectory3& b) {
  return a.status == b.status && same_bits(a.duration, b.duration) && same_bits(a.impulse, b.impulse) &&
         same_bits(a.normal_impulse, b.normal_impulse) && same_bits(a.energy_loss, b.energy_loss) &&
         same_bits(a.energy_loss_events, b.energy_loss_events) && a.collisions == b.collisions &&
         a.edge_collisions == b.edge_collisions && a.contacts == b.contacts && a.edge_contacts == b.edge_contacts &&
         same_bits(a.contact_time, b.contact_time) && same_bits(a.orbits, b.orbits) && a.ode_steps == b.ode_steps &&
         a.periodic == b.periodic && a.stopped == b.stopped && a.stalled == b.stalled &&
         same_state(a.final_state, b.final_state) && same_state(a.exit_state, b.exit_state);
}

}  // namespace funnel::test
