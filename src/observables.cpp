// The observable table and the values of each observable.
#include "funnel/observables.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace funnel {

namespace {

constexpr std::array<ObservableInfo, observable_count_3d> table{{
    {Observable::Duration, "duration", "time until the exit (or the end of the run)", "sqrt(H/g)", false, false, true, false},
    {Observable::Impulse, "impulse", "total impulse on the walls, sum |J| + integral of |F| dt", "m sqrt(gH)", false, false, true, false},
    {Observable::NormalImpulse, "normal_impulse", "normal impulse on the walls", "m sqrt(gH)", false, false, true, false},
    {Observable::EnergyLoss, "energy_loss", "energy lost, E_0 - E_end", "mgH", false, false, true, false},
    {Observable::Collisions, "collisions", "collisions, face and edge", "", true, false, true, false},
    {Observable::EdgeCollisions, "edge_collisions", "collisions with an edge", "", true, false, true, false},
    {Observable::FaceCollisions, "face_collisions", "collisions with a face", "", true, false, false, false},
    {Observable::Contacts, "contacts", "sustained face contacts", "", true, false, false, false},
    {Observable::EdgeContacts, "edge_contacts", "sustained edge contacts", "", true, false, true, false},
    {Observable::ContactTime, "contact_time", "time in sustained contact (faces and edges)", "sqrt(H/g)", false, false, true, false},
    {Observable::ExitX, "exit_x", "centre's x at the exit level (or, passing under a higher lower end sideways, that end's x)", "H", false, true, true, true},
    {Observable::ExitU, "exit_u", "horizontal velocity at the exit", "sqrt(gH)", false, true, true, true},
    {Observable::ExitV, "exit_v", "vertical velocity at the exit (negative: down)", "sqrt(gH)", false, true, true, false},
    {Observable::ExitSpeed, "exit_speed", "speed at the exit", "sqrt(gH)", false, true, true, false},
    {Observable::ExitAngle, "exit_angle", "direction at the exit from the downward vertical, positive towards +x", "degrees", false, true, true, true},
    {Observable::ExitSpin, "exit_spin", "spin at the exit, counter-clockwise", "sqrt(g/H)", false, true, true, true},
    // 3D only. In 3D exit_speed is |v|, exit_angle the angle between v and the downward vertical
    // (>= 0) and exit_spin the spin about z.
    {Observable::ExitZ, "exit_z", "centre's z at the exit level (3D)", "H", false, true, true, false},
    {Observable::ExitW, "exit_w", "velocity along z at the exit (3D)", "sqrt(gH)", false, true, true, false},
    {Observable::ExitSpinX, "exit_spin_x", "spin about x at the exit (3D)", "sqrt(g/H)", false, true, true, false},
    {Observable::ExitSpinY, "exit_spin_y", "spin about the vertical axis at the exit (3D)", "sqrt(g/H)", false, true, true, false},
    {Observable::Orbits, "orbits", "turns about the vertical axis, |net azimuth swept| / 2 pi (3D)", "", false, false, true, false},
}};

}  // namespace

std::span<const ObservableInfo> observables() { return std::span(table).first(observable_count); }

std::span<const ObservableInfo> observables_3d() { return table; }

const ObservableInfo& info(Observable o) { return table[static_cast<std::size_t>(o)]; }

const ObservableInfo* find_observable(std::string_view name) {
  for (const ObservableInfo& o : table) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

double value(const Trajectory& t, Observable o) {
  const bool exited = t.status == Status::Exited;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const State& x = t.exit_state;
  switch (o) {
    case Observable::Duration: return t.duration;
    case Observable::Impulse: return t.impulse;
    case Observable::NormalImpulse: return t.normal_impulse;
    case Observable::EnergyLoss: return t.energy_loss;
    case Observable::Collisions: return static_cast<double>(t.collisions);
    case Observable::EdgeCollisions: return static_cast<double>(t.edge_collisions);
    case Observable::FaceCollisions: return static_cast<double>(t.collisions - t.edge_collisions);
    case Observable::Contacts: return static_cast<double>(t.contacts);
    case Observable::EdgeContacts: return static_cast<double>(t.edge_contacts);
    case Observable::ContactTime: return t.contact_time;
    case Observable::ExitX: return exited ? x.r.x : nan;
    case Observable::ExitU: return exited ? x.v.x : nan;
    case Observable::ExitV: return exited ? x.v.y : nan;
    case Observable::ExitSpeed: return exited ? std::hypot(x.v.x, x.v.y) : nan;
    case Observable::ExitAngle: return exited ? std::atan2(x.v.x, -x.v.y) * (180.0 / std::numbers::pi) : nan;
    case Observable::ExitSpin: return exited ? x.omega : nan;
    default: return nan;  // 3D only
  }
  return nan;
}

}  // namespace funnel
