// Building the runtime funnel from the parameters: the paper's V (bit for bit the numbers of
// make_geometry), its asymmetric and spouted variants, and wall profiles (docs/model.md §2b).
#include "funnel/funnel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace funnel {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

/// One straight segment of a wall, bottom to top, as the builder takes it.
struct SegmentIn {
  Vec2 lower;           ///< surface vertex at the segment's lower end
  double sin_a, cos_a;  ///< angle to the horizontal (0..90 degrees)
  double length;        ///< surface length; infinite for the top segment
  std::optional<Vec2> ref;  ///< a point of the centre line, if the caller knows one exactly
};

Vec2 normal_of(double ws, double sin_a, double cos_a) { return {-ws * sin_a, cos_a}; }

/// Where two centre lines n1.(r - p1) = 0 and n2.(r - p2) = 0 meet.
Vec2 meet(Vec2 n1, Vec2 p1, Vec2 n2, Vec2 p2) {
  const double c1 = dot(n1, p1), c2 = dot(n2, p2);
  const double det = n1.x * n2.y - n1.y * n2.x;
  return {(c1 * n2.y - c2 * n1.y) / det, (n1.x * c2 - n2.x * c1) / det};
}

/// The faces and corners of one wall from its segments (bottom to top). `bottom_corner` marks the
/// lower end as the shared bottom of a closed funnel (its face's region then starts at `bottom`).
Side build_side(const std::vector<SegmentIn>& segs, double ws, double a, bool bottom_corner, Vec2 bottom) {
  Side side;
  side.ws = ws;
  const std::size_t n = segs.size();
  side.faces.resize(n);
  side.corners.resize(n);
  double surface = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    Face& f = side.faces[k];
    const SegmentIn& s = segs[k];
    f.sin_a = s.sin_a;
    f.cos_a = s.cos_a;
    f.n = normal_of(ws, s.sin_a, s.cos_a);
    f.up = {ws * s.cos_a, s.sin_a};
    f.down = {-ws * s.cos_a, -s.sin_a};
    f.ref = s.ref ? *s.ref : s.lower + a * f.n;
    f.length = inf;
  }
  for (std::size_t k = 0; k < n; ++k) {
    Corner& c = side.corners[k];
    c.point = segs[k].lower;
    Face& above = side.faces[k];
    if (k == 0) {
      c.outlet = true;
      c.bottom = bottom_corner;
      c.convex = !bottom_corner;
      above.low_convex = !bottom_corner;
      above.low = bottom_corner ? bottom : c.point + a * above.n;
    } else {
      Face& below = side.faces[k - 1];
      // Convex when the segment below is steeper: the wall turns away from the particle.
      c.convex = below.sin_a * above.cos_a - below.cos_a * above.sin_a > 0.0;
      if (c.convex) {
        above.low = c.point + a * above.n;
        below.high = c.point + a * below.n;
      } else {
        above.low = meet(below.n, below.ref, above.n, above.ref);
        below.high = above.low;
      }
      above.low_convex = c.convex;
      below.high_convex = c.convex;
      below.length = dot(below.up, below.high - below.low);
    }
    if (c.convex) {
      // Arc of contact normals in the wall's own left-facing frame: from the normal of the face
      // below (the wall's underside at the lower end) to the normal of the face above.
      const double top = std::atan2(above.cos_a, above.sin_a);
      const Face* below = k == 0 ? nullptr : &side.faces[k - 1];
      const double low = below ? std::atan2(below->cos_a, below->sin_a) : top - std::numbers::pi;
      c.arc = {Vec2{ws < 0.0 ? c.point.x : 0.0 - c.point.x, c.point.y}, low, top};
      c.top = above.low.y;
    }
    above.surface_offset = surface + dot(above.up, above.low - c.point);
    surface += segs[k].length;
  }
  return side;
}

/// The segments of one wall of a V at angle theta (degrees), with an optional spout below.
std::vector<SegmentIn> v_wall(double ws, double sin_t, double cos_t, double half_gap, double y_b, double c, double spout) {
  std::vector<SegmentIn> segs;
  const Vec2 edge{ws * half_gap, y_b};
  if (spout > 0.0) segs.push_back({{ws * half_gap, y_b - spout}, 1.0, 0.0, spout, std::nullopt});
  segs.push_back({edge, sin_t, cos_t, inf, Vec2{0.0, c}});
  return segs;
}

