// Model parameters (MODEL.md §1) and their validation.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace funnel {

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
  double p_c = 1e-9;          ///< collapse threshold on the normal speed after a face collision, > 0
  double eps_rest = 1e-12;    ///< closed funnel: energy above the vertex below which the particle rests, > 0
};

/// The documented defaults of MODEL.md §1 and §5–6.
Params default_params();

/// A rejected parameter value: which parameter, the value given and the valid range.
struct ParamError {
  std::string name;   ///< parameter name as on the command line, e.g. "theta"
  std::string value;  ///< the offending value, as text
  std::string range;  ///< the valid range, e.g. "0 < theta < 90 (degrees)"
  /// One-line message: "invalid theta = 95: valid range is 0 < theta < 90 (degrees)".
  std::string message() const;
};

/// Checks every field (NaN and infinities included); the first invalid one, if any.
std::optional<ParamError> validate(const Params& params);

/// Valid-range text of a parameter by its name (e.g. "theta"), for help texts; empty if unknown.
std::string_view valid_range(std::string_view name);

/// Number of release positions in an ensemble; default of MODEL.md §8.
inline constexpr std::int64_t default_samples = 4000;

}  // namespace funnel
