// The parameter table and the validation of the model parameters (docs/model.md §1).
#include "funnel/params.hpp"

#include "funnel/funnel.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>

namespace funnel {

namespace {

// Captureless accessors for the table.
#define FUNNEL_FIELD(field)                                               \
  [](const Params& p) { return static_cast<double>(p.field); },          \
  [](Params& p, double v) { p.field = static_cast<decltype(p.field)>(v); }

/// Deepest vertex (where the two centre lines meet) below the outlet, in units of H: beyond it
/// the funnel's height would be lost in the rounding of its coordinates.
constexpr double max_vertex_depth = 1e8;

// The 2D parameters first; parameters() is their prefix.
constexpr std::size_t parameter_count_2d = 18;

const std::array<ParameterInfo, 22> table{{
    {"theta", "wall angle to the horizontal", "degrees", "0 < theta < 90 (degrees)", "60", false, true,
     FUNNEL_FIELD(theta)},
    {"e", "normal restitution", "", "0 <= e <= 1", "0.99", false, true, FUNNEL_FIELD(e)},
    {"mu", "Coulomb friction coefficient", "", "mu >= 0 (finite)", "1", false, true, FUNNEL_FIELD(mu)},
    {"beta0", "maximum tangential restitution (Walton)", "", "-1 <= beta0 <= 1", "0", false, true,
     FUNNEL_FIELD(beta0)},
    {"radius", "particle radius a", "H", "1e-100 <= radius < 1", "0.01", false, true, FUNNEL_FIELD(radius)},
    {"gap", "gap between the walls' lower edges (0 = closed funnel)", "H",
     "gap = 0 (closed funnel) or gap > 2*radius (finite)", "0.04", false, true, FUNNEL_FIELD(gap)},
    {"inertia", "kappa = I/(m a^2): 0.4 solid sphere, 2/3 hollow sphere, 0.5 disk", "", "inertia > 0 (finite)",
     "0.4", false, true, FUNNEL_FIELD(inertia)},
    {"t-max", "time cap", "sqrt(H/g)", "t-max > 0 (finite)", "1e5", false, true, FUNNEL_FIELD(t_max)},
    {"max-collisions", "collision cap per trajectory", "", "1 <= max-collisions < 9e18 (an integer)", "1e8", true, true,
     FUNNEL_FIELD(max_collisions)},
    {"release-height", "height H0 of the release line above the funnel bottom", "H",
     "release-height > 0 (finite), with the release line above the faces' lower ends and the vertex", "1",
     false, true, FUNNEL_FIELD(release_height)},
    {"release-u", "initial horizontal velocity of the centre", "sqrt(gH)", "finite, |release-u| <= 1e6", "0",
     false, true, FUNNEL_FIELD(release_u)},
    {"release-v", "initial vertical velocity of the centre (up positive)", "sqrt(gH)",
     "finite, |release-v| <= 1e6", "0", false, true, FUNNEL_FIELD(release_v)},
    {"release-spin", "initial spin, counter-clockwise", "sqrt(g/H)", "finite, |release-spin| <= 1e8", "0", false,
     true, FUNNEL_FIELD(release_spin)},
    {"theta-left", "angle of the left wall to the horizontal (an asymmetric V)", "degrees",
     "0 < theta-left < 90 (degrees)", "theta", false, true, [](const Params& p) { return p.left_angle(); },
     [](Params& p, double v) { p.theta_left = v; }},
    {"theta-right", "angle of the right wall to the horizontal (an asymmetric V)", "degrees",
     "0 < theta-right < 90 (degrees)", "theta", false, true, [](const Params& p) { return p.right_angle(); },
     [](Params& p, double v) { p.theta_right = v; }},
    {"spout-length", "length of vertical walls (a spout) below the edges; the exit is at their lower ends", "H",
     "spout-length >= 0 (finite), with gap > 0", "0", false, true, FUNNEL_FIELD(spout_length)},
    {"p-c", "collapse threshold on the normal speed after a collision", "sqrt(gH)", "p-c > 0 (finite)", "1e-9",
     false, false, FUNNEL_FIELD(p_c)},
    {"eps-rest", "closed funnel: energy above the vertex below which the particle rests", "mgH",
     "eps-rest > 0 (finite)", "1e-12", false, false, FUNNEL_FIELD(eps_rest)},
    {"release-w", "3D: initial velocity along z, out of the release's meridian plane", "sqrt(gH)",
     "finite, |release-w| <= 1e6; 0 in 2d", "0", false, true, FUNNEL_FIELD(release_w)},
    {"release-spin-x", "3D: initial spin about x", "sqrt(g/H)", "finite, |release-spin-x| <= 1e8; 0 in 2d", "0",
     false, true, FUNNEL_FIELD(release_spin_x)},
    {"release-spin-y", "3D: initial spin about the vertical axis", "sqrt(g/H)",
     "finite, |release-spin-y| <= 1e8; 0 in 2d", "0", false, true, FUNNEL_FIELD(release_spin_y)},
    {"max-ode-steps", "3D: integrator steps allowed in one sustained contact; a contact that needs more ends the run "
     "as trapped, flagged stalled", "", "1 <= max-ode-steps < 9e18 (an integer); 2e7 in 2d", "2e7", true, true,
     FUNNEL_FIELD(max_ode_steps)},
}};

#undef FUNNEL_FIELD

ParamError error(std::string_view name, double value) {
  return ParamError{std::string(name), format_number(value), std::string(valid_range(name))};
}

bool same_name(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const char x = a[i] == '_' ? '-' : a[i];
    const char y = b[i] == '_' ? '-' : b[i];
    if (x != y) return false;
  }
  return true;
}

}  // namespace

