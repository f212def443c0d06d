// The axisymmetric funnel in 3D: the 2D funnel's meridian section revolved about the vertical
// axis (docs/model.md §9). A cone face at angle theta, a circular
// outlet of diameter d whose rim is a circle; the same parameters and frame as in 2D, with z the
// second horizontal axis.
#pragma once

#include <cmath>

#include "funnel/geometry.hpp"
#include "funnel/params.hpp"
#include "funnel/vec3.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// Kinematic state of the sphere in 3D: centre position, velocity and spin vector.
struct State3 {
  Vec3 r;      ///< centre position, units H
  Vec3 v;      ///< centre velocity, units sqrt(gH)
  Vec3 omega;  ///< angular velocity (right-handed about each axis), units sqrt(g/H)
};

/// Total mechanical energy |v|^2/2 + kappa a^2 |omega|^2/2 + y, units m g H.
inline double energy(const State3& s, double kappa, double radius) {
  return 0.5 * dot(s.v, s.v) + 0.5 * kappa * radius * radius * dot(s.omega, s.omega) + s.r.y;
}

/// Orbital angular momentum of the centre about the vertical axis, (r x v)_y = z u - x w, units m H sqrt(gH).
inline double orbital_momentum_y(const State3& s) { return s.r.z * s.v.x - s.r.x * s.v.z; }

/// Total angular momentum about the vertical axis: orbital + kappa a^2 omega_y, units m H sqrt(gH).
inline double angular_momentum_y(const State3& s, double kappa, double radius) {
  return orbital_momentum_y(s) + kappa * radius * radius * s.omega.y;
}

/// The axisymmetric funnel. Its meridian section is the 2D funnel of the same parameters, whose
/// right half (x >= 0) is revolved: the centre cone y = rho tan(theta) above C*, and the rim, the
/// circle of radius d/2 at height y_b.
struct Cone {
  Geometry g;               ///< the meridian section (2D numbers: y_b, C*, y_0, L)
  double rim_radius = 0.0;  ///< R = d/2, radius of the rim circle, units H (0 when closed)
};

/// The cone of already validated parameters.
Cone make_cone(const Params& params);

/// Distance of a point from the vertical axis, sqrt(x^2 + z^2) (positions are O(1): no scaling
/// as in hypot is needed; sqrt(x^2) is |x| exactly, so a point with z = 0 gives the 2D numbers).
inline double axis_distance(Vec3 r) { return std::sqrt(r.x * r.x + r.z * r.z); }

/// Unit horizontal direction (b_x, 0, b_z) of the meridian half-plane through r; (1, 0, 0) on the axis.
Vec3 meridian_direction(Vec3 r);

/// Unit horizontal direction normal to the meridian half-plane b: (-b_z, 0, b_x) (the 2D +z axis).
inline Vec3 azimuthal_direction(Vec3 b) { return {-b.z, 0.0, b.x}; }

/// Inward unit normal of the cone face in the meridian half-plane b: (-sin b_x, cos, -sin b_z).
inline Vec3 cone_normal(const Cone& c, Vec3 b) { return {-c.g.sin_t * b.x, c.g.cos_t, -c.g.sin_t * b.z}; }

/// Nearest point of the rim circle to a centre in the meridian half-plane b.
inline Vec3 rim_point(const Cone& c, Vec3 b) { return {c.rim_radius * b.x, c.g.y_bottom, c.rim_radius * b.z}; }

/// Distance up the face from C* of the foot of the perpendicular from a centre at distance rho
/// from the axis and height y (>= 0: on the face), as in 2D for the right wall.
inline double up_face(const Cone& c, double rho, double y) {
  return c.g.cos_t * (rho - c.g.x_face_end) + c.g.sin_t * (y - c.g.y_face_end);
}

/// The 2D state in the meridian half-plane b: x = r.b, u = v.b and the spin about the plane's
/// normal (-b_z, 0, b_x). Exact (no rounding) for b = (+-1, 0, 0).
State to_meridian(const State3& s, Vec3 b);

/// The 3D state of a 2D state in the meridian half-plane b (the inverse of to_meridian for a
/// motion in that plane with the spin normal to it).
State3 from_meridian(const State& s, Vec3 b);

/// True when the motion lies exactly in the meridian half-plane b: no velocity across it and a
/// spin normal to it (exact zeros), so that the 2D closed forms apply.
bool in_meridian_plane(const State3& s, Vec3 b);

/// Normal force per unit mass that a contact with the rim needs now: for a centre at distance a
/// from the rim circle moving tangentially to the rim torus, n_y - v_m^2/a - v_phi^2 (n.b)/rho,
/// with v_m the velocity in the meridian plane and v_phi across it. A contact holds while > 0.
double rim_normal_force(const Cone& c, const State3& s);

/// Signed azimuth swept (radians, right-handed about +y) by the horizontal position going in a
/// straight line from r0 to r1; 0 when the line passes exactly through the axis.
double azimuth_swept(Vec3 r0, Vec3 r1);

}  // namespace funnel
