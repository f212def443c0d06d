// The edge quartic's root as first written, and the quartic of an edge approach (test, fuzz and
// benchmark support, not the library).
#pragma once

#include <array>

#include "funnel/roots.hpp"

namespace funnel::test {

/// |d + v t - (0, t^2/2)|^2 - a^2 as a quartic in t: a centre at d = (dx, dy) from an edge point,
/// moving at v = (vx, vy) under gravity, approaching the circle of radius a (src/flight.cpp's
/// edge_time, for a flight that does not start on the circle).
inline std::array<double, 5> edge_approach_quartic(double dx, double dy, double vx, double vy, double a) {
  return {dx * dx + dy * dy - a * a, 2 * (dx * vx + dy * vy), vx * vx + vy * vy - dy, -vy, 0.25};
}

/// Regula falsi with a bisection every third step, until lo and hi are adjacent doubles: the
/// loop that defines an edge-collision time's last bit. detail::refine_reference must return
/// its bits (it evaluates ahead, the same operations on the same values).
inline double plain_refinement(const std::array<double, 5>& c, double lo, double hi, double flo, double fhi) {
  for (int it = 0; it < 200; ++it) {
    double mid = lo + (hi - lo) * (flo / (flo - fhi));
    if (!(mid > lo && mid < hi) || it % 3 == 2) mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const double fm = eval_quartic(c, mid);
    if (fm > 0.0) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
      fhi = fm;
    }
  }
  return hi;
}

}  // namespace funnel::test
