// Self-retracing orbits of an elastic frictionless particle: bracketing and refining the turn angle.
#include "funnel/retrace.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "funnel/ensemble.hpp"
#include "funnel/geometry.hpp"

namespace funnel::retrace {

std::string_view to_string(Turn turn) { return turn == Turn::Wall ? "wall" : "rest"; }

Params frictionless(const Params& params) {
  Params p = params;
  p.e = 1.0;
  p.mu = 0.0;
  return p;
}

namespace detail {

bool atan2_negative(double y, double x) {
  // Where |y| is not tiny next to |x| (both finite, y not 0), atan2 is at least about 2^-900 in
  // size, so not 0, and has y's sign.
  if (y != 0.0 && std::isfinite(y) && std::isfinite(x) && std::fabs(y) >= 0x1p-900 * std::fabs(x)) return y < 0.0;
  return std::atan2(y, x) < 0.0;
}

}  // namespace detail

namespace {

/// Unit tangent of a wall pointing up the wall, mirror symmetric: left (-cos, sin), right (cos, sin).
Vec2 up_tangent(const Geometry& g, Wall wall) { return {wall_sign(wall) * g.cos_t, g.sin_t}; }

/// A turn angle as the arguments (y, x) of its atan2: computed only where its value is needed (a
/// scan compares most of them only by sign, and a refinement needs one collision's of each run).
struct AngleArgs {
  double y, x;
  double value() const { return std::atan2(y, x); }
  bool negative() const { return detail::atan2_negative(y, x); }
};

/// The turn angles of a face collision.
struct Turns {
  AngleArgs wall;  ///< of the incoming velocity to the wall normal, (-pi/2, pi/2)
  AngleArgs rest;  ///< of the outgoing velocity to the upward vertical, (-pi, pi]
};

/// The first collisions of a release: their events, walls and turn angles.
struct Probe {
  std::vector<Event> hits;  ///< face collisions, in order, up to the first other event
  std::string sequence;     ///< 'L'/'R' per face collision
  std::vector<Turns> turns;  ///< per face collision
};

/// Keeps the face collisions of a run up to its first other event, and ends the run there.
class ProbeSink final : public EventSink {
 public:
  ProbeSink(const Geometry& g, Probe& out) : g_(g), out_(out) {}
  void record(const Event& e) override {
    if (done_) return;
    if (e.kind != EventKind::Face) {
      done_ = true;  // an edge, a contact or the exit ends the clean prefix
      return;
    }
    const Vec2 n = face_normal(g_, *e.wall);
    const Vec2 tau = up_tangent(g_, *e.wall);
    out_.hits.push_back(e);
    out_.sequence += *e.wall == Wall::Left ? 'L' : 'R';
    out_.turns.push_back({{dot(e.velocity_before, tau), -dot(e.velocity_before, n)}, {e.velocity_after.x, e.velocity_after.y}});
  }
  bool finished() const override { return done_; }

 private:
  const Geometry& g_;
  Probe& out_;
  bool done_ = false;
};

Probe probe(const Params& p, const Geometry& g, const Funnel& f, double fraction, int k) {
  Params q = p;
  q.max_collisions = k;
  Probe out;
  const auto n = static_cast<std::size_t>(std::max(k, 0));
  out.hits.reserve(n);
  out.sequence.reserve(n);
  out.turns.reserve(n);
  ProbeSink sink(g, out);
  simulate_release(q, f, fraction, &sink);
  return out;
}

const AngleArgs& turn_args(const Probe& pr, Turn turn, int k) {
  const Turns& t = pr.turns[static_cast<std::size_t>(k - 1)];
  return turn == Turn::Wall ? t.wall : t.rest;
}

double turn_angle(const Probe& pr, Turn turn, int k) { return turn_args(pr, turn, k).value(); }

/// A sign change of the turn angle of collision k between two releases with the same first k walls.
struct Bracket {
  double lo, hi;
  int k;
  Turn turn;
  std::string sequence;
};

/// A zero crossing of the turn angle between two samples. The wall angle lies in (-pi/2, pi/2); the
/// rest angle wraps at +-pi (straight down), and a sign change there is not a crossing of 0.
bool crosses(Turn turn, double a, double b) {
  if ((a < 0.0) == (b < 0.0)) return false;
  return turn == Turn::Wall || std::fabs(a) + std::fabs(b) < std::numbers::pi;
}

/// crosses() for collision k of two probes, their angles computed only where the signs differ.
bool crosses(Turn turn, const Probe& pa, const Probe& pb, int k) {
  const AngleArgs &a = turn_args(pa, turn, k), &b = turn_args(pb, turn, k);
  if (a.negative() == b.negative()) return false;
  return crosses(turn, a.value(), b.value());
}

/// Number of leading collisions on which two probes agree.
int agreeing_prefix(const Probe& a, const Probe& b) {
  const std::size_t n = std::min(a.sequence.size(), b.sequence.size());
  std::size_t i = 0;
  while (i < n && a.sequence[i] == b.sequence[i]) ++i;
  return static_cast<int>(i);
}

class Search {
 public:
  Search(const Params& p, const Options& o) : p_(p), g_(make_geometry(p)), f_(make_funnel(p)), opt_(o) {}

