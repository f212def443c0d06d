// The paper's figures as data: one TOML file per figure under paper/ (docs/paper.md).
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "funnel/grid.hpp"
#include "funnel/params.hpp"

namespace funnel::paper {

/// One panel of a figure: its id ("a"), label and the parameters it fixes.
struct PanelSpec {
  std::string id;
  std::string label;
  std::map<std::string, double> params;
  /// theta-right = theta + this at every grid point (an asymmetric V that follows the angle).
  std::optional<double> theta_right_offset;
};

/// A figure definition read from paper/figNN.toml.
struct FigureSpec {
  std::string id;                        ///< "fig03"
  std::string kind;                      ///< theta_sweep, release_scan, trajectories, eigenvalues, closed_final, periodic_fraction,
                                         ///< funnel_sketch, period2_orbits, retrace_orbits, retrace_windows
  std::string title, caption, series;
  std::vector<std::string> observables;
  std::int64_t samples = default_samples;
  std::vector<std::string> dists{"line"};  ///< release distributions (several for Fig. 13)
  std::map<std::string, double> params;    ///< fixed model parameters
  std::vector<Axis> grid;                  ///< swept axes ([grid])
  std::vector<PanelSpec> panels;           ///< at least one
  std::vector<double> thetas, mus, releases;
  toml::table check;                       ///< how the paper's claim is checked
  toml::table settings;                    ///< [settings]: kind-specific settings ([quick.settings] merged under --quick)
  std::string source;                      ///< path of the TOML file
};

/// Reads one figure definition; with `quick`, the [quick] table overrides grids and samples.
/// Throws InputError naming the file and the key on any problem.
FigureSpec load_figure(const std::string& path, bool quick);

/// Every paper/fig*.toml of a directory, sorted by name.
std::vector<FigureSpec> load_figures(const std::string& dir, bool quick);

/// Parameters of a panel: defaults, then the figure's fixed parameters, then the panel's.
Params panel_params(const FigureSpec& fig, const PanelSpec& panel);

}  // namespace funnel::paper
