// JSON and CSV renderings of parameters, trajectories, events, ensembles and wear, all driven
// by the library's parameter and observable tables: what the CLI writes and the paper's figures
// are made of.
#pragma once

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/params.hpp"
#include "funnel/wear.hpp"

namespace funnel::paper {

/// Bad input from a user (a figure definition, an option's text): the CLI exits with code 2,
/// Python raises ValueError. The message names what is wrong and the valid values.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Shortest text that reads back as the same double (17 significant digits at most); 0, not -0.
std::string number(double x);
/// number(x), or an empty CSV field for NaN (a value that is not defined).
std::string csv_number(double x);

/// Every parameter of the space by its output key: {"theta": ..., "e": ..., ..., "eps_rest": ...}
/// (3D: also release_w, release_spin_x, release_spin_y); null for one that a geometry file leaves
/// unused (reported_value).
nlohmann::ordered_json params_json(const Params& p, Space space = Space::TwoD);

/// The funnel of a run: its source ("v" or the geometry file), the walls' surfaces (top cut
/// 0.1 above the release line), the exit level, the release line and each wall's material.
nlohmann::ordered_json geometry_json(const Params& p);
/// {"version": ..., "git_commit": ..., "command": ...}: what is needed to regenerate an output.
nlohmann::ordered_json provenance_json(const std::string& command_line);
/// Observables of one trajectory, without params and events (exit ones null if it did not exit).
nlohmann::ordered_json trajectory_json(const Trajectory& t);
/// One event of the log.
nlohmann::ordered_json event_json(const Event& e);
/// {"samples", "duration": {"mean","std","sem","min","max"}, ..., "status_counts": {...}}; the
/// exit observables are over the exited samples (null when none exited).
nlohmann::ordered_json ensemble_json(const EnsembleResult& r);
/// {"left": {"s", "collisions", "normal_impulse", "impulse", "edge": {...}}, "right": {...}, "bin_width"}.
nlohmann::ordered_json wear_json(const Wear& w);
/// The wear as CSV: one row per wall and bin (bin "edge" for the edge point).
std::string wear_csv(const Wear& w);

/// Column names of an event log row.
std::vector<std::string> event_columns();
/// One event as CSV fields (in event_columns() order).
std::vector<std::string> event_row(const Event& e);

/// Column names of the parameter part of a row (the space's command-line parameters), then their
/// values (an empty field for one that a geometry file leaves unused).
std::vector<std::string> param_columns(Space space = Space::TwoD);
std::vector<std::string> param_row(const Params& p, Space space = Space::TwoD);
/// Column names of an ensemble's statistics (<observable>_<stat>, then the counts), then values.
std::vector<std::string> ensemble_columns();
std::vector<std::string> ensemble_row(const EnsembleResult& r);
/// Column names and values of one trajectory's observables (status first; exit ones empty if
/// it did not exit).
std::vector<std::string> trajectory_columns();
std::vector<std::string> trajectory_row(const Trajectory& t);

/// Joins fields with commas, ending with a newline.
std::string csv_line(const std::vector<std::string>& fields);

}  // namespace funnel::paper
