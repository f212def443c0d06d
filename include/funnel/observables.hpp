// The observables of a trajectory (docs/model.md §7): one table behind every output.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

#include "funnel/engine.hpp"

namespace funnel {

/// Every observable of one trajectory, in the order of the outputs' columns.
enum class Observable {
  Duration, Impulse, NormalImpulse, EnergyLoss, Collisions, EdgeCollisions, FaceCollisions, Contacts,
  EdgeContacts, ContactTime, ExitX, ExitU, ExitV, ExitSpeed, ExitAngle, ExitSpin,
  // 3D only (the axisymmetric funnel): after every 2D one.
  ExitZ, ExitW, ExitSpinX, ExitSpinY, Orbits,
};

/// Number of observables of a 2D trajectory (the first ones of the enum).
inline constexpr std::size_t observable_count = 16;
/// Number of observables of a 3D trajectory: the 2D ones and ExitZ ... Orbits.
inline constexpr std::size_t observable_count_3d = 21;

/// One observable: its name in outputs and Python, meaning, unit and how it is summarised.
struct ObservableInfo {
  Observable id;
  std::string_view name;     ///< e.g. "energy_loss"
  std::string_view meaning;  ///< one line
  std::string_view unit;     ///< unit in the nondimensionalisation, "" if dimensionless
  bool count;                ///< an integer count
  bool exited_only;          ///< defined only for exited trajectories (statistics over those)
  bool summarized;           ///< reported with statistics by ensembles and sweeps
  bool mirror_odd;           ///< changes sign for the mirror-image trajectory (x -> -x)
};

/// The table of the 2D observables, in column order.
std::span<const ObservableInfo> observables();

/// The table of the 3D observables, in column order: the 2D ones (exit_speed and exit_angle in
/// 3D, exit_spin the spin about z), then exit_z, exit_w, exit_spin_x, exit_spin_y and orbits.
std::span<const ObservableInfo> observables_3d();

/// The entry of one observable.
const ObservableInfo& info(Observable o);

/// The observable with this name (2D or 3D), or null.
const ObservableInfo* find_observable(std::string_view name);

/// Value of an observable for a trajectory; NaN for an exit observable of a trajectory that
/// did not exit.
double value(const Trajectory& t, Observable o);

}  // namespace funnel
