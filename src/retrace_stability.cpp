// Self-retracing orbits: the reduced monodromy (Birkhoff coordinates), the engine's return check, windows.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "funnel/geometry.hpp"
#include "funnel/retrace.hpp"

namespace funnel::retrace {

namespace {

/// Unit tangent of a wall pointing up the wall: left (-cos, sin), right (cos, sin).
Vec2 up_tangent(const Geometry& g, Wall wall) { return {wall_sign(wall) * g.cos_t, g.sin_t}; }

/// Keeps the face collisions of a run and notes any other event.
class FaceLog final : public EventSink {
 public:
  void record(const Event& e) override {
    if (e.kind == EventKind::Face) {
      faces.push_back(e);
    } else {
      other = true;
    }
  }
  std::vector<Event> faces;
  bool other = false;
};

/// (s, q) of a collision: distance from the origin along the centre line and velocity up the wall.
Eigen::Vector2d birkhoff(const Geometry& g, const Event& e) {
  const Vec2 tau = up_tangent(g, *e.wall);
  return {dot(tau, e.position), dot(tau, e.velocity_after)};
}

/// Canonical sequence of a family: the one whose first collision is on the left wall.
std::string canonical(const std::string& sequence) {
  std::string s = sequence;
  if (!s.empty() && s[0] == 'R') {
    for (char& c : s) c = c == 'L' ? 'R' : 'L';
  }
  return s;
}

}  // namespace

std::vector<Event> period_collisions(const Params& params, const Orbit& orbit) {
  Params p = frictionless(params);
  p.theta = orbit.theta;
  p.max_collisions = orbit.collisions_per_period + 1;
  const Geometry g = make_geometry(p);
  FaceLog log;
  simulate_release(p, g, orbit.release, &log);
  return log.faces;
}

Eigen::Matrix2d collision_map_jacobian(const Params& params, const Event& from, const Event& to) {
  const Geometry g = make_geometry(params);
  const Vec2 n0 = face_normal(g, *from.wall), tau0 = up_tangent(g, *from.wall);
  const Vec2 n1 = face_normal(g, *to.wall), tau1 = up_tangent(g, *to.wall);
  const Vec2 v0 = from.velocity_after, v1 = to.velocity_before;
  const double t = to.time - from.time;
  const double p0 = dot(v0, n0), q0 = dot(v0, tau0);
  const double rate = dot(n1, v1);  // normal velocity on arrival, < 0
  const Vec2 gravity{0.0, -1.0};
  // On the energy surface the normal speed after the collision is p0 = sqrt(2(E - s sin) - q0^2),
  // so dp0/ds = -sin/p0 and dp0/dq = -q0/p0. The flight r(t) = r0 + v0 t + gravity t^2/2 ends when
  // n1.r = 0: dt = -n1.(dr0 + t dv0)/(n1.v1). The frictionless collision keeps q, so q' = tau1.v1.
  Eigen::Matrix2d jac;
  for (int j = 0; j < 2; ++j) {
    const Vec2 dr0 = j == 0 ? tau0 : Vec2{0.0, 0.0};
    const Vec2 dv0 = j == 0 ? (-g.sin_t / p0) * n0 : tau0 + (-q0 / p0) * n0;
    const Vec2 dr_at_t = dr0 + t * dv0;
    const double dt = -dot(n1, dr_at_t) / rate;
    const Vec2 dr1 = dr_at_t + dt * v1;
    const Vec2 dv1 = dv0 + dt * gravity;
    jac(0, j) = dot(tau1, dr1);
    jac(1, j) = dot(tau1, dv1);
  }
  return jac;
}

Eigen::Matrix2d monodromy(const Params& params, const Orbit& orbit) {
  Params p = frictionless(params);
  p.theta = orbit.theta;
  const std::vector<Event> c = period_collisions(p, orbit);
  Eigen::Matrix2d m = Eigen::Matrix2d::Identity();
  const std::size_t n = static_cast<std::size_t>(orbit.collisions_per_period);
  if (c.size() < n + 1) return Eigen::Matrix2d::Constant(std::nan(""));
  for (std::size_t i = 0; i < n; ++i) m = collision_map_jacobian(p, c[i], c[i + 1]) * m;
  return m;
}

Eigen::Matrix2d monodromy_fd(const Params& params, const Orbit& orbit, double step) {
  Params p = frictionless(params);
  p.theta = orbit.theta;
  const Geometry g = make_geometry(p);
  const std::vector<Event> c = period_collisions(p, orbit);
  if (c.empty()) return Eigen::Matrix2d::Constant(std::nan(""));
  const Event& first = c.front();
  const Wall wall = *first.wall;
  const Vec2 n = face_normal(g, wall), tau = up_tangent(g, wall);
  const Eigen::Vector2d x0 = birkhoff(g, first);
  const double energy = first.position.y + 0.5 * dot(first.velocity_after, first.velocity_after);
  const Eigen::Vector2d h(step * std::fabs(x0(0)), step * std::sqrt(2.0 * (energy - first.position.y)));
  Params run = p;
  run.max_collisions = orbit.collisions_per_period;
  // One period of the engine from a state just after the first collision, given by (s, q) at the same energy.
  auto period_map = [&](const Eigen::Vector2d& x) -> Eigen::Vector2d {
    State s;
    s.r = x(0) * tau;
    const double pn = std::sqrt(2.0 * (energy - s.r.y) - x(1) * x(1));
    s.v = x(1) * tau + pn * n;
    FaceLog log;
    simulate(run, g, s, &log);
    if (log.faces.empty()) return Eigen::Vector2d::Constant(std::nan(""));
    return birkhoff(g, log.faces.back());
  };
  Eigen::Matrix2d m;
  for (int j = 0; j < 2; ++j) {
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    d(j) = h(j);
    m.col(j) = (period_map(x0 + d) - period_map(x0 - d)) / (2.0 * h(j));
  }
  return m;
}

ReturnCheck check_return(const Params& params, const Orbit& orbit) {
  Params p = frictionless(params);
  p.theta = orbit.theta;
  p.t_max = orbit.period;  // the engine stops at exactly t = period, between collisions
  const Geometry g = make_geometry(p);
  FaceLog log;
  const Trajectory t = simulate_release(p, g, orbit.release, &log);
  const Vec2 start = release_point(g, orbit.release);
  const Vec2 d = t.final_state.r - start;
  ReturnCheck r;
  r.position_error = std::sqrt(dot(d, d));
  r.speed = std::sqrt(dot(t.final_state.v, t.final_state.v));
  r.collisions = t.collisions;
  r.left = log.other || t.status != Status::Trapped;
  return r;
}

std::vector<Window> windows(const std::vector<Orbit>& orbits, const std::vector<double>& thetas) {
  // Family -> per grid angle: 0 absent, 1 exists, 2 exists and stable (any orbit of the family).
  using Key = std::tuple<int, std::string, int>;
  std::map<Key, std::vector<int>> state;
  std::map<double, std::size_t> index;
  for (std::size_t i = 0; i < thetas.size(); ++i) index.emplace(thetas[i], i);
  for (const Orbit& o : orbits) {
    const auto it = index.find(o.theta);
    if (it == index.end()) continue;
    auto& v = state.try_emplace(Key{o.bounces, canonical(o.sequence), static_cast<int>(o.turn)},
                                std::vector<int>(thetas.size(), 0)).first->second;
    v[it->second] = std::max(v[it->second], o.stable ? 2 : 1);
  }
  std::vector<Window> out;
  for (const auto& [key, v] : state) {
    for (const int level : {1, 2}) {
      for (std::size_t i = 0; i < v.size();) {
        if (v[i] < level) {
          ++i;
          continue;
        }
        std::size_t j = i;
        while (j + 1 < v.size() && v[j + 1] >= level) ++j;
        Window w;
        w.sequence = std::get<1>(key);
        w.turn = static_cast<Turn>(std::get<2>(key));
        w.stable = level == 2;
        w.theta_from = thetas[i];
        w.theta_to = thetas[j];
        w.points = static_cast<int>(j - i + 1);
        out.push_back(w);
        i = j + 1;
      }
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Window& a, const Window& b) {
    if (a.sequence.size() != b.sequence.size()) return a.sequence.size() < b.sequence.size();
    if (a.sequence != b.sequence) return a.sequence < b.sequence;
    if (a.turn != b.turn) return a.turn < b.turn;
    if (a.stable != b.stable) return a.stable < b.stable;
    return a.theta_from < b.theta_from;
  });
  return out;
}

}  // namespace funnel::retrace
