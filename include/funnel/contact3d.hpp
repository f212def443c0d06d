// Sustained contact in the axisymmetric funnel: sliding or rolling on the cone face or over the
// rim (docs/model.md §9). In a meridian plane (no azimuthal
// motion, spin normal to the plane) the 2D closed forms of contact.hpp and edge_contact.hpp are
// used; otherwise the equations of motion on the surface are integrated with an adaptive
// Runge-Kutta method with dense output, on which every event is located by root refinement.
#pragma once

#include <atomic>

#include <cstdint>
#include <limits>

#include "funnel/cone.hpp"
#include "funnel/params.hpp"
#include "funnel/vec3.hpp"
#include "funnel/walton.hpp"

namespace funnel {

/// How a sustained contact in 3D ended.
enum class Contact3End {
  FaceEnd,   ///< on the face, the centre reached C* moving down: the rim or a flight takes over
  RimTop,    ///< on the rim, the centre reached C* moving up: the face takes over
  TakeOff,   ///< on the rim, the normal force fell to zero: a flight tangent to the rim torus
  Exit,      ///< on the rim, the centre crossed the outlet's level y_b moving down
  Rest,      ///< closed funnel: at the vertex, or the energy above it fell below eps_rest
  TimeCap,   ///< the time budget ran out inside the contact
  Periodic,  ///< a conservative contact (rolling, or frictionless sliding) repeats its radial
             ///< period forever: extrapolated to the time budget
};

/// Numerical settings of a sustained contact.
struct Contact3Options {
  double t_budget = std::numeric_limits<double>::infinity();  ///< time left before the cap, units sqrt(H/g)
  double eps_rest = 1e-12;      ///< closed funnel: energy above the vertex at which it rests, units m g H
  double rel_tol = 1e-12;       ///< relative tolerance of the integrator (per step)
  double abs_tol = 1e-14;       ///< absolute tolerance of the integrator (per step)
  bool detect_periodic = true;  ///< extrapolate conservative contacts once a radial period has repeated
  bool closed_forms = true;     ///< use the 2D closed forms for motion in a meridian plane
  /// The step guard: accepted integrator steps after which the contact ends as TimeCap before its
  /// budget (the engine then flags the run `stalled`), >= 1; Params::max_ode_steps.
  std::int64_t max_steps = default_max_ode_steps;
  /// Unit horizontal direction of the meridian half-plane of a face contact whose centre starts on
  /// the axis (a closed cone's vertex, which every generator reaches): the generator of the
  /// collision that collapsed there. The position alone gives no half-plane.
  Vec3 axis_side{1.0, 0.0, 0.0};
  /// Once set, an integrated contact stops within 1024 steps, as at the step guard (TimeCap): a
  /// cancelled ensemble (Ctrl-C) does not wait for its long contacts. Its results are discarded.
  const std::atomic<bool>* cancel = nullptr;
};

/// Outcome of a sustained contact in 3D.
struct Contact3Result {
  State3 end;                     ///< state at the end
  Contact3End how = Contact3End::FaceEnd;
  double duration = 0.0;          ///< time in contact, units sqrt(H/g)
  double impulse = 0.0;           ///< integral of sqrt(N^2 + |F|^2) dt, units m sqrt(gH)
  double normal_impulse = 0.0;    ///< integral of N dt
  Vec3 contact_impulse;           ///< integral of (N n + F) dt = v_end - v_start + (0, duration, 0)
  double energy_lost = 0.0;       ///< E_start - E_end (>= 0 up to the integration error), units m g H
  double swept = 0.0;             ///< azimuth swept about the vertical axis, radians (right-handed about +y)
  Regime first_regime = Regime::Sliding;  ///< Sliding or Rolling at the start
  Regime last_regime = Regime::Sliding;   ///< at the end
  int phases = 0;                 ///< phases (sliding/rolling) integrated
  std::int64_t steps = 0;         ///< accepted integrator steps (0 for a closed form)
  bool closed_form = false;       ///< solved by the 2D closed forms (motion in a meridian plane)
};

/// Sustained contact on the cone face, from `start` (centre on the centre cone up the face from
/// C*, velocity tangent to it) until the centre reaches C* (or the vertex of a closed funnel).
Contact3Result face_contact(const State3& start, const Cone& cone, const Material& m, const Contact3Options& opt);

/// Sustained contact with the rim, from `start` (centre at distance a from the rim circle on the
/// rim's arc, velocity tangent to the rim torus) until take-off, the return to C*, or the exit.
Contact3Result rim_contact(const State3& start, const Cone& cone, const Material& m, const Contact3Options& opt);

/// Circular orbit on the cone face at distance rho from the axis: the speed that keeps a
/// frictionless ball at its height, v^2 = rho tan(theta), units sqrt(gH).
double sliding_orbit_speed(const Cone& cone, double rho);

/// The same for rolling without slipping (no spin about the normal): v^2 = rho tan(theta)/(1 + kappa).
double rolling_orbit_speed(const Cone& cone, double rho, double kappa);

}  // namespace funnel
