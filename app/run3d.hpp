// The 3D (axisymmetric funnel) variants of `funnel trajectory` and `funnel ensemble`, selected
// by --space 3d; `funnel sweep` uses to_ensemble3_options and output3d.hpp directly.
#pragma once

#include <string>

#include "cli_common.hpp"
#include "funnel/ensemble3d.hpp"

namespace funnel::cli {

/// The 3D ensemble options of the command line's ensemble options: line or disk releases (disk
/// unless --release-dist was given); throws UsageError for a 2D-only option (wear bins, uniform
/// or gaussian releases).
Ensemble3Options to_ensemble3_options(const EnsembleOptions& options, bool dist_given);

/// Writes one 3D trajectory released at x0 = release * L, z0 = 0 (JSON, or CSV: the observables
/// or, with events, the event log).
void write_trajectory_3d(const Params& params, double release, bool events, Format format, const std::string& out,
                         const std::string& command_line);

/// Writes the statistics of a 3D ensemble (JSON, or CSV: one row, or one row per sample).
void write_ensemble_3d(const Params& params, const Ensemble3Options& options, bool per_sample, Format format,
                       const std::string& out, const std::string& command_line);

}  // namespace funnel::cli
