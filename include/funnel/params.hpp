// Model parameters (docs/model.md §1), their one table and their validation.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace funnel {

struct ProfileSpec;

/// The default step guard of a 3D sustained contact (Params::max_ode_steps), about 20 s of one
/// core. Within the default time cap three kinds of contact reach it (docs/model.md §9): a ball
/// orbiting the cone for a long time, rolling and sliding in turn (about 10^3 steps per unit of
/// time), an exactly circular orbit, which never repeats a radial period, and the stick-slip of
/// docs/robustness.md, finding 22.
inline constexpr std::int64_t default_max_ode_steps = 20'000'000;

/// The least radius: far below any physical size, and far above the radii at which the squares in
/// the spin's energy underflow (a^2 = 0 below about 1.5e-154 H: the 3D energies were NaN) or the
/// 2D edge geometry loses its last bits (subnormal radii below about 5e-309 H left trajectories
/// trapped with NaN impulse and energy).
inline constexpr double min_radius = 1e-100;

/// Physical and numerical parameters of one funnel run. Units: H = g = m = 1.
struct Params {
  double theta = 60.0;        ///< wall angle to the horizontal, degrees, 0 < theta < 90
  double e = 0.99;            ///< normal restitution, 0 <= e <= 1
  double mu = 1.0;            ///< Coulomb friction coefficient, finite, >= 0
  double beta0 = 0.0;         ///< Walton's maximum tangential restitution, -1 <= beta0 <= 1
  double radius = 0.01;       ///< particle radius a / H, 0 < a < 1
  double gap = 0.04;          ///< gap d between the walls' lower edges / H: 0 (closed) or d > 2a
  double inertia = 0.4;       ///< kappa = I/(m a^2), > 0 (2/5 solid sphere)
  double t_max = 1e5;         ///< time cap, units of sqrt(H/g), > 0
  std::int64_t max_collisions = 100'000'000;  ///< collision cap, >= 1
  double release_height = 1.0;  ///< H0: height of the release line above the funnel bottom, units of H
  double release_u = 0.0;       ///< initial horizontal velocity, units sqrt(gH), finite
  double release_v = 0.0;       ///< initial vertical velocity (up positive), units sqrt(gH), finite
  double release_spin = 0.0;    ///< initial spin, counter-clockwise, units sqrt(g/H), finite
  double theta_left = unset;  ///< angle of the left wall, degrees (unset: theta), 0 < theta-left < 90
  double theta_right = unset; ///< angle of the right wall, degrees (unset: theta), 0 < theta-right < 90
  double spout_length = 0.0;  ///< vertical walls of this length below the edges, units of H, >= 0
  double p_c = 1e-9;          ///< collapse threshold on the normal speed after a collision, > 0
  double eps_rest = 1e-12;    ///< closed funnel: energy above the vertex below which the particle rests, > 0
  /// A wall profile (docs/model.md §2b) replacing the V of theta, theta-left/right, gap and
  /// spout-length; null for the V.
  std::shared_ptr<const ProfileSpec> profile;

  /// Marks theta-left/theta-right as "the same as theta".
  /// NaN: no value can be given as NaN, so every value set (valid or not) reads back as itself.
  static constexpr double unset = std::numeric_limits<double>::quiet_NaN();
  static bool is_unset(double angle) { return std::isnan(angle); }
  /// The left and right wall angles in degrees (theta where unset).
  double left_angle() const { return is_unset(theta_left) ? theta : theta_left; }
  double right_angle() const { return is_unset(theta_right) ? theta : theta_right; }
  /// True for the paper's symmetric V (no per-side angle, no spout, no profile).
  bool plain_v() const { return left_angle() == theta && right_angle() == theta && spout_length == 0.0 && !profile; }
  // 3D only (the axisymmetric funnel); at their defaults in 2D.
  double release_w = 0.0;       ///< initial velocity along z, out of the release's meridian plane, units sqrt(gH), finite
  double release_spin_x = 0.0;  ///< initial spin about x, units sqrt(g/H), finite
  double release_spin_y = 0.0;  ///< initial spin about the vertical axis, units sqrt(g/H), finite
  /// The step guard of an integrated sustained contact: accepted integrator steps after which the
  /// contact, and the run, end as trapped with the trajectory's `stalled` flag (docs/model.md §9),
  /// >= 1; its default in 2D.
  std::int64_t max_ode_steps = default_max_ode_steps;
};

/// The space of a simulation: the paper's 2D funnel, or the funnel revolved about its axis in 3D.
enum class Space { TwoD, ThreeD };

/// "2d" or "3d".
std::string_view to_string(Space space);
/// Parses "2d" or "3d"; nullopt otherwise.
std::optional<Space> parse_space(std::string_view text);

/// The documented defaults (docs/model.md §1).
Params default_params();

/// One model parameter: the single description behind the command-line options, the JSON/CSV
/// columns, the sweep axes and the Python keywords.
struct ParameterInfo {
  std::string_view name;          ///< command-line name, e.g. "t-max"; the key in outputs and Python is key()
  std::string_view meaning;       ///< one line, for --help
  std::string_view unit;          ///< unit in the nondimensionalisation, "" if dimensionless
  std::string_view range;         ///< the valid range, as text
  std::string_view default_text;  ///< the default, as text
  bool integer = false;           ///< only integers are valid
  bool option = true;             ///< a command-line option, sweep axis and CSV column (false: library only)
  double (*get)(const Params&) = nullptr;
  void (*set)(Params&, double) = nullptr;

