// Sustained contact in the axisymmetric funnel: the 2D closed forms for a motion in a meridian
// plane, and the integrated equations of motion (contact3d_integrate.cpp) for any other.
#include "funnel/contact3d.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "contact3d_integrate.hpp"
#include "funnel/contact.hpp"
#include "funnel/edge_contact.hpp"
#include "funnel/funnel.hpp"

namespace funnel {

namespace {

/// The 2D funnel's right face, as the cone's face in a meridian half-plane.
Face right_face(const Geometry& g) {
  Face f;
  f.sin_a = g.sin_t;
  f.cos_a = g.cos_t;
  f.n = {-g.sin_t, g.cos_t};
  f.up = {g.cos_t, g.sin_t};
  f.down = {-g.cos_t, -g.sin_t};
  f.ref = {0.0, 0.0};
  f.low = g.closed ? Vec2{0.0, 0.0} : Vec2{g.x_face_end, g.y_face_end};
  f.length = std::numeric_limits<double>::infinity();
  f.low_convex = !g.closed;
  return f;
}

}  // namespace

Contact3Result face_contact(const State3& start, const Cone& cone, const Material& m, const Contact3Options& opt) {
  // On the axis (a closed cone's vertex, after a collapse there) the contact is on the generator
  // of the collision that collapsed (docs/robustness.md, finding 26).
  const Vec3 b = start.r.x == 0.0 && start.r.z == 0.0 ? opt.axis_side : meridian_direction(start.r);
  if (!(opt.closed_forms && in_meridian_plane(start, b))) return detail::integrate_contact(false, start, cone, m, opt);
  // In the meridian half-plane b the face is the 2D funnel's right wall.
  const ContactResult r = slide_on_face(to_meridian(start, b), right_face(cone.g), 1.0, m);
  Contact3Result res;
  res.closed_form = true;
  res.end = from_meridian(r.end, b);
  res.how = cone.g.closed ? Contact3End::Rest : Contact3End::FaceEnd;
  res.duration = r.duration;
  res.impulse = r.impulse;
  res.normal_impulse = r.normal_impulse;
  res.contact_impulse = res.end.v - start.v + Vec3{0.0, res.duration, 0.0};
  res.energy_lost = r.energy_lost;
  res.first_regime = r.first_regime;
  res.last_regime = r.last_regime;
  res.phases = r.phase_count;
  return res;
}

Contact3Result rim_contact(const State3& start, const Cone& cone, const Material& m, const Contact3Options& opt) {
  const Vec3 b = meridian_direction(start.r);
  if (!(opt.closed_forms && in_meridian_plane(start, b))) return detail::integrate_contact(true, start, cone, m, opt);
  // In the meridian half-plane the rim is the 2D right edge, solved as the mirrored left edge
  // exactly as the 2D engine does.
  const double top = std::atan2(cone.g.cos_t, cone.g.sin_t);
  const EdgeArc left_arc{edge_point(cone.g, Wall::Left), top - std::numbers::pi, top};
  EdgeContactResult r = edge_contact(mirror(to_meridian(start, b)), left_arc, m);
  Contact3Result res;
  res.closed_form = true;
  res.end = from_meridian(mirror(r.end), b);
  res.how = r.exit == EdgeExit::High ? Contact3End::RimTop : Contact3End::TakeOff;
  res.duration = r.duration;
  res.impulse = r.impulse;
  res.normal_impulse = r.normal_impulse;
  res.contact_impulse = res.end.v - start.v + Vec3{0.0, res.duration, 0.0};
  res.energy_lost = r.energy_lost;
  res.first_regime = r.first_regime;
  res.last_regime = r.last_regime;
  res.phases = r.phases;
  return res;
}

double sliding_orbit_speed(const Cone& cone, double rho) { return std::sqrt(rho * cone.g.tan_t); }

double rolling_orbit_speed(const Cone& cone, double rho, double kappa) {
  return std::sqrt(rho * cone.g.tan_t / (1.0 + kappa));
}

}  // namespace funnel
