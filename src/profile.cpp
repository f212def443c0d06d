// Checks of a user's wall profile (docs/model.md §2b): every rule the engine relies on, with an
// error that names the side, the vertex or segment, its value and the rule.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "funnel/funnel.hpp"

namespace funnel {

/// Distance from p to the segment [a, b].
double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double len2 = dot(d, d);
  const double t = len2 > 0.0 ? std::clamp(dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
  const Vec2 q = p - (a + t * d);
  return std::hypot(q.x, q.y);
}

namespace {

/// The smallest distance between the two walls, each with its top segment continued upward
/// (docs/model.md §2b) as far as `reach` above the highest vertex; that between two polylines
/// that do not cross is at a vertex of one of them. Also the vertex and the wall it is near.
struct Closest {
  double distance;
  int side;   ///< the side of the vertex
  Vec2 vertex;
};
Closest closest_walls(const ProfileSpec& spec, double reach) {
  std::array<std::vector<Vec2>, 2> walls = spec.sides;
  double top = -std::numeric_limits<double>::infinity();
  for (const auto& w : walls) {
    for (const Vec2 v : w) top = std::max(top, v.y);
  }
  for (auto& w : walls) {  // the top segment continued to top + reach
    const Vec2 d = w[0] - w[1];
    if (d.y > 0.0) w.insert(w.begin(), w[0] + ((top + reach - w[0].y) / d.y) * d);
  }
  Closest best{std::numeric_limits<double>::infinity(), 0, {}};
  for (int i = 0; i < 2; ++i) {
    const auto& other = walls[static_cast<std::size_t>(1 - i)];
    for (const Vec2 v : walls[static_cast<std::size_t>(i)]) {
      for (std::size_t k = 0; k + 1 < other.size(); ++k) {
        const double dist = segment_distance(v, other[k], other[k + 1]);
        if (dist < best.distance) best = {dist, i, v};
      }
    }
  }
  return best;
}

const char* side_name(int i) { return i == 0 ? "left" : "right"; }

ParamError profile_error(const std::string& where, const std::string& value, const std::string& rule) {
  return ParamError{"geometry " + where, value, rule};
}

std::string point_text(Vec2 p) { return "(" + format_number(p.x) + ", " + format_number(p.y) + ")"; }

/// x of a wall's surface at height y (y within the wall's heights), for a monotone wall.
double surface_x(const std::vector<Vec2>& v, double y) {
  if (y >= v.front().y) {  // the top segment, continued without limit
    const Vec2 d = v[0] - v[1];
    return v[0].x + d.x * (y - v[0].y) / d.y;
  }
  for (std::size_t k = 0; k + 1 < v.size(); ++k) {
    const Vec2 hi = v[k], lo = v[k + 1];
    if (y <= hi.y && y >= lo.y) return hi.y == lo.y ? (hi.x + lo.x) / 2.0 : lo.x + (hi.x - lo.x) * (y - lo.y) / (hi.y - lo.y);
  }
  return v.back().x;
}

}  // namespace

std::optional<ParamError> validate_profile(const ProfileSpec& spec, const Params& params) {
  constexpr double min_length = 1e-9;  // units of H: shorter segments are rounding, not geometry
  constexpr double max_coordinate = 1e6;
  for (int i = 0; i < 2; ++i) {
    const std::vector<Vec2>& v = spec.sides[i];
    const std::string side = side_name(i);
    if (v.size() < 2) {
      return profile_error(side + ".vertices", std::to_string(v.size()) + " vertices",
                           "at least 2 vertices (top to bottom) per side");
    }
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (!(std::fabs(v[k].x) <= max_coordinate && std::fabs(v[k].y) <= max_coordinate)) {
        return profile_error(side + ".vertices[" + std::to_string(k) + "]", point_text(v[k]),
                             "finite coordinates, |x|, |y| <= 1e6 (units of H)");
      }
    }
    const double inward = i == 0 ? 1.0 : -1.0;  // the direction of the outlet from this side
    for (std::size_t k = 0; k + 1 < v.size(); ++k) {
      const Vec2 d = v[k + 1] - v[k];  // down the wall
      const std::string where = side + " segment " + std::to_string(k) + "-" + std::to_string(k + 1);
      if (!(std::hypot(d.x, d.y) > min_length)) {
        return profile_error(where, point_text(v[k]) + " to " + point_text(v[k + 1]),
                             "segments longer than 1e-9 (units of H): drop repeated vertices");
      }
      if (d.y > 0.0 || inward * d.x < 0.0) {
        return profile_error(where, point_text(v[k]) + " to " + point_text(v[k + 1]),
                             std::string("a wall that goes down (or level) and towards the outlet from its top ") +
                                 "to its lower end: x " + (i == 0 ? "non-decreasing" : "non-increasing") +
                                 " and y non-increasing along the vertices");
      }
      if (k > 0) {
        const Vec2 u = v[k] - v[k - 1];
        const double cross = u.x * d.y - u.y * d.x;
        if (std::fabs(cross) <= 1e-12 * std::hypot(u.x, u.y) * std::hypot(d.x, d.y)) {
          return profile_error(side + ".vertices[" + std::to_string(k) + "]", point_text(v[k]),
                               "a vertex where the wall turns: merge collinear segments");
        }
      }
    }
    if (v[0].y == v[1].y) {
      return profile_error(side + " segment 0-1", point_text(v[0]) + " to " + point_text(v[1]),
                           "a top segment that rises (not horizontal): the wall continues along it upward");
    }
    const std::optional<double> materials[3] = {spec.e[i], spec.mu[i], spec.beta0[i]};
    if (materials[0] && !(*materials[0] >= 0.0 && *materials[0] <= 1.0)) {
      return profile_error(side + ".e", format_number(*materials[0]), "0 <= e <= 1");
    }
    if (materials[1] && !(*materials[1] >= 0.0 && std::isfinite(*materials[1]))) {
      return profile_error(side + ".mu", format_number(*materials[1]), "mu >= 0 (finite)");
    }
    if (materials[2] && !(*materials[2] >= -1.0 && *materials[2] <= 1.0)) {
      return profile_error(side + ".beta0", format_number(*materials[2]), "-1 <= beta0 <= 1");
    }
  }