Params default_params() { return Params{}; }

std::string ParameterInfo::key() const {
  std::string k(name);
  for (char& c : k) {
    if (c == '-') c = '_';
  }
  return k;
}

std::span<const ParameterInfo> parameters() { return std::span(table).first(parameter_count_2d); }

std::span<const ParameterInfo> parameters(Space space) {
  return space == Space::TwoD ? parameters() : std::span<const ParameterInfo>(table);
}

bool only_3d(const ParameterInfo& parameter) { return &parameter >= table.data() + parameter_count_2d; }

std::string_view to_string(Space space) { return space == Space::TwoD ? "2d" : "3d"; }

std::optional<Space> parse_space(std::string_view text) {
  if (text == "2d") return Space::TwoD;
  if (text == "3d") return Space::ThreeD;
  return std::nullopt;
}

const ParameterInfo* find_parameter(std::string_view name) {
  for (const ParameterInfo& p : table) {
    if (same_name(p.name, name)) return &p;
  }
  return nullptr;
}

std::string format_number(double value) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value);  // shortest round-trip form
  return ec == std::errc() ? std::string(buf, ptr) : "?";
}

bool set_by_geometry(std::string_view name) {
  const ParameterInfo* p = find_parameter(name);
  if (p == nullptr) return false;
  for (const std::string_view v : {"theta", "gap", "theta-left", "theta-right", "spout-length"}) {
    if (p->name == v) return true;
  }
  return false;
}