/// The release line between the walls' centre lines at height y0, for a V of one or two angles.
void v_release(Funnel& f, double y0, double tan_l, double tan_r, double c_l, double c_r) {
  const double x_l = -(y0 - c_l) / tan_l;
  const double x_r = (y0 - c_r) / tan_r;
  f.y_release = y0;
  f.x_release_mid = 0.5 * (x_l + x_r);
  f.half_width = 0.5 * (x_r - x_l);
}

void finish(Funnel& f, const Params& params) {
  f.radius = params.radius;
  for (Side& s : f.sides) s.law = collision_constants(s.material);
  f.skip_height = -inf;
  for (const Side& s : f.sides) {
    for (const Corner& c : s.corners) {
      if (c.convex) f.skip_height = std::max(f.skip_height, c.top);
    }
  }
  const Vec2 el = f.sides[0].corners[0].point, er = f.sides[1].corners[0].point;
  f.closed = f.sides[0].corners[0].bottom;
  f.one_face = f.sides[0].faces.size() == 1 && f.sides[1].faces.size() == 1;
  f.y_exit = std::min(el.y, er.y);
  if (f.closed) {
    const Vec2 vl = f.sides[0].faces[0].low, vr = f.sides[1].faces[0].low;
    f.y_vertex = vl.y;
    const double scale = std::fmax(std::fmax(std::fabs(vl.x), std::fabs(vl.y)), std::fmax(std::fabs(vr.x), std::fabs(vr.y)));
    f.vertex_tolerance = std::ldexp(scale, -44);
  }
  if (!f.closed && el.y != er.y) {
    // The vertical under the higher end: the lower wall's end lies at least a inside it
    // (validate_profile), so no contact with the lower wall reaches it.
    f.side_exit = el.y > er.y ? -1 : 1;
    f.side_exit_end = el.y > er.y ? el : er;
  }
}

Funnel v_funnel(const Params& params) {
  Funnel f;
  f.source = "v";
  const double a = params.radius;
  const double half_gap = 0.5 * params.gap;
  const bool closed = params.gap == 0.0;
  if (params.left_angle() == params.right_angle()) {
    // The paper's V (and its spouted variant): the numbers of make_geometry, bit for bit.
    Params p = params;
    p.theta = params.left_angle();
    const Geometry g = make_geometry(p);
    for (const int i : {0, 1}) {
      const double ws = i == 0 ? -1.0 : 1.0;
      f.sides[i] = build_side(v_wall(ws, g.sin_t, g.cos_t, g.half_gap, g.y_bottom, 0.0, params.spout_length), ws, a,
                              closed, {0.0, 0.0});
    }
    f.y_bottom = g.y_bottom;
    f.y_release = g.y_release;
    f.half_width = g.half_width;
    f.x_release_mid = 0.0;
    f.symmetric = true;
  } else {
    double sn[2], cs[2], tn[2], yb[2];
    for (const int i : {0, 1}) {
      const double rad = (i == 0 ? params.left_angle() : params.right_angle()) * std::numbers::pi / 180.0;
      sn[i] = std::sin(rad);
      cs[i] = std::cos(rad);
      tn[i] = std::tan(rad);
      yb[i] = half_gap * tn[i] - a / cs[i];
    }
    // Both edges at one height, the mean of the two walls' own y_b; each centre line then
    // crosses the axis at c = y_b - y_b(side) (0 for equal angles).
    const double y_b = 0.5 * (yb[0] + yb[1]);
    double c[2];
    Vec2 bottom{0.0, 0.0};
    for (const int i : {0, 1}) c[i] = y_b - yb[i];
    if (closed) {
      const Vec2 nl{sn[0], cs[0]}, nr{-sn[1], cs[1]};
      bottom = meet(nl, {0.0, c[0]}, nr, {0.0, c[1]});
    }
    for (const int i : {0, 1}) {
      const double ws = i == 0 ? -1.0 : 1.0;
      f.sides[i] = build_side(v_wall(ws, sn[i], cs[i], half_gap, y_b, c[i], params.spout_length), ws, a, closed, bottom);
    }
    f.y_bottom = y_b;
    v_release(f, y_b + params.release_height, tn[0], tn[1], c[0], c[1]);
  }
  for (Side& s : f.sides) s.material = material(params);
  finish(f, params);
  return f;
}

