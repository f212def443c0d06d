// Geometry of the axisymmetric funnel and the maps between 3D states and meridian-plane states.
#include "funnel/cone.hpp"

#include <cmath>

namespace funnel {

Cone make_cone(const Params& params) {
  Cone c;
  c.g = make_geometry(params);
  c.rim_radius = c.g.half_gap;
  return c;
}

Vec3 meridian_direction(Vec3 r) {
  // In the plane z = 0 the direction is (+-1, 0, +-0) exactly, as x / |x| and z / |x| would give.
  if (r.z == 0.0) return r.x == 0.0 ? Vec3{1.0, 0.0, 0.0} : Vec3{r.x > 0.0 ? 1.0 : -1.0, 0.0, r.z};
  const double inv = 1.0 / axis_distance(r);
  return {r.x * inv, 0.0, r.z * inv};
}

State to_meridian(const State3& s, Vec3 b) {
  State m;
  m.r = {b.x * s.r.x + b.z * s.r.z, s.r.y};
  m.v = {b.x * s.v.x + b.z * s.v.z, s.v.y};
  m.omega = -b.z * s.omega.x + b.x * s.omega.z;
  return m;
}

State3 from_meridian(const State& s, Vec3 b) {
  State3 t;
  t.r = {s.r.x * b.x, s.r.y, s.r.x * b.z};
  t.v = {s.v.x * b.x, s.v.y, s.v.x * b.z};
  t.omega = {-s.omega * b.z, 0.0, s.omega * b.x};
  return t;
}

bool in_meridian_plane(const State3& s, Vec3 b) {
  const Vec3 across = azimuthal_direction(b);
  // Position, velocity and spin: no component out of the plane (r, v) or in it (omega).
  return dot(s.r, across) == 0.0 && dot(s.v, across) == 0.0 && s.omega.y == 0.0 &&
         b.x * s.omega.x + b.z * s.omega.z == 0.0;
}

double rim_normal_force(const Cone& c, const State3& s) {
  const Vec3 b = meridian_direction(s.r);
  const Vec3 d = s.r - rim_point(c, b);
  const double dist = norm(d);
  const Vec3 n = (1.0 / dist) * d;
  const double v_phi = dot(s.v, azimuthal_direction(b));
  const double v_m2 = dot(s.v, s.v) - v_phi * v_phi;
  const double rho = s.r.x * b.x + s.r.z * b.z;
  // Centripetal terms of the torus: 1/a across the tube, (n.b)/rho along the parallel circle.
  return n.y - v_m2 / c.g.radius - v_phi * v_phi * (n.x * b.x + n.z * b.z) / rho;
}

double azimuth_swept(Vec3 r0, Vec3 r1) {
  const double sine = r0.z * r1.x - r0.x * r1.z;
  if (sine == 0.0) return 0.0;
  return std::atan2(sine, r0.x * r1.x + r0.z * r1.z);
}

}  // namespace funnel
