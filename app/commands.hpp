// The subcommands of the funnel command line.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace funnel::cli {

/// Registers `funnel trajectory`: one trajectory, with its optional event log.
void add_trajectory_command(CLI::App& app, const std::string& command_line);
/// Registers `funnel ensemble`: statistics over release positions.
void add_ensemble_command(CLI::App& app, const std::string& command_line);
/// Registers `funnel sweep`: one ensemble per point of a parameter grid, to CSV.
void add_sweep_command(CLI::App& app, const std::string& command_line);
/// Registers `funnel closed`: long-time states of a closed funnel.
void add_closed_command(CLI::App& app, const std::string& command_line);
/// Registers `funnel orbit`: eigenvalues and stability of the period-2 orbit.
void add_orbit_command(CLI::App& app, const std::string& command_line);
/// Registers `funnel retrace`: self-retracing orbits of the elastic frictionless particle.
void add_retrace_command(CLI::App& app, const std::string& command_line);
/// Registers `funnel paper`: every figure of the paper.
void add_paper_command(CLI::App& app, const std::string& command_line);
/// Registers `funnel bench`: collisions per second of the reference ensemble and sweep.
void add_bench_command(CLI::App& app, const std::string& command_line);

}  // namespace funnel::cli