  /// Brackets on the interval [a, b] for k >= k_min; bisects where the sequences part.
  void brackets(double a, const Probe& pa, double b, const Probe& pb, int k_min, int depth, std::vector<Bracket>& out) const {
    const int agree = std::min(agreeing_prefix(pa, pb), opt_.max_bounces);
    for (int k = k_min; k <= agree; ++k) {
      for (const Turn turn : {Turn::Wall, Turn::Rest}) {
        if (turn == Turn::Rest && !opt_.rest_turns) continue;
        if (crosses(turn, pa, pb, k)) {
          out.push_back({a, b, k, turn, pa.sequence.substr(0, static_cast<std::size_t>(k))});
        }
      }
    }
    // Where the sequences part, a root may lie between a sample and the change: look closer.
    const bool parted = agree < opt_.max_bounces &&
                        (static_cast<int>(pa.sequence.size()) > agree || static_cast<int>(pb.sequence.size()) > agree);
    if (!parted || depth >= max_depth) return;
    const double m = 0.5 * (a + b);
    const Probe pm = at(m);
    const int next = std::max(k_min, agree + 1);
    brackets(a, pa, m, pm, next, depth + 1, out);
    brackets(m, pm, b, pb, next, depth + 1, out);
  }

  /// Turn angle of collision k at release f, or nullopt if its first k walls are not `sequence`.
  std::optional<double> angle(double f, const Bracket& br) const {
    const Probe pr = at(f, br.k);
    if (pr.sequence.size() < static_cast<std::size_t>(br.k) || pr.sequence.compare(0, br.sequence.size(), br.sequence) != 0) {
      return std::nullopt;
    }
    return turn_angle(pr, br.turn, br.k);
  }

  /// Brent's method on the turn angle over the bracket, to the last bits; nullopt if it leaves the sequence.
  std::optional<double> refine(const Bracket& br) const {
    double a = br.lo, b = br.hi;
    auto fa0 = angle(a, br), fb0 = angle(b, br);
    if (!fa0 || !fb0) return std::nullopt;
    double fa = *fa0, fb = *fb0;
    double c = a, fc = fa, d = b - a, e = d;
    for (int iter = 0; iter < 200; ++iter) {
      if ((fb > 0.0) == (fc > 0.0)) {
        c = a;
        fc = fa;
        d = e = b - a;
      }
      if (std::fabs(fc) < std::fabs(fb)) {
        a = b, b = c, c = a;
        fa = fb, fb = fc, fc = fa;
      }
      const double tol = 2.0 * std::numeric_limits<double>::epsilon() * std::fabs(b) + 1e-300;
      const double m = 0.5 * (c - b);
      if (std::fabs(m) <= tol || fb == 0.0) return b;
      if (std::fabs(e) >= tol && std::fabs(fa) > std::fabs(fb)) {
        // Inverse quadratic (or secant) step, accepted only while it stays well inside the bracket.
        const double s = fb / fa;
        double p, q;
        if (a == c) {
          p = 2.0 * m * s;
          q = 1.0 - s;
        } else {
          const double qq = fa / fc, r = fb / fc;
          p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
          q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
        }
        if (p > 0.0) q = -q;
        p = std::fabs(p);
        if (2.0 * p < std::min(3.0 * m * q - std::fabs(tol * q), std::fabs(e * q))) {
          e = d;
          d = p / q;
        } else {
          d = m;
          e = m;
        }
      } else {
        d = m;
        e = m;
      }
      a = b;
      fa = fb;
      b += std::fabs(d) > tol ? d : (m > 0.0 ? tol : -tol);
      const auto fnew = angle(b, br);
      if (!fnew) return std::nullopt;
      fb = *fnew;
    }
    return b;
  }

