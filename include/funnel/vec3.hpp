// A small 3-vector value type for the axisymmetric funnel in 3D (docs/model.md, "3D").
#pragma once

#include <cmath>

namespace funnel {

/// A point or a vector in space: x and z horizontal, y vertically up; (x, y, z) is right-handed.
struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
/// Dot product, summed in the order x, y, z (so that a vector with z = 0 gives the 2D bits).
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// Cross product a x b.
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
/// Euclidean length.
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

}  // namespace funnel