  /// Name in outputs and Python: '-' becomes '_' ("t_max").
  std::string key() const;
};

/// Every model parameter of the 2D funnel, in the order of the outputs' columns and of a sweep
/// grid's axes.
std::span<const ParameterInfo> parameters();

/// Every model parameter of the 3D funnel: those of parameters(), then release-w,
/// release-spin-x, release-spin-y (release-spin is the spin about z) and max-ode-steps.
std::span<const ParameterInfo> parameters(Space space);

/// True for a parameter that only the 3D funnel has (release-w, release-spin-x, release-spin-y,
/// max-ode-steps).
bool only_3d(const ParameterInfo& parameter);

/// The parameter with this command-line name or output key ("t-max" or "t_max"); null if none.
const ParameterInfo* find_parameter(std::string_view name);

/// A rejected parameter value: which parameter, the value given and the valid range.
struct ParamError {
  std::string name;   ///< parameter name as on the command line, e.g. "theta"
  std::string value;  ///< the offending value, as text
  std::string range;  ///< the valid range, e.g. "0 < theta < 90 (degrees)"
  /// One-line message: "invalid theta = 95: valid range is 0 < theta < 90 (degrees)".
  std::string message() const;
};

/// The range text of a V parameter given with a geometry file, which defines the walls instead.
inline constexpr std::string_view not_with_geometry = "not with a geometry file (the file defines the walls)";

/// The range text of theta given with both theta-left and theta-right, which set the walls'
/// angles instead: theta would be recorded in the output (a sweep over it would label equal rows
/// apart) as if it had been used.
inline constexpr std::string_view not_with_both_sides =
    "not with both theta-left and theta-right (they set the two walls' angles: theta would change nothing)";

/// True for the parameters of the V that a geometry file replaces (theta, gap, theta-left,
/// theta-right, spout-length; command-line or output name): giving one with a file is bad input.
bool set_by_geometry(std::string_view name);

/// Why a parameter given with the funnel of `profile` would have no effect, as a ParamError
/// range ("not with a geometry file ..."), or nothing if it has one: a V parameter
/// (set_by_geometry), or a material parameter (e, mu, beta0) that every wall of the file sets
/// for itself. Such a parameter given, or swept, is bad input: it would be recorded in the
/// output (a sweep would label equal rows apart) as if it had been used.
std::optional<std::string> unused_with_geometry(std::string_view name, const ProfileSpec& profile);

/// A parameter given by a front end (command line, Python, a figure's definition): its name (any
/// spelling find_parameter takes) and its value as the user wrote it (a list for a sweep axis).
struct GivenParameter {
  std::string name;
  std::string value;
};

/// The first given parameter that would have no effect, as a ParamError naming it, or nothing:
/// theta given with both theta-left and theta-right (not_with_both_sides), checked first, then a
/// parameter that the funnel of the geometry file `profile` (if any) replaces
/// (unused_with_geometry). Such a parameter is bad input: it would be recorded in the output (a
/// sweep over it would label equal rows apart) as if it had been used.
std::optional<ParamError> unused_given(std::span<const GivenParameter> given, const ProfileSpec* profile);

/// A parameter's value as the outputs report it: NaN (JSON null, an empty CSV field, Python None
/// or NaN) for one that the funnel of a geometry file leaves unused (unused_with_geometry), and
/// for theta when theta-left and theta-right are both set, so that no output shows a theta the
/// funnel does not have; else info.get(p).
double reported_value(const ParameterInfo& info, const Params& p);

/// Checks every field (NaN and infinities included); the first invalid one, if any.
std::optional<ParamError> validate(const Params& params);

/// The range of theta for the period-2 orbit's eigenvalues (validate_orbit), narrower than the model's.
inline constexpr std::string_view orbit_theta_range = "1e-3 <= theta < 90 (degrees) for the orbit";

/// The checks of the parameters the period-2 orbit theory reads (theta, beta0, inertia, radius;
/// funnel orbit): each in its own range, independent of the funnel's gap and release line.
std::optional<ParamError> validate_orbit(const Params& params);

/// validate(params), then the space: in 2D every 3D-only parameter must be at its default (0 for
/// the release's velocity and spins).
std::optional<ParamError> validate(const Params& params, Space space);

/// Valid-range text of a parameter by its name (e.g. "theta"), for help texts; empty if unknown.
std::string_view valid_range(std::string_view name);

/// Sets the parameter `name` to `value`; an error for an unknown name (range "a model
/// parameter: ...") or a non-integral value of an integer parameter. No range check.
std::optional<ParamError> set_parameter_checked(Params& params, std::string_view name, double value);

/// Shortest text that reads back as the same double.
std::string format_number(double value);

/// Number of release positions in an ensemble; default of docs/model.md §8.
inline constexpr std::int64_t default_samples = 4000;

}  // namespace funnel