  /// The orbit at a refined release, or nullopt if it is not one (a jump, or a repetition).
  std::optional<Orbit> orbit_at(double f, const Bracket& br) const {
    const Probe pr = at(f, br.k);
    if (pr.sequence.size() < static_cast<std::size_t>(br.k) || pr.sequence.compare(0, br.sequence.size(), br.sequence) != 0) {
      return std::nullopt;
    }
    const double residual = std::fabs(turn_angle(pr, br.turn, br.k));
    if (!(residual <= opt_.accept_angle)) return std::nullopt;
    for (int j = 1; j < br.k; ++j) {  // an earlier turn: this is a shorter orbit, repeated
      if (std::fabs(turn_angle(pr, Turn::Wall, j)) < opt_.repeat_angle ||
          std::fabs(turn_angle(pr, Turn::Rest, j)) < opt_.repeat_angle) {
        return std::nullopt;
      }
    }
    double lowest = std::numeric_limits<double>::infinity();
    for (int j = 0; j < br.k; ++j) lowest = std::min(lowest, pr.hits[static_cast<std::size_t>(j)].position.y);
    // An orbit through the vertex (only in a closed funnel) is not a regular orbit: the corner
    // makes the flow singular there.
    if (g_.closed && !(lowest > vertex_clearance * g_.y_release)) return std::nullopt;
    const Event& turn = pr.hits[static_cast<std::size_t>(br.k - 1)];
    Orbit o;
    o.theta = p_.theta;
    o.release = f;
    o.y0 = g_.y_release;
    o.sequence = br.sequence;
    o.turn = br.turn;
    o.bounces = br.k;
    o.collisions_per_period = br.turn == Turn::Wall ? 2 * br.k - 1 : 2 * br.k;
    // Wall turn: out and back along the same path. Rest turn: up to the second rest point (time v'/g) and back.
    o.period = br.turn == Turn::Wall ? 2.0 * turn.time : 2.0 * (turn.time + turn.velocity_after.y);
    o.min_height = lowest;
    o.turn_x = turn.position.x / g_.half_width;
    o.residual = residual;
    const Eigen::Matrix2d m = monodromy(p_, o);
    o.trace = m.trace();
    o.stable = std::fabs(o.trace) < 2.0 - parabolic_margin;
    return o;
  }

  /// The orbit at the refined release, or at one of its neighbouring doubles if the engine brings
  /// that one back to rest closer: for strongly unstable orbits (|trace| in the thousands) the last
  /// bit of x0/L matters at the 1e-12 level.
  std::optional<Orbit> polish(double f, const Bracket& br) const {
    std::optional<Orbit> best = orbit_at(f, br);
    if (!best) return best;
    double best_error = return_error(*best);
    double below = f, above = f;
    for (int step = 0; step < polish_steps && best_error > polish_threshold; ++step) {
      below = std::nextafter(below, -2.0);
      above = std::nextafter(above, 2.0);
      for (const double x : {below, above}) {
        const auto o = orbit_at(x, br);
        if (!o) continue;
        const double err = return_error(*o);
        if (err < best_error) {
          best = o;
          best_error = err;
        }
      }
    }
    return best;
  }

  double return_error(const Orbit& o) const {
    const ReturnCheck r = check_return(p_, o);
    return r.left ? std::numeric_limits<double>::infinity() : std::max(r.position_error, r.speed);
  }

  Probe at(double f, int k = -1) const { return probe(p_, g_, f_, f, k < 0 ? opt_.max_bounces : k); }

