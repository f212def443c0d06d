// The batched face-to-face step (internal to the library): many trajectories of one funnel in
// the lanes of a SIMD vector. See src/batch.cpp for the kernel and src/engine.cpp for the driver.
#pragma once

#include <cstdint>

namespace funnel::batch {

/// Vectors of lanes face_steps steps side by side (src/batch.cpp: each hides the other's latency).
inline constexpr int tracks = 2;

/// Lanes the widest path steps at once: two vectors of AVX-512's 8 doubles.
inline constexpr int max_lanes = tracks * 8;

/// Codes of how a lane's current flight began (the scalar engine's FlightStart), as doubles.
inline constexpr double start_fresh = -1.0;  ///< nothing set (a release)
inline constexpr double start_left = 0.0;    ///< on the left face's centre line only
inline constexpr double start_right = 1.0;   ///< on the right face's centre line only
inline constexpr double start_other = 2.0;   ///< anything else: the scalar engine steps it
inline constexpr double start_idle = 3.0;    ///< no trajectory in this lane

/// One wall's face and collision law, as the scalar engine reads them.
struct SideConstants {
  double nx, ny, refx, refy, lowx, lowy, upx, upy;
  double low_ok;  ///< 1 if the face's lower end is at or above the skip height, else 0
  double e, mu, one_plus_e, slide_factor, one_plus_beta0, reduced, kappa_a, half_1_minus_e2, half_reduced,
      radius;
};

/// Everything the common step needs besides the lanes.
struct Constants {
  SideConstants side[2];  ///< left, right
  double skip_height;     ///< a flight starting above it meets no edge and no exit
  // A face whose region reaches below skip_height (the steeper wall of an asymmetric V): a
  // landing on it above skip_height is the common step too, once the exit (at y_exit) is shown
  // to come later, as the scalar search's slow path checks it.
  double low_landing;      ///< 1 if a side's low_ok is 0, else 0
  double y_exit;
  double t_max, p_c, max_collisions;
  // A closed V: no region to check, no edge, no exit; a collision that leaves less than
  // eps_rest of energy above y_rest is the scalar engine's (rest).
  double closed;           ///< 1 closed, 0 open
  double y_rest, eps_rest;
  double spin_energy;      ///< 0.5 kappa a a, as the energy is computed (energy() in walton.hpp)
  double vertex_tolerance; ///< a collision less than this above y_rest is the scalar engine's (Funnel::vertex_tolerance)
  // The orbit watch of a closed funnel (funnel/watch.hpp), if `watch` is 1.
  double watch, window, slip_tol, height_tol;
};

/// The lanes' state, structure of arrays.
struct Lanes {
  alignas(64) double rx[max_lanes];
  alignas(64) double ry[max_lanes];
  alignas(64) double vx[max_lanes];
  alignas(64) double vy[max_lanes];
  alignas(64) double omega[max_lanes];
  alignas(64) double time[max_lanes];
  alignas(64) double impulse[max_lanes];
  alignas(64) double normal_impulse[max_lanes];
  alignas(64) double energy_loss[max_lanes];
  alignas(64) double collisions[max_lanes];
  alignas(64) double start[max_lanes];  ///< start_* codes
  alignas(64) double slid[max_lanes];   ///< 1 once a collision slid (Trajectory::slid), else 0
  // The orbit watch's memory (OrbitWatch::Memory) when Constants::watch is 1.
  alignas(64) double streak[max_lanes];
  alignas(64) double have_last[max_lanes];  ///< 0 or 1
  alignas(64) double last_wall[max_lanes];  ///< 0 left, 1 right
  alignas(64) double last_x[max_lanes];
  alignas(64) double last_y[max_lanes];
  alignas(64) double prev_x[max_lanes];
  alignas(64) double prev_y[max_lanes];
};

/// Steps every busy lane through flight and face collision for as long as each lane's next event
/// is the common one: a flight from a face (or a release) to a face above the edges, ending in a
/// collision that leaves a normal speed of at least p_c, within the time and collision caps. Returns the bit mask of
/// busy lanes whose next event is not (they were not stepped by the last round): the scalar
/// engine takes them. Lanes [0, width()) are used. Every operation is the scalar engine's, in
/// its order (IEEE-exact in each lane), so the results are the same bits.
std::uint32_t face_steps(const Constants& k, Lanes& lanes);

/// Doubles in a vector of the path in use (2 SSE4, 4 AVX2, 8 AVX-512).
int vector_lanes();

/// Lanes face_steps uses on the path in use: tracks vectors' worth.
int width();

}  // namespace funnel::batch
