// Validation of the model parameters (MODEL.md §1).
#include "funnel/params.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <charconv>
#include <utility>

namespace funnel {

namespace {

constexpr std::array<std::pair<std::string_view, std::string_view>, 11> range_table{{
    {"theta", "0 < theta < 90 (degrees)"},
    {"e", "0 <= e <= 1"},
    {"mu", "mu >= 0 (finite)"},
    {"beta0", "-1 <= beta0 <= 1"},
    {"radius", "0 < radius < 1"},
    {"gap", "gap = 0 (closed funnel) or gap > 2*radius (finite)"},
    {"inertia", "inertia > 0 (finite)"},
    {"t-max", "t-max > 0 (finite)"},
    {"max-collisions", "max-collisions >= 1"},
    {"p-c", "p-c > 0 (finite)"},
    {"eps-rest", "eps-rest > 0 (finite)"},
}};

std::string format_value(double value) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value);  // shortest round-trip form
  return ec == std::errc() ? std::string(buf, ptr) : "?";
}

ParamError error(std::string_view name, double value) {
  return ParamError{std::string(name), format_value(value), std::string(valid_range(name))};
}

}  // namespace

Params default_params() { return Params{}; }

std::string ParamError::message() const {
  return "invalid " + name + " = " + value + ": valid range is " + range;
}

std::string_view valid_range(std::string_view name) {
  for (const auto& [key, text] : range_table) {
    if (key == name) return text;
  }
  return {};
}

std::optional<ParamError> validate(const Params& params) {
  // Every comparison is written so that NaN fails it.
  if (!(params.theta > 0.0 && params.theta < 90.0)) return error("theta", params.theta);
  if (!(params.e >= 0.0 && params.e <= 1.0)) return error("e", params.e);
  if (!(params.mu >= 0.0 && std::isfinite(params.mu))) return error("mu", params.mu);
  if (!(params.beta0 >= -1.0 && params.beta0 <= 1.0)) return error("beta0", params.beta0);
  if (!(params.radius > 0.0 && params.radius < 1.0)) return error("radius", params.radius);
  if (!(params.gap == 0.0 || (params.gap > 2.0 * params.radius && std::isfinite(params.gap)))) {
    ParamError err = error("gap", params.gap);
    err.range += " with radius = " + format_value(params.radius);
    return err;
  }
  // The release point (H = 1 above the funnel bottom) must lie above the vertex, where the
  // centre lines meet; this fails only for a wide particle in a very steep closed funnel.
  {
    const double rad = params.theta * std::numbers::pi / 180.0;
    const double y_bottom = 0.5 * params.gap * std::tan(rad) - params.radius / std::cos(rad);
    if (!(1.0 + y_bottom > 0.0)) {
      ParamError err = error("theta", params.theta);
      err.range = "0 < theta < 90 (degrees) with the release point above the funnel's vertex: "
                  "1 + (gap/2) tan(theta) - radius/cos(theta) > 0";
      return err;
    }
    // The derived geometry must be finite (found by fuzz/fuzz_parse): a gap near the largest
    // double overflows y_b, and a subnormal theta (below ~1e-306 degrees) overflows the
    // release line's half-width L = y_0 / tan(theta); either made every output NaN.
    if (!std::isfinite(y_bottom)) {
      ParamError err = error("gap", params.gap);
      err.range += " with (gap/2) tan(theta) finite";
      return err;
    }
    if (!std::isfinite((1.0 + y_bottom) / std::tan(rad))) {
      ParamError err = error("theta", params.theta);
      err.range = "0 < theta < 90 (degrees) with a finite half-width (1 + y_b)/tan(theta) of the release line";
      return err;
    }
  }
  if (!(params.inertia > 0.0 && std::isfinite(params.inertia))) return error("inertia", params.inertia);
  if (!(params.t_max > 0.0 && std::isfinite(params.t_max))) return error("t-max", params.t_max);
  if (!(params.max_collisions >= 1)) {
    return ParamError{"max-collisions", std::to_string(params.max_collisions),
                      std::string(valid_range("max-collisions"))};
  }
  if (!(params.p_c > 0.0 && std::isfinite(params.p_c))) return error("p-c", params.p_c);
  if (!(params.eps_rest > 0.0 && std::isfinite(params.eps_rest))) return error("eps-rest", params.eps_rest);
  return std::nullopt;
}

}  // namespace funnel