 private:
  static constexpr int max_depth = 24;  // the half line's grid step / 2^24: about 3e-11 in x0/L
  static constexpr double vertex_clearance = 1e-9;  // lowest collision height / release height
  static constexpr double polish_threshold = 2e-13;  // return error (H, sqrt(gH)) below which no polishing
  static constexpr int polish_steps = 8;             // neighbouring doubles tried on each side
  Params p_;
  Geometry g_;
  Funnel f_;  // built once: every probe runs in it
  Options opt_;
};

/// The mirror image (x -> -x) of an orbit: the same orbit released at -x0.
Orbit mirror(const Orbit& o) {
  Orbit m = o;
  m.release = -o.release;
  m.turn_x = -o.turn_x;
  for (char& c : m.sequence) c = c == 'L' ? 'R' : 'L';
  return m;
}

bool orbit_order(const Orbit& a, const Orbit& b) {
  if (a.bounces != b.bounces) return a.bounces < b.bounces;
  if (a.release != b.release) return a.release < b.release;
  return a.turn < b.turn;
}

/// Extra grid points towards each end of the half line: 0.5/N times 2^-1 ... 2^-end_levels.
constexpr int end_levels = 30;

}  // namespace

std::vector<Orbit> find_orbits(const Params& params, const Options& options) {
  const Params p = frictionless(params);
  Search search(p, options);
  const int n = std::max(options.scan_points, 16);
  // Releases on the left half, x0 < 0: every sequence starts on the left wall. The right half is the mirror.
  // A uniform grid, refined geometrically towards both ends: next to the axis the particle falls
  // close to the vertex and the turn angles vary on ever smaller scales of x0/L.
  std::vector<double> grid;
  for (int j = end_levels; j >= 1; --j) grid.push_back(-1.0 + std::ldexp(0.5 / n, -j));
  for (int i = 0; i < n; ++i) grid.push_back(-1.0 + (i + 0.5) / n);
  for (int j = 1; j <= end_levels; ++j) grid.push_back(-std::ldexp(0.5 / n, -j));
  // Each interval's brackets need only its two ends' probes: two are kept, not the grid's (a
  // probe holds its collisions' events, about 1 kB: 10^6 scan points held 1 GB per angle).
  std::vector<Bracket> brackets;
  Probe previous = search.at(grid.front());
  for (std::size_t i = 0; i + 1 < grid.size(); ++i) {
    Probe next = search.at(grid[i + 1]);
    search.brackets(grid[i], previous, grid[i + 1], next, 1, 0, brackets);
    previous = std::move(next);
  }
  std::vector<Orbit> found;
  for (const Bracket& br : brackets) {
    const auto f = search.refine(br);
    if (!f) continue;
    const auto o = search.polish(*f, br);
    if (!o) continue;
    const bool seen = std::any_of(found.begin(), found.end(), [&](const Orbit& x) {
      return x.bounces == o->bounces && x.turn == o->turn && std::fabs(x.release - o->release) < 1e-12;
    });
    if (!seen) found.push_back(*o);
  }
  std::vector<Orbit> out = found;
  for (const Orbit& o : found) out.push_back(mirror(o));
  std::sort(out.begin(), out.end(), orbit_order);
  return out;
}

std::vector<Orbit> scan(const Params& params, const std::vector<double>& thetas, const Options& options) {
  std::vector<std::vector<Orbit>> per(thetas.size());
  const auto n = static_cast<std::int64_t>(thetas.size());
  std::int64_t finished = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(resolve_threads(options.threads))
  for (std::int64_t i = 0; i < n; ++i) {
    if (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed)) continue;
    Params p = params;
    p.theta = thetas[static_cast<std::size_t>(i)];
    per[static_cast<std::size_t>(i)] = find_orbits(p, options);
    if (options.progress) {
#pragma omp critical(funnel_retrace_progress)
      options.progress(++finished, n);
    }
  }
  std::vector<Orbit> out;
  for (auto& v : per) out.insert(out.end(), v.begin(), v.end());
  return out;
}

std::optional<Orbit> transfer(const Orbit& orbit, const Params& target, const Options& options) {
  Params p = frictionless(target);
  p.theta = orbit.theta;
  Options opt = options;
  opt.max_bounces = orbit.bounces;
  Search search(p, opt);
  // The release x0/L is the same in any funnel of this angle (the flow in the wedge is scale
  // invariant); only its last bits may move. Bracket it closely and refine again.
  const Bracket br{orbit.release - 1e-10, orbit.release + 1e-10, orbit.bounces, orbit.turn, orbit.sequence};
  const auto lo = search.angle(br.lo, br), hi = search.angle(br.hi, br);
  if (!lo || !hi || !crosses(br.turn, *lo, *hi)) return std::nullopt;
  const auto f = search.refine(br);
  if (!f) return std::nullopt;
  return search.polish(*f, br);
}

}  // namespace funnel::retrace
