// Parameter grids for sweeps: value lists and ranges, and their Cartesian product.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "funnel/params.hpp"

namespace funnel {

/// Parses a strict finite decimal number (the whole text); nullopt otherwise.
std::optional<double> parse_number(std::string_view text);

/// Parses "v", "v1,v2,..." or an inclusive range "start:stop:step" (step > 0, stop >= start)
/// into values; on failure returns nullopt and sets `error` to a reason.
std::optional<std::vector<double>> parse_values(std::string_view text, std::string& error);

/// Names of the parameters a sweep in `space` can vary, in the order of the grid's axes and CSV
/// columns (3D: the 2D ones, then the 3D-only ones).
const std::vector<std::string>& sweep_parameter_names(Space space = Space::TwoD);

/// Sets the parameter called `name` (one of sweep_parameter_names()) to `value`.
/// Returns false for an unknown name or a non-integral max-collisions.
bool set_parameter(Params& params, std::string_view name, double value);

/// Reads the parameter called `name` as a double.
double get_parameter(const Params& params, std::string_view name);

/// One axis of a grid: a parameter name and its values.
struct Axis {
  std::string name;
  std::vector<double> values;
};

/// Points of the axes' Cartesian product (a double: the product may exceed any integer).
double grid_points(const std::vector<Axis>& axes);

/// Grid points a sweep may have (CLI and Python): its rows, about 2 kB each, are held in memory
/// twice (the finished points and the output text).
inline constexpr double max_sweep_points = 2e6;

/// The Cartesian product of the axes over a base parameter set; the last axis varies fastest.
std::vector<Params> expand_grid(const Params& base, const std::vector<Axis>& axes);

}  // namespace funnel
