// JSON and CSV renderings of 3D trajectories, events and ensembles (the axisymmetric funnel),
// driven by the library's 3D parameter and observable tables.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "funnel/engine3d.hpp"
#include "funnel/ensemble3d.hpp"
#include "funnel/paper/records.hpp"
#include "funnel/params.hpp"

namespace funnel::cli {

// The 2D records of the same names, overloaded here with the 3D ones.
using paper::ensemble_json;
using paper::ensemble_row;
using paper::event_json;
using paper::event_row;
using paper::param_columns;
using paper::param_row;
using paper::params_json;
using paper::trajectory_json;
using paper::trajectory_row;

/// Observables of one 3D trajectory (exit ones null if it did not exit), with "orbits_signed".
nlohmann::ordered_json trajectory_json(const Trajectory3& t);
/// Column names and values of one 3D trajectory's observables (status first, then periodic and
/// stalled as 0 or 1).
std::vector<std::string> trajectory_columns_3d();
std::vector<std::string> trajectory_row(const Trajectory3& t);

/// One 3D event: the 2D event's keys (u = v_x, v = v_y, omega = omega_z, slip = |slip|,
/// j_t = |J_t|) plus z, w_before/after and omega_x/y/z_before/after.
nlohmann::ordered_json event_json(const Event3& e);
/// Column names of a 3D event log row, then one event's fields.
std::vector<std::string> event_columns_3d();
std::vector<std::string> event_row(const Event3& e);

/// {"samples", "<observable>": {"mean","std","sem","min","max"}, ..., "status_counts", ...}: the
/// 3D observables; exit ones over the exited samples (null when none exited).
nlohmann::ordered_json ensemble_json(const Ensemble3Result& r);
/// Column names of a 3D ensemble's statistics (<observable>_<stat>, then the counts), then values.
std::vector<std::string> ensemble_columns_3d();
std::vector<std::string> ensemble_row(const Ensemble3Result& r);

}  // namespace funnel::cli