  const Vec2 el = spec.sides[0].back(), er = spec.sides[1].back();
  const bool closed = el.x == er.x && el.y == er.y;
  const double a = params.radius;
  if (closed) {
    // The two lowest segments must form a wedge (not parallel, not a flat floor).
    const Vec2 dl = spec.sides[0][spec.sides[0].size() - 2] - el, dr = spec.sides[1][spec.sides[1].size() - 2] - er;
    if (!(std::fabs(dl.x * dr.y - dl.y * dr.x) > 1e-12 * std::hypot(dl.x, dl.y) * std::hypot(dr.x, dr.y)) ||
        (dl.y == 0.0 && dr.y == 0.0)) {
      return profile_error("lower ends", point_text(el),
                           "a closed funnel's two lowest segments meet at an angle (a wedge, not a flat floor)");
    }
  } else {
    // Walls that go down towards the outlet narrow downwards: the narrowest passage is at the
    // higher lower end's level, and the lower ends must be farther apart than the diameter.
    const double y = std::max(el.y, er.y);
    const double width = surface_x(spec.sides[1], y) - surface_x(spec.sides[0], y);
    const double ends = std::hypot(er.x - el.x, er.y - el.y);
    if (!(el.x < er.x && width > 2.0 * a && ends > 2.0 * a)) {
      return profile_error("outlet", point_text(el) + " to " + point_text(er),
                           "the left lower end left of the right one, the walls' lower ends (or closed: equal) farther "
                           "apart than 2*radius = " + format_number(2.0 * a) + " and the walls wider than that at "
                           "the higher end's level");
    }
    // The ball's passage: nowhere may the walls come within 2a of each other (where a wall
    // slants, the horizontal width above is not the distance), so that a ball touching one wall
    // clears the other, whose contacts never look at it (an audit's narrow throat: a ball sliding
    // down one wall passed 0.79 a from the other's end).
    const Closest c = closest_walls(spec, 2.0 * a);
    if (!(c.distance > 2.0 * a)) {
      return profile_error("passage", format_number(c.distance),
                           "the walls farther apart than 2*radius = " + format_number(2.0 * a) + " everywhere (the " +
                               side_name(c.side) + " vertex " + point_text(c.vertex) + " is that near the " +
                               side_name(1 - c.side) + " wall)");
    }
    // A particle that passes under the higher of two unequal lower ends has left (§2b): the
    // lower wall must not reach under it, where a ball touching that wall would be beyond the
    // vertical through the higher end (an audit's ledge over a lower end 0.001 beside it).
    // (Either way round, the lower end is er.x - el.x inside the vertical through the higher.)
    if (el.y != er.y && !(er.x - el.x >= a)) {
      return profile_error("outlet", point_text(el) + " to " + point_text(er),
                           std::string("the lower end at least radius = ") + format_number(a) +
                               " inside the vertical through the higher end (horizontally), so that the lower wall "
                               "does not reach under the higher one");
    }
  }
  if (spec.bottom && !(std::fabs(*spec.bottom) <= max_coordinate)) {
    return profile_error("bottom", format_number(*spec.bottom), "a finite height, |bottom| <= 1e6 (units of H)");
  }

