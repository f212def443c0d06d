// Shared pieces of the command-line front end: model options, usage errors, atomic output.
#pragma once

#include <CLI/CLI.hpp>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "funnel/ensemble.hpp"
#include "funnel/grid.hpp"
#include "funnel/params.hpp"
#include "funnel/paper/records.hpp"
#include "output_file.hpp"

namespace funnel::cli {

// The records the CLI writes (JSON, CSV, number texts) come from the paper module.
using namespace funnel::paper;

/// Bad input: reported as "funnel: error: <message>" with exit code 2 (the paper module's
/// error, so that the figure definitions' messages reach the user alike).
using UsageError = paper::InputError;

/// The model options as given on the command line (text), keyed by parameter name.
struct ModelOptions {
  std::map<std::string, std::string> given;  ///< only the options the user set
  std::string geometry;                      ///< --geometry FILE.toml, empty for the V
};

/// Adds --geometry FILE.toml (a funnel of any 2D wall profile) to a command that simulates.
void add_geometry_option(CLI::App& app, ModelOptions& options);

/// Makes an option that names a file refuse an empty value (exit 2: `--geometry ""` would
/// otherwise read as not given at all).
CLI::Option* nonempty(CLI::Option* option, const std::string& name, const std::string& valid);

/// The default parameters with the profile of --geometry, if given.
Params base_params(const ModelOptions& options);

/// Adds one option per model parameter of the library's table (--theta ... --release-spin).
/// With `lists`, each also accepts a list "a,b,c" or a range "start:stop:step". With
/// Space::ThreeD, also the 3D ones (--release-w, --release-spin-x/-y; --release-spin-z is
/// --release-spin), for the commands that take --space.
void add_model_options(CLI::App& app, ModelOptions& options, bool lists, Space space = Space::TwoD);

/// Parameters from single-valued options over the defaults; throws UsageError if invalid (in
/// 2D, also for a 3D option that is not 0).
Params to_params(const ModelOptions& options, Space space = Space::TwoD);

/// Adds --space (2d or 3d, default 2d).
void add_space_option(CLI::App& app, std::string& space);
/// Parses "2d" or "3d"; throws UsageError.
Space to_space(const std::string& text);

/// Grid axes from list-valued options (and the parameters' defaults for the rest). A grid of
/// more than `max_points` points is refused (check_grid_cap, `why` its reason) as soon as the
/// axes read so far exceed it: eleven axes of 10^7 values took 4.5 s and 920 MB to be refused.
std::vector<Axis> to_axes(const ModelOptions& options, double max_points, const std::string& why);

/// "theta 8801 x mu 115": the axes of more than one value, with their sizes.
std::string grid_dims(const std::vector<Axis>& axes);

/// A count of points or trajectories as text: exact below 10^15 (rounded, 1000001 would read as
/// 1e+06, within a cap of 10^6), else to 3 digits.
std::string count_text(double n);

/// Refuses, before the grid is built, a grid of more than `max_points` points (their product
/// over the axes): its points and rows are held in memory (a huge grid ended in bad_alloc).
void check_grid_cap(const std::vector<Axis>& axes, double max_points, const std::string& why);

/// Validates every point of a grid; throws UsageError naming the first invalid one.
void validate_all(const std::vector<Params>& points, Space space = Space::TwoD);
/// The same, and in 2D that each point's funnel takes the options' releases (disk releases in a
/// mirror-symmetric funnel only); a UsageError naming the first failure.
void validate_all(const std::vector<Params>& points, Space space, const EnsembleOptions& options);

/// Parses a sample count (>= 1); throws UsageError.
std::int64_t to_samples(const std::string& text);
/// Parses "line", "disk", "uniform" or "gaussian"; throws UsageError.
ReleaseDist to_release_dist(const std::string& text);
/// Parses a thread count (>= 1, or 0 for all cores); throws UsageError.
int to_threads(const std::string& text);

/// The ensemble options as text (--samples --release-dist --seed --release --release-sd
/// --velocity-sd --wear-bins --threads).
struct EnsembleText {
  std::string samples = std::to_string(default_samples);
  std::string release_dist = "line";
  std::string seed = "1";
  std::string release = "0";
  std::string release_sd = "0.1";
  std::string velocity_sd = "0";
  std::string wear_bins = "0";
  std::string threads = "0";
  /// The gaussian distribution's options given ("release", "release-sd"): refused with another.
  std::vector<std::string> gaussian_given;
  /// --seed given: refused where no random number is drawn.
  bool seed_given = false;
  /// The command takes --velocity-sd (funnel closed does not): its refusal of --seed says so.
  bool velocity = true;
};
/// Adds the ensemble options; with `velocity` also --velocity-sd, with `wear` --wear-bins.
void add_ensemble_options(CLI::App& app, EnsembleText& text, bool velocity = true, bool wear = true);
/// The options, validated by the library; throws UsageError. `space` words the refusal of a
/// seed (in 3d only random velocities draw random numbers).
EnsembleOptions to_ensemble_options(const EnsembleText& text, Space space = Space::TwoD);

/// Adds --format (json or csv, default json) and --out (default '-': standard output).
void add_output_options(CLI::App& app, std::string& format, std::string& out);

/// Output format of a command.
enum class Format { Json, Csv };
/// Parses "json" or "csv"; throws UsageError.
Format to_format(const std::string& text);

/// The items of a comma-separated list of names, as written (an empty item stays, for the
/// caller to reject by name): "a,b" -> {"a", "b"}.
std::vector<std::string> comma_items(const std::string& text);

/// Warns on standard error when `stalled` of `runs` runs (runs >= 1) were ended by an internal
/// guard before the time cap (Trajectory::stalled, Trajectory3::stalled: status trapped), naming
/// the likely guard of the space: `who` is the command ("funnel ensemble"), `where` says where
/// the output shows it ("the count stalled"; 3D only), `guard` is the max-ode-steps in effect (0:
/// it varies). Nothing when stalled is 0.
void warn_stalled(const std::string& who, Space space, std::int64_t stalled, std::int64_t runs,
                  const std::string& where = "", std::int64_t guard = 0);

/// Warns on standard error when `capped` of `runs` runs (runs >= 1) reached the collision cap
/// inside the funnel (Trajectory::capped, Trajectory3::capped: status trapped, the observables
/// cut short there): `who` is the command, `cap` the max-collisions in effect (0: it varies).
/// Nothing when capped is 0.
void warn_capped(const std::string& who, std::int64_t capped, std::int64_t runs, std::int64_t cap);

}  // namespace funnel::cli
