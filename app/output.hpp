// JSON and CSV renderings of parameters, trajectories, events and ensembles.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "funnel/engine.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/params.hpp"

namespace funnel::cli {

/// {"theta": ..., "e": ..., ..., "max_collisions": ...}.
nlohmann::ordered_json params_json(const Params& p);
/// {"version": ..., "git_commit": ..., "command": ...}: what is needed to regenerate an output.
nlohmann::ordered_json provenance_json(const std::string& command_line);
/// Observables of one trajectory, without params and events.
nlohmann::ordered_json trajectory_json(const Trajectory& t);
/// One event of the log.
nlohmann::ordered_json event_json(const Event& e);
/// {"samples", "duration": {"mean","std","sem","min","max"}, ..., "status_counts": {...}}.
nlohmann::ordered_json ensemble_json(const EnsembleResult& r);

/// Column names of an event log row.
std::vector<std::string> event_columns();
/// One event as CSV fields (in event_columns() order).
std::vector<std::string> event_row(const Event& e);

/// Column names of the parameter part of a row, then of the statistics part.
std::vector<std::string> param_columns();
std::vector<std::string> param_row(const Params& p);
std::vector<std::string> ensemble_columns();
std::vector<std::string> ensemble_row(const EnsembleResult& r);
/// Column names and values of one trajectory's observables.
std::vector<std::string> trajectory_columns();
std::vector<std::string> trajectory_row(const Trajectory& t);

/// Joins fields with commas, ending with a newline.
std::string csv_line(const std::vector<std::string>& fields);

}  // namespace funnel::cli