/// The segments of one side of a profile, bottom to top, from its vertices (top to bottom).
std::vector<SegmentIn> profile_wall(const std::vector<Vec2>& vertices) {
  std::vector<SegmentIn> segs;
  for (std::size_t k = vertices.size() - 1; k >= 1; --k) {
    const Vec2 lower = vertices[k], upper = vertices[k - 1];
    const Vec2 d = upper - lower;
    const double len = std::hypot(d.x, d.y);
    // Vertical and horizontal segments get exact 1 and 0.
    const double sin_a = d.x == 0.0 ? 1.0 : d.y / len;
    const double cos_a = d.y == 0.0 ? 1.0 : std::fabs(d.x) / len;
    segs.push_back({lower, sin_a, cos_a, k == 1 ? inf : len, std::nullopt});
  }
  return segs;
}

/// Smallest ws * x of a centre touching the wall at height y: the inner boundary of the region
/// the centre can reach, from the face centre lines and edge circles that exist at that height.
double inner_x(const Side& side, double y, double a) {
  double best = inf;
  for (const Face& f : side.faces) {
    const double top = f.length == inf ? inf : f.high.y;
    if (f.sin_a == 0.0 || y < f.low.y || y > top) continue;
    const double x = f.ref.x - f.n.y * (y - f.ref.y) / f.n.x;
    best = std::min(best, side.ws * x);
  }
  for (const Corner& c : side.corners) {
    const double dy = y - c.point.y;
    if (!c.convex || std::fabs(dy) > a) continue;
    best = std::min(best, side.ws * c.point.x - std::sqrt(a * a - dy * dy));
  }
  return best;
}

/// `value` to 12 significant digits: the number a user typed, recovered from one computed from it.
double typed(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.12g", value);
  return std::strtod(text, nullptr);
}

/// The V (theta-left/right, gap, spout-length) a profile is, within rounding, if it is one
/// (docs/model.md §2b, "A V given as a profile"): every vertex within 1e-13 of the V's (relative
/// to the funnel's size), the top vertex on the V's wall line, the release measured from the V's
/// edges, with angles, gap and spout length of at most 12 significant digits.
std::optional<Params> v_of_profile(const ProfileSpec& spec, const Params& params) {
  const std::vector<Vec2>& left = spec.sides[0];
  const std::vector<Vec2>& right = spec.sides[1];
  if (left.size() != right.size() || left.size() < 2 || left.size() > 3) return std::nullopt;
  Params p = params;
  p.profile.reset();
  double angle[2];
  for (const int i : {0, 1}) {
    const Vec2 d = spec.sides[i][0] - spec.sides[i][1];
    angle[i] = typed(std::atan2(d.y, std::fabs(d.x)) * 180.0 / std::numbers::pi);
  }
  p.theta = angle[0];
  p.theta_left = Params::unset;
  p.theta_right = angle[1] == angle[0] ? Params::unset : angle[1];
  p.gap = typed(right[1].x - left[1].x);
  p.spout_length = left.size() == 3 ? typed(left[1].y - left[2].y) : 0.0;
  if (validate(p)) return std::nullopt;
  const Funnel v = v_funnel(p);
  double size = 1.0;
  for (const std::vector<Vec2>& side : spec.sides) {
    for (const Vec2 q : side) size = std::max({size, std::fabs(q.x), std::fabs(q.y)});
  }
  const double tol = 1e-13 * size;
  const auto near = [tol](Vec2 q, Vec2 r) { return std::fabs(q.x - r.x) <= tol && std::fabs(q.y - r.y) <= tol; };
  for (const int i : {0, 1}) {
    const std::vector<Vec2>& given = spec.sides[i];
    const Side& s = v.sides[i];
    for (std::size_t k = 0; k < s.corners.size(); ++k) {
      if (!near(given[given.size() - 1 - k], s.corners[k].point)) return std::nullopt;
    }
    const double off_line = dot(s.faces.back().n, given[0] - s.corners.back().point);
    if (!(std::fabs(off_line) <= tol)) return std::nullopt;
  }
  const double bottom = spec.bottom.value_or(std::max(left.back().y, right.back().y));
  if (!(std::fabs(bottom - v.y_bottom) <= tol)) return std::nullopt;
  return p;
}

