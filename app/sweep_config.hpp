// The TOML file of `funnel sweep --config`: a grid of model parameters, samples, release-dist.
#pragma once

#include <map>
#include <optional>
#include <string>

namespace funnel::cli {

/// A sweep's settings as the command line would give them (text).
struct SweepConfig {
  std::map<std::string, std::string> params;  ///< model parameter (CLI name) -> number, list or range
  std::optional<std::string> samples;         ///< release positions N
  std::optional<std::string> release_dist;    ///< line or disk
};

/// How a sweep config is written, for error messages and --help.
extern const char* const sweep_config_layout;

/// Reads a sweep config. Model parameters may be at the top level or in a [grid] (or [params])
/// table, each a number, an array of numbers or a string "a,b,c" / "start:stop:step"; samples
/// and release-dist (or release_dist) at the top level. Throws UsageError for a missing,
/// unreadable or empty file, a directory, a syntax error (with its line and column), an
/// unknown key (with the nearest valid one) or a figure definition of `funnel paper`.
SweepConfig read_sweep_config(const std::string& file);

}  // namespace funnel::cli