  // The runtime funnel: every face's region must have a non-negative length (a short segment
  // between two concave corners may vanish for a large sphere), and the release line must have
  // a width.
  Params p = params;
  p.profile = std::shared_ptr<const ProfileSpec>(std::shared_ptr<const ProfileSpec>(), &spec);  // not owned
  const Funnel f = make_funnel(p);
  for (int i = 0; i < 2; ++i) {
    const Side& s = f.sides[i];
    for (std::size_t k = 0; k + 1 < s.faces.size(); ++k) {
      const std::size_t n = spec.sides[i].size();
      if (!(s.faces[k].length >= 0.0)) {
        return profile_error(std::string(side_name(i)) + " segment " + std::to_string(n - k - 2) + "-" +
                                 std::to_string(n - k - 1),
                             point_text(spec.sides[i][n - k - 2]) + " to " + point_text(spec.sides[i][n - k - 1]),
                             "a segment long enough for a sphere of radius " + format_number(a) +
                                 " to touch it between its corners");
      }
    }
  }
  // A release line at or below the exit level would start the particle out of the funnel (it
  // "exited" at once). Without `bottom` the line is above the higher lower end, so only a given
  // bottom can put it there.
  if (spec.bottom && !f.closed && !(f.y_release > f.y_exit)) {
    return profile_error("bottom", format_number(*spec.bottom),
                         "a height that puts the release line, bottom + release-height = " + format_number(f.y_release) +
                             ", above the exit level y = " + format_number(f.y_exit) + " (the lower of the lower ends)");
  }
  if (!(f.half_width > 0.0 && std::isfinite(f.half_width) && std::isfinite(f.x_release_mid))) {
    ParamError err{"release-height", format_number(params.release_height),
                   "release-height > 0 with a release line of positive width between the walls, here at y = " +
                       format_number(f.y_release) + " (" + format_number(params.release_height) + " above " +
                       (spec.bottom ? "the geometry's bottom" : "the higher lower end") + ", y = " +
                       format_number(f.y_bottom) + ")"};
    return err;
  }
  return std::nullopt;
}

ProfileSpec assemble_profile(const std::optional<WallSpec>& left, const std::optional<WallSpec>& right, bool mirror) {
  if (!left || !left->vertices) throw std::invalid_argument("no left wall with vertices");
  ProfileSpec spec;
  if (mirror) {
    if (right && right->vertices) throw std::invalid_argument("mirror = true and right vertices: give one or the other");
    spec = mirrored_profile(*left->vertices);
  } else {
    if (!right || !right->vertices) throw std::invalid_argument("no right wall with vertices (or mirror = true)");
    spec.sides = {*left->vertices, *right->vertices};
  }
  // The right wall's material: its own, else (mirrored) the left's, else the parameters'.
  const auto right_of = [&](std::optional<double> WallSpec::*m) {
    return right ? (*right).*m : (mirror ? (*left).*m : std::nullopt);
  };
  spec.e = {left->e, right_of(&WallSpec::e)};
  spec.mu = {left->mu, right_of(&WallSpec::mu)};
  spec.beta0 = {left->beta0, right_of(&WallSpec::beta0)};
  return spec;
}

ProfileSpec mirrored_profile(std::vector<Vec2> left) {
  ProfileSpec spec;
  spec.sides[1] = left;
  for (Vec2& p : spec.sides[1]) p.x = 0.0 - p.x;
  spec.sides[0] = std::move(left);
  return spec;
}

ProfileSpec mirror_image(const ProfileSpec& spec) {
  ProfileSpec m = spec;
  for (int side = 0; side < 2; ++side) {
    m.sides[side] = spec.sides[1 - side];
    for (Vec2& v : m.sides[side]) v.x = 0.0 - v.x;
    m.e[side] = spec.e[1 - side];
    m.mu[side] = spec.mu[1 - side];
    m.beta0[side] = spec.beta0[1 - side];
  }
  return m;
}

}  // namespace funnel
