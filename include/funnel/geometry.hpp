// Funnel geometry (docs/model.md §2): centre lines, finite walls, edges and the release line.
#pragma once

#include "funnel/params.hpp"

namespace funnel {

/// A point or a vector in the plane of the funnel (x horizontal, y up).
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }

/// The two walls of the funnel.
enum class Wall { Left, Right };

/// Mirror sign of a wall: -1 for the left wall, +1 for the right one.
inline double wall_sign(Wall wall) { return wall == Wall::Left ? -1.0 : 1.0; }

/// Derived geometry of the 2D funnel; origin where the two centre lines meet.
/// The right wall is the mirror image (x -> -x) of the left one.
struct Geometry {
  double sin_t = 0.0;      ///< sin(theta)
  double cos_t = 0.0;      ///< cos(theta)
  double tan_t = 0.0;      ///< tan(theta)
  double radius = 0.0;     ///< particle radius a
  double half_gap = 0.0;   ///< d/2; 0 for a closed funnel
  bool closed = false;     ///< d = 0: the walls meet at the vertex, no edges, no exit
  double y_bottom = 0.0;   ///< y_b, height of the edges (the funnel bottom); exit level
  double y_release = 0.0;  ///< y_0 = y_b + H0, release height of the centre
  double half_width = 0.0; ///< L = y_0 / tan(theta), half the opening for the centre at y_0
  double y_face_end = 0.0; ///< height of C*, the lower end of the face-contact region (0 if closed)
  double x_face_end = 0.0; ///< |x| of C*_R (C*_L is at -x_face_end); 0 if closed
};

/// Geometry of the funnel described by already validated parameters.
Geometry make_geometry(const Params& params);

/// Inward unit normal of a wall face: n_L = (sin, cos), n_R = (-sin, cos).
inline Vec2 face_normal(const Geometry& g, Wall wall) { return {-wall_sign(wall) * g.sin_t, g.cos_t}; }

/// Lower edge point E of a wall: (-d/2, y_b) or (d/2, y_b).
inline Vec2 edge_point(const Geometry& g, Wall wall) { return {wall_sign(wall) * g.half_gap, g.y_bottom}; }

/// Signed distance of a centre position from a wall's centre line, positive inside the funnel.
inline double face_distance(const Geometry& g, Wall wall, Vec2 r) {
  return -wall_sign(wall) * g.sin_t * r.x + g.cos_t * r.y;
}

/// Release position of the centre for x0 = fraction * L, fraction in (-1, 1).
inline Vec2 release_point(const Geometry& g, double fraction) { return {fraction * g.half_width, g.y_release}; }

}  // namespace funnel
