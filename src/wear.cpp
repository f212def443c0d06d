// Binning of collisions and contact impulses along the walls.
#include "funnel/wear.hpp"

#include <algorithm>
#include <cmath>


namespace funnel {

namespace {

/// Length of a wall's surface from its lower end up to the height y (beyond its top vertex
/// along the top segment).
double surface_length_to(const Side& side, double y) {
  double s = 0.0;
  for (std::size_t k = 0; k < side.faces.size(); ++k) {
    const Face& f = side.faces[k];
    const Vec2 lower = side.corners[k].point;
    const bool top = k + 1 == side.faces.size();
    const double upper_y = top ? y : side.corners[k + 1].point.y;
    if (y <= upper_y || top) return s + (f.sin_a > 0.0 ? (y - lower.y) / f.sin_a : 0.0);
    const Vec2 upper = side.corners[k + 1].point;
    s += std::hypot(upper.x - lower.x, upper.y - lower.y);
  }
  return s;
}

}  // namespace

Wear Wear::make(const Funnel& f, int bins) {
  Wear w;
  w.bins = bins;
  if (bins <= 0) return w;
  for (int i = 0; i < 2; ++i) w.widths[i] = surface_length_to(f.sides[i], f.y_release) / bins;
  for (WallWear& ww : w.walls) {
    ww.collisions.assign(static_cast<std::size_t>(bins), 0.0);
    ww.normal_impulse.assign(static_cast<std::size_t>(bins), 0.0);
    ww.impulse.assign(static_cast<std::size_t>(bins), 0.0);
  }
  return w;
}

namespace {

std::size_t bin_of(const Wear& w, double width, double s) {
  const double k = std::floor(s / width);
  if (!(k > 0.0)) return 0;
  return static_cast<std::size_t>(std::min(k, static_cast<double>(w.bins - 1)));
}

}  // namespace

void Wear::add_collision(Wall wall, double s, double j_n, double j) {
  if (bins <= 0) return;
  WallWear& ww = (*this)[wall];
  const std::size_t k = bin_of(*this, widths[wall == Wall::Left ? 0 : 1], s);
  ww.collisions[k] += 1.0;
  ww.normal_impulse[k] += j_n;
  ww.impulse[k] += j;
}

void Wear::add_edge(Wall wall, double j_n, double j, bool count) {
  if (bins <= 0) return;
  WallWear& ww = (*this)[wall];
  if (count) ww.edge_collisions += 1.0;
  ww.edge_normal_impulse += j_n;
  ww.edge_impulse += j;
}

void Wear::add_face_phase(Wall wall, const FacePhase& ph, double cos_theta, double offset) {
  if (bins <= 0 || !(ph.duration > 0.0)) return;
  WallWear& ww = (*this)[wall];
  const double bin_width = width(wall);
  const double total = std::hypot(cos_theta, ph.force);
  // Distance up the face: s(t) = start - speed t - accel t^2 / 2. Split at its turning point
  // (if any) into monotone pieces; in each, the time between crossings of the bin boundaries.
  auto s_at = [&](double t) { return offset + ph.start - (ph.speed * t + 0.5 * ph.accel * t * t); };
  double cuts[3] = {0.0, ph.duration, ph.duration};
  int n_cuts = 2;
  if (ph.accel != 0.0) {
    const double t_turn = -ph.speed / ph.accel;
    if (t_turn > 0.0 && t_turn < ph.duration) {
      cuts[1] = t_turn;
      n_cuts = 3;
    }
  }
  for (int piece = 0; piece + 1 < n_cuts; ++piece) {
    double t0 = cuts[piece];
    const double t1 = cuts[piece + 1];
    const double s1 = s_at(t1);
    std::size_t k = bin_of(*this, bin_width, s_at(t0));
    const std::size_t k_end = bin_of(*this, bin_width, s1);
    // Walk bin by bin from k towards k_end; the boundary between is crossed where s(t) = b.
    while (k != k_end) {
      const bool up = k_end > k;
      const double boundary = (up ? static_cast<double>(k + 1) : static_cast<double>(k)) * bin_width;
      // s is monotone on the piece: bisect for s(t) = boundary to the last bit.
      double lo = t0, hi = t1;
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi)) break;
        ((s_at(mid) < boundary) == up ? lo : hi) = mid;
      }
      const double t = hi;
      ww.normal_impulse[k] += cos_theta * (t - t0);
      ww.impulse[k] += total * (t - t0);
      t0 = t;
      k = up ? k + 1 : k - 1;
    }
    ww.normal_impulse[k] += cos_theta * (t1 - t0);
    ww.impulse[k] += total * (t1 - t0);
  }
}

void Wear::merge(const Wear& o, bool mirror) {
  if (o.bins <= 0) return;
  if (bins <= 0) {
    *this = mirror ? o.mirrored() : o;
    return;
  }
  for (int w = 0; w < 2; ++w) {
    WallWear& a = walls[w];
    const WallWear& b = o.walls[mirror ? 1 - w : w];
    for (std::size_t k = 0; k < a.collisions.size(); ++k) {
      a.collisions[k] += b.collisions[k];
      a.normal_impulse[k] += b.normal_impulse[k];
      a.impulse[k] += b.impulse[k];
    }
    a.edge_collisions += b.edge_collisions;
    a.edge_normal_impulse += b.edge_normal_impulse;
    a.edge_impulse += b.edge_impulse;
  }
}

void Wear::clear() {
  for (WallWear& a : walls) {
    for (auto* v : {&a.collisions, &a.normal_impulse, &a.impulse}) std::fill(v->begin(), v->end(), 0.0);
    a.edge_collisions = a.edge_normal_impulse = a.edge_impulse = 0.0;
  }
}

void Wear::scale(double f) {
  for (WallWear& a : walls) {
    for (auto* v : {&a.collisions, &a.normal_impulse, &a.impulse}) {
      for (double& x : *v) x *= f;
    }
    a.edge_collisions *= f;
    a.edge_normal_impulse *= f;
    a.edge_impulse *= f;
  }
}

Wear Wear::mirrored() const {
  Wear m = *this;
  std::swap(m.walls[0], m.walls[1]);
  std::swap(m.widths[0], m.widths[1]);
  return m;
}

}  // namespace funnel
