// The 3D face time of many flights at once in SIMD lanes (internal to the library): see
// src/batch3d.cpp for the kernel and src/flight3d.cpp (cone_face_times) for its caller.
#pragma once

#include <cstddef>

namespace funnel::batch {

/// The most flights face_times takes at once.
inline constexpr std::size_t max_flights = 16;

/// The cone, as cone_face_time reads it.
struct FaceConstants {
  double sin_t, cos_t, x_face_end, y_face_end;
  bool closed;
  int max_iterations;  ///< iterations of the fixed point before the bracketing fallback
};

/// The flights, structure of arrays; lanes [0, n) are read, lanes up to n rounded up to the
/// vector width must have active = 0.
struct FaceFlights {
  alignas(64) double rx[max_flights];
  alignas(64) double ry[max_flights];
  alignas(64) double rz[max_flights];
  alignas(64) double vx[max_flights];
  alignas(64) double vy[max_flights];
  alignas(64) double vz[max_flights];
  alignas(64) double bx[max_flights];       ///< meridian_direction(r): the first half-plane
  alignas(64) double bz[max_flights];
  alignas(64) double on_face[max_flights];  ///< 1 if the flight starts on the face (FlightStart3::on_face), else 0
  alignas(64) double active[max_flights];   ///< 1 for a flight to iterate, 0 for none
  alignas(64) double t_best[max_flights];   ///< out: the fixed point's last time (never if none)
  alignas(64) double fallback[max_flights]; ///< out: 1 if the iteration cap was reached, else 0
  std::size_t n = 0;
};

/// The fixed point of cone_face_time for every active flight: t_best and fallback as its scalar
/// iteration leaves them (the same bits), before its fallback and its check that the hit is on
/// the face.
void face_times(const FaceConstants& k, FaceFlights& f);

}  // namespace funnel::batch