/// Each wall's material: the parameters', with what the profile gives for that wall instead.
void apply_materials(Funnel& f, const ProfileSpec& spec, const Params& params) {
  const Material base = material(params);
  for (const int i : {0, 1}) {
    Material& m = f.sides[i].material;
    m = base;
    m.e = spec.e[i].value_or(base.e);
    m.mu = spec.mu[i].value_or(base.mu);
    m.beta0 = spec.beta0[i].value_or(base.beta0);
  }
}

bool same_material(const Funnel& f) {
  const Material& ml = f.sides[0].material;
  const Material& mr = f.sides[1].material;
  return ml.e == mr.e && ml.mu == mr.mu && ml.beta0 == mr.beta0;
}

Funnel profile_funnel(const Params& params) {
  const ProfileSpec& spec = *params.profile;
  if (const std::optional<Params> v = v_of_profile(spec, params)) {
    // The V's own numbers, so that a V written out as a profile gives the V's results bit for bit.
    Funnel f = v_funnel(*v);
    f.source = spec.source.empty() ? "profile" : spec.source;
    apply_materials(f, spec, params);
    f.symmetric = f.symmetric && same_material(f);
    finish(f, params);
    return f;
  }
  Funnel f;
  f.source = spec.source.empty() ? "profile" : spec.source;
  const double a = params.radius;
  const Vec2 el = spec.sides[0].back(), er = spec.sides[1].back();
  const bool closed = el.x == er.x && el.y == er.y;
  std::array<std::vector<SegmentIn>, 2> segs{profile_wall(spec.sides[0]), profile_wall(spec.sides[1])};
  Vec2 bottom{};
  if (closed) {
    Vec2 nrm[2], ref[2];
    for (const int i : {0, 1}) {
      const double ws = i == 0 ? -1.0 : 1.0;
      nrm[i] = normal_of(ws, segs[i][0].sin_a, segs[i][0].cos_a);
      ref[i] = segs[i][0].lower + a * nrm[i];
    }
    bottom = meet(nrm[0], ref[0], nrm[1], ref[1]);
  }
  for (const int i : {0, 1}) f.sides[i] = build_side(segs[i], i == 0 ? -1.0 : 1.0, a, closed, bottom);
  apply_materials(f, spec, params);
  f.y_bottom = spec.bottom.value_or(std::max(el.y, er.y));
  f.y_release = f.y_bottom + params.release_height;
  const double x_l = -inner_x(f.sides[0], f.y_release, a);
  const double x_r = inner_x(f.sides[1], f.y_release, a);
  f.x_release_mid = 0.5 * (x_l + x_r);
  f.half_width = 0.5 * (x_r - x_l);
  bool mirrored = spec.sides[0].size() == spec.sides[1].size();
  for (std::size_t k = 0; mirrored && k < spec.sides[0].size(); ++k) {
    mirrored = spec.sides[1][k].x == 0.0 - spec.sides[0][k].x && spec.sides[1][k].y == spec.sides[0][k].y;
  }
  f.symmetric = mirrored && same_material(f);
  if (f.symmetric) f.x_release_mid = 0.0;  // exactly: x_l = -x_r
  finish(f, params);
  return f;
}

}  // namespace

std::vector<Vec2> wall_surface(const Funnel& f, int side, double y_top) {
  const Side& s = f.sides[side];
  const Corner& last = s.corners.back();
  const Face& top = s.faces.back();
  const double along = top.up.y > 0.0 ? (y_top - last.point.y) / top.up.y : 1.0;
  std::vector<Vec2> out{last.point + along * top.up};
  for (auto c = s.corners.rbegin(); c != s.corners.rend(); ++c) out.push_back(c->point);
  return out;
}

double drawing_top(const Funnel& f) {
  double top = f.y_release;
  for (const Side& s : f.sides) top = std::max(top, s.corners.back().point.y);
  return top + 0.1;
}

Funnel make_funnel(const Params& params) {
  if (!params.profile) return v_funnel(params);
  return profile_funnel(params);
}

}  // namespace funnel