double reported_value(const ParameterInfo& info, const Params& p) {
  if (p.profile && unused_with_geometry(info.name, *p.profile)) return std::numeric_limits<double>::quiet_NaN();
  if (info.name == "theta" && !Params::is_unset(p.theta_left) && !Params::is_unset(p.theta_right)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return info.get(p);
}

std::optional<std::string> unused_with_geometry(std::string_view name, const ProfileSpec& profile) {
  if (set_by_geometry(name)) return std::string(not_with_geometry);
  const ParameterInfo* p = find_parameter(name);
  if (p == nullptr) return std::nullopt;
  const std::array<std::optional<double>, 2>* own = p->name == "e"      ? &profile.e
                                                    : p->name == "mu"    ? &profile.mu
                                                    : p->name == "beta0" ? &profile.beta0
                                                                         : nullptr;
  if (own == nullptr || !(*own)[0] || !(*own)[1]) return std::nullopt;
  return "not with a geometry file whose walls all set their own " + std::string(p->name) + " (" +
         (profile.source.empty() ? std::string("the geometry") : profile.source) + ": left " +
         format_number(*(*own)[0]) + ", right " + format_number(*(*own)[1]) + ")";
}

std::optional<ParamError> unused_given(std::span<const GivenParameter> given, const ProfileSpec* profile) {
  const auto find = [&](std::string_view name) -> const GivenParameter* {
    for (const GivenParameter& g : given) {
      if (const ParameterInfo* p = find_parameter(g.name); p != nullptr && p->name == name) return &g;
    }
    return nullptr;
  };
  if (const GivenParameter* theta = find("theta"); theta != nullptr && find("theta-left") && find("theta-right")) {
    return ParamError{"theta", theta->value, std::string(not_with_both_sides)};
  }
  if (profile != nullptr) {
    for (const GivenParameter& g : given) {
      const ParameterInfo* p = find_parameter(g.name);
      if (p == nullptr) continue;
      if (auto why = unused_with_geometry(p->name, *profile)) return ParamError{std::string(p->name), g.value, std::move(*why)};
    }
  }
  return std::nullopt;
}

std::string ParamError::message() const {
  return "invalid " + name + " = " + value + ": valid range is " + range;
}

std::string_view valid_range(std::string_view name) {
  const ParameterInfo* p = find_parameter(name);
  return p != nullptr ? p->range : std::string_view{};
}

std::optional<ParamError> set_parameter_checked(Params& params, std::string_view name, double value) {
  const ParameterInfo* p = find_parameter(name);
  if (p == nullptr) {
    std::string names;
    for (const ParameterInfo& q : table) {
      if (!q.option) continue;
      names += names.empty() ? "" : ", ";
      names += q.name;
    }
    return ParamError{std::string(name), format_number(value), "a model parameter: " + names};
  }
  if (p->integer && !(value == std::floor(value) && std::fabs(value) < 9.0e18)) {
    return ParamError{std::string(p->name), format_number(value), std::string(p->range)};
  }
  p->set(params, value);
  return std::nullopt;
}

std::optional<ParamError> validate(const Params& params) {
  // Every comparison is written so that NaN fails it.
  if (!(params.theta > 0.0 && params.theta < 90.0)) return error("theta", params.theta);
  if (!(params.e >= 0.0 && params.e <= 1.0)) return error("e", params.e);
  if (!(params.mu >= 0.0 && std::isfinite(params.mu))) return error("mu", params.mu);
  if (!(params.beta0 >= -1.0 && params.beta0 <= 1.0)) return error("beta0", params.beta0);
  if (!(params.radius >= min_radius && params.radius < 1.0)) return error("radius", params.radius);
  // With a geometry file the V's gap is unused (the file's outlet is checked by validate_profile):
  // its default must not limit the radius.
  if (!params.profile && !(params.gap == 0.0 || (params.gap > 2.0 * params.radius && std::isfinite(params.gap)))) {
    ParamError err = error("gap", params.gap);
    err.range += " with radius = " + format_number(params.radius);
    return err;
  }
  if (!(params.release_height > 0.0 && std::isfinite(params.release_height))) {
    return error("release-height", params.release_height);
  }
  for (const auto& [name, value] : {std::pair<const char*, double>{"theta-left", params.theta_left},
                                    {"theta-right", params.theta_right}}) {
    if (!Params::is_unset(value) && !(value > 0.0 && value < 90.0)) return error(name, value);
  }
  if (!(params.spout_length >= 0.0 && std::isfinite(params.spout_length))) {
    return error("spout-length", params.spout_length);
  }
  if (params.spout_length > 0.0 && params.gap == 0.0) {
    ParamError err = error("spout-length", params.spout_length);
    err.range = "spout-length = 0 in a closed funnel (gap = 0): a spout hangs below an open outlet";
    return err;
  }
  if (params.profile && (!Params::is_unset(params.theta_left) || !Params::is_unset(params.theta_right) ||
                         params.spout_length != 0.0)) {
    const char* name = !Params::is_unset(params.theta_left)    ? "theta-left"
                       : !Params::is_unset(params.theta_right) ? "theta-right"
                                                              : "spout-length";
    ParamError err = error(name, find_parameter(name)->get(params));
    err.range = not_with_geometry;
    return err;
  }
  for (const double theta : {params.left_angle(), params.right_angle()}) {
    const bool own = theta != params.theta;
    const char* name = !own ? "theta" : theta == params.left_angle() ? "theta-left" : "theta-right";
    const double rad = theta * std::numbers::pi / 180.0;
    const double y_bottom = 0.5 * params.gap * std::tan(rad) - params.radius / std::cos(rad);
    // The derived geometry must be finite (found by fuzz/fuzz_parse): a gap near the largest
    // double overflows y_b.
    if (!std::isfinite(y_bottom)) {
      ParamError err = error("gap", params.gap);
      err.range += " with (gap/2) tan(theta) finite";
      return err;
    }
    // Heights are measured from the vertex, where the centre lines meet: for a wall within
    // rounding of vertical over a wide gap it lies so far below the outlet (5.6e16 H at
    // 90 - 1.4e-14 degrees and gap 64) that the funnel's own height is lost in the rounding of
    // its coordinates, and the release line ended up beyond the walls (found by
    // fuzz/fuzz_physics). The vertex must lie within max_vertex_depth H of the outlet.
    if (!(std::fabs(y_bottom) <= max_vertex_depth)) {
      // The angle is named when the wall is within a few 1e-5 degrees of vertical (no gap or
      // radius of a sane size reaches 1e8 H otherwise), else the gap (a gap of 1e9 at 60 degrees
      // blamed the angle the user had not set).
      const bool blame_angle = std::tan(rad) > 1e6;
      ParamError err = error(blame_angle ? name : "gap", blame_angle ? theta : params.gap);
      err.range = std::string(blame_angle ? "0 < " + std::string(name) + " < 90 (degrees)" : "gap >= 0") +
                  " with the vertex within 1e8 H of the outlet: |(gap/2) tan(theta) - radius/cos(theta)| <= 1e8";
      return err;
    }
    if (params.profile) break;  // the profile's own checks (validate_profile)
    // The release line must lie above the vertex, where the centre lines meet (this fails only
    // for a wide particle in a very steep closed funnel, or a low release line) ...
    if (!(params.release_height + y_bottom > 0.0)) {
      // Named: the radius or the release height if putting it back to its default satisfies the
      // rule (the user's choice, most likely), else the angle; the values that combine are given.
      const auto holds = [&](const Params& q) {
        return q.release_height + 0.5 * q.gap * std::tan(rad) - q.radius / std::cos(rad) > 0.0;
      };
      const Params defaults;
      Params q = params;
      q.radius = defaults.radius;
      const bool blame_radius = params.radius != defaults.radius && holds(q);
      q = params;
      q.release_height = defaults.release_height;
      const bool blame_height = !blame_radius && params.release_height != defaults.release_height && holds(q);
      ParamError err = blame_radius   ? error("radius", params.radius)
                       : blame_height ? error("release-height", params.release_height)
                                      : error(name, theta);
      err.range = std::string(blame_radius   ? "1e-100 <= radius < 1"
                              : blame_height ? "release-height > 0"
                                             : "0 < " + std::string(name) + " < 90 (degrees)") +
                  " with the release line above the funnel's vertex: release-height + (gap/2) tan(theta) - "
                  "radius/cos(theta) > 0 (here " + name + " = " + format_number(theta) + ", gap = " +
                  format_number(params.gap) + ", radius = " + format_number(params.radius) + ", release-height = " +
                  format_number(params.release_height) + ")";
      return err;
    }
    // ... and, in an open funnel, above the faces' lower ends C* (a cos(theta) above the edges),
    // where the funnel's width is bounded by the faces.
    if (params.gap != 0.0 && !(params.release_height > params.radius * std::cos(rad))) {
      ParamError err = error("release-height", params.release_height);
      err.range = "release-height > radius * cos(theta) = " + format_number(params.radius * std::cos(rad)) +
                  " (the release line above the lower ends of the faces)";
      return err;
    }
    // A wall's reach along the release line, (y_0 + spout) / tan(theta), is kept within
    // max_vertex_depth H, as the vertex's depth is. A subnormal theta (below ~1e-306 degrees)
    // overflowed it and made every output NaN (found by fuzz/fuzz_parse; then by fuzz/fuzz_physics
    // with a spout). A nearly flat wall (1.2e-143 degrees: a reach of 1e141 H) still gave finite
    // numbers but lost the funnel in their rounding: the particle landed 3.4e125 H out on the flat
    // wall, and its sliding contact found itself past the wall's lower end at once and jumped to
    // the edge in no time (found by fuzz/fuzz_physics). Within 1e8 H the rounding of a position
    // (1.5e-8 H) stays below any radius the engine is tested with.
    const auto reach_of = [&](const Params& q) {
      return (q.release_height + q.spout_length + (0.5 * q.gap * std::tan(rad) - q.radius / std::cos(rad))) / std::tan(rad);
    };
    if (!(reach_of(params) <= max_vertex_depth)) {
      // Named: the spout, the release height or the gap if putting it back to its default
      // brings the reach within the limit (a gap of 3e8 at 30 degrees blamed the angle), else
      // the angle.
      const Params defaults;
      const char* blamed = name;
      double value = theta;
      std::string range = "0 < " + std::string(name) + " < 90 (degrees)";
      for (const char* candidate : {"spout-length", "release-height", "gap"}) {
        const ParameterInfo* info = find_parameter(candidate);
        if (info->get(params) == info->get(defaults)) continue;
        Params q = params;
        info->set(q, info->get(defaults));
        if (reach_of(q) <= max_vertex_depth) {
          blamed = candidate;
          value = info->get(params);
          range = std::string(candidate) + (std::string_view(candidate) == "release-height" ? " > 0" : " >= 0");
          break;
        }
      }
      ParamError err = error(blamed, value);
      err.range = range + " with the release line's half-width (H0 + spout-length + y_b)/tan(theta) at most 1e8 H (here " +
                  name + " = " + format_number(theta) + ", gap = " + format_number(params.gap) + ", release-height = " +
                  format_number(params.release_height) + ", spout-length = " + format_number(params.spout_length) + ")";
      return err;
    }
  }
  if (!(params.inertia > 0.0 && std::isfinite(params.inertia))) return error("inertia", params.inertia);
  if (!(params.t_max > 0.0 && std::isfinite(params.t_max))) return error("t-max", params.t_max);
  if (!(params.max_collisions >= 1)) {
    return ParamError{"max-collisions", std::to_string(params.max_collisions),
                      std::string(valid_range("max-collisions"))};
  }
  if (!(std::fabs(params.release_u) <= 1e6)) return error("release-u", params.release_u);
  if (!(std::fabs(params.release_v) <= 1e6)) return error("release-v", params.release_v);
  if (!(std::fabs(params.release_spin) <= 1e8)) return error("release-spin", params.release_spin);
  if (!(params.p_c > 0.0 && std::isfinite(params.p_c))) return error("p-c", params.p_c);
  if (!(params.eps_rest > 0.0 && std::isfinite(params.eps_rest))) return error("eps-rest", params.eps_rest);
  if (!(std::fabs(params.release_w) <= 1e6)) return error("release-w", params.release_w);
  if (!(std::fabs(params.release_spin_x) <= 1e8)) return error("release-spin-x", params.release_spin_x);
  if (!(std::fabs(params.release_spin_y) <= 1e8)) return error("release-spin-y", params.release_spin_y);
  if (!(params.max_ode_steps >= 1)) {
    return ParamError{"max-ode-steps", std::to_string(params.max_ode_steps), std::string(valid_range("max-ode-steps"))};
  }
  if (params.profile) return validate_profile(*params.profile, params);
  return std::nullopt;
}

std::optional<ParamError> validate_orbit(const Params& params) {
  // Below 1e-3 degrees the eigenvalues near 1 (1 +- O(theta)) are not resolved: at 1e-8 the
  // orbit came out "stable" and at 1e-200 every eigenvalue 0 (found by an audit).
  if (!(params.theta >= 1e-3 && params.theta < 90.0)) {
    return ParamError{"theta", format_number(params.theta),
                      std::string(orbit_theta_range) +
                          ": below it its eigenvalues 1 +- O(theta) are not resolved in double precision"};
  }
  if (!(params.beta0 >= -1.0 && params.beta0 <= 1.0)) return error("beta0", params.beta0);
  if (!(params.inertia > 0.0 && std::isfinite(params.inertia))) return error("inertia", params.inertia);
  if (!(params.radius >= min_radius && params.radius < 1.0)) return error("radius", params.radius);
  return std::nullopt;
}

std::optional<ParamError> validate(const Params& params, Space space) {
  if (auto err = validate(params)) return err;
  if (space == Space::ThreeD) {
    // The 3D funnel is the cone of theta and gap: the 2D shapes are 2D only.
    if (params.profile) return ParamError{"geometry", params.profile->source, "a 2D funnel only (--space 2d)"};
    for (const char* name : {"theta-left", "theta-right", "spout-length"}) {
      const ParameterInfo* info = find_parameter(name);
      const double v = info->get(params);
      const double plain = std::string_view(name) == "spout-length" ? 0.0 : params.theta;
      if (v != plain) {
        // The cone has one angle: a wall's own angle (or a spout) is a 2D shape.
        const std::string same = std::string_view(name) == "spout-length" ? "0" : "theta (" + format_number(plain) + ")";
        return ParamError{name, format_number(v),
                          std::string(name) + " = " + same + " in 3d, the cone of theta and gap (a 2D shape only: --space 2d)"};
      }
    }
    return std::nullopt;
  }
  const Params defaults = default_params();
  for (std::size_t i = parameter_count_2d; i < table.size(); ++i) {
    const ParameterInfo& p = table[i];
    if (p.get(params) != p.get(defaults)) {
      return ParamError{std::string(p.name), format_number(p.get(params)),
                        std::string(p.default_text) + " in 2d: " + std::string(p.name) +
                            " is a 3D option (use --space 3d)"};
    }
  }
  return std::nullopt;
}

}  // namespace funnel
