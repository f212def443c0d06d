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
};

/// Number of observables.
inline constexpr std::size_t observable_count = 16;

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

/// The table, in column order.
std::span<const ObservableInfo> observables();

/// The entry of one observable.
const ObservableInfo& info(Observable o);

/// The observable with this name, or null.
const ObservableInfo* find_observable(std::string_view name);

/// Value of an observable for a trajectory; NaN for an exit observable of a trajectory that
/// did not exit.
double value(const Trajectory& t, Observable o);

}  // namespace funnel
