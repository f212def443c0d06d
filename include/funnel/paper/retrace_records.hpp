// CSV and JSON renderings of self-retracing orbits and their windows (funnel retrace, funnel paper).
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "funnel/retrace.hpp"

namespace funnel::paper {

/// An orbit with the engine's return check (retrace::check_return) in the funnel it was found in.
struct CheckedOrbit {
  retrace::Orbit orbit;
  retrace::ReturnCheck check;
};

/// Runs the return check of every orbit.
std::vector<CheckedOrbit> check_orbits(const Params& params, const std::vector<retrace::Orbit>& orbits);

/// Column names of an orbit row: theta, release, sequence, turn, bounces, ... return_speed.
std::vector<std::string> orbit_columns();
/// One orbit as CSV fields (orbit_columns() order).
std::vector<std::string> orbit_row(const CheckedOrbit& o);
/// One orbit as a JSON object with the keys of orbit_columns().
nlohmann::ordered_json orbit_json(const CheckedOrbit& o);

/// Column names of a window row: sequence, turn, bounces, window, theta_from, theta_to, points.
std::vector<std::string> window_columns();
/// One window as CSV fields.
std::vector<std::string> window_row(const retrace::Window& w);
/// One window as a JSON object with the keys of window_columns().
nlohmann::ordered_json window_json(const retrace::Window& w);

/// Parses --turns: "wall" or "wall,rest" (also "rest,wall", "all"); true if rest turns are wanted.
/// Throws InputError otherwise.
bool parse_turns(const std::string& text);

}  // namespace funnel::paper
