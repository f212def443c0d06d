// Root finders for event times: quadratics in closed form, the edge quartic by monotone pieces.
#include "funnel/roots.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace funnel {

double line_arrival_time(double delta0, double p, double c) {
  // On the line: exactly 2p/c (docs/model.md §3). The general form gives the same bits, since
  // sqrt(fl(p*p)) = |p| in binary floating point, but costs a square root.
  if (delta0 == 0.0) return p >= 0.0 ? 2.0 * p / c : 0.0;
  if (delta0 > 0.0) {
    const double s = std::sqrt(p * p + 2.0 * delta0 * c);
    // Both forms avoid subtracting nearly equal numbers (docs/model.md §3).
    return p >= 0.0 ? (p + s) / c : 2.0 * delta0 / (s - p);
  }
  // Behind the line (possible only below a wall's end): it is crossed back inward first,
  // then outward at the larger root, which needs p > 0.
  const double disc = p * p + 2.0 * delta0 * c;
  if (p <= 0.0 || disc < 0.0) return never;
  return (p + std::sqrt(disc)) / c;
}

double first_positive_root(double a2, double a1, double a0) {
  if (a2 == 0.0) {
    if (a1 == 0.0) return never;
    const double t = -a0 / a1;
    return t > 0.0 ? t : never;
  }
  const double disc = a1 * a1 - 4.0 * a2 * a0;
  if (disc < 0.0) return never;
  // q has the sign of a1 so that no cancellation occurs; the roots are q/a2 and a0/q.
  // a1 = -0 is taken as +0 (not copysign): a mirror-image input, such as the speed along the
  // right face of a particle at rest (0 * -cos = -0), must give the same bits as the left's
  // (found by fuzz/fuzz_physics: a mirror release slid for a different last bit of time).
  const double root = std::sqrt(disc);
  const double q = -0.5 * (a1 + (a1 < 0.0 ? -root : root));
  double r1 = q / a2;
  double r2 = q != 0.0 ? a0 / q : r1;
  if (r1 > r2) std::swap(r1, r2);
  if (r1 > 0.0) return r1;
  if (r2 > 0.0) return r2;
  return never;
}

int cubic_real_roots(double b, double c, double d, std::array<double, 3>& roots) {
  // Depressed cubic y^3 + P y + Q with t = y - b/3.
  const double shift = b / 3.0;
  const double P = c - b * shift;
  const double Q = d - c * shift + 2.0 * shift * shift * shift;
  int count = 0;
  const double disc = (Q * Q) / 4.0 + (P * P * P) / 27.0;
  if (P < 0.0 && disc <= 0.0) {
    // Three real roots: trigonometric form.
    const double m = 2.0 * std::sqrt(-P / 3.0);
    const double arg = std::clamp(3.0 * Q / (P * m), -1.0, 1.0);
    const double phi = std::acos(arg) / 3.0;
    for (int k = 0; k < 3; ++k) {
      roots[k] = m * std::cos(phi - 2.0 * std::numbers::pi * k / 3.0) - shift;
    }
    count = 3;
  } else {
    const double sq = std::sqrt(std::max(disc, 0.0));
    const double u = std::cbrt(-Q / 2.0 + (Q <= 0.0 ? sq : -sq));
    const double y = u != 0.0 ? u - P / (3.0 * u) : 0.0;
    roots[0] = y - shift;
    count = 1;
  }
  // Polish each root with two Newton steps: the closed forms lose digits near double roots.
  for (int k = 0; k < count; ++k) {
    for (int it = 0; it < 2; ++it) {
      const double t = roots[k];
      const double f = ((t + b) * t + c) * t + d;
      const double df = (3.0 * t + 2.0 * b) * t + c;
      if (df == 0.0) break;
      const double next = t - f / df;
      if (!std::isfinite(next)) break;
      roots[k] = next;
    }
  }
  std::sort(roots.begin(), roots.begin() + count);
  return count;
}

double eval_quartic(const std::array<double, 5>& c, double t) {
  return (((c[4] * t + c[3]) * t + c[2]) * t + c[1]) * t + c[0];
}

namespace {

/// Root of a decreasing function on [lo, hi] with f(lo) > 0 >= f(hi): bisection to the last bit,
/// accelerated by secant steps that stay inside the bracket.
double refine_descending(const std::array<double, 5>& c, double lo, double hi, double flo, double fhi) {
  for (int it = 0; it < 200; ++it) {
    double mid = lo + (hi - lo) * (flo / (flo - fhi));  // regula falsi guess
    if (!(mid > lo && mid < hi) || it % 3 == 2) mid = 0.5 * (lo + hi);  // guarantee shrinking
    if (mid <= lo || mid >= hi) break;  // adjacent doubles: converged
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

}  // namespace

double first_descending_root(const std::array<double, 5>& c, double t_end) {
  // Critical points of f: roots of f'(t) = 4 c4 t^3 + 3 c3 t^2 + 2 c2 t + c1.
  const double lead = 4.0 * c[4];
  std::array<double, 3> crit{};
  const int n = cubic_real_roots(3.0 * c[3] / lead, 2.0 * c[2] / lead, c[1] / lead, crit);
  std::array<double, 5> knots{};
  int m = 0;
  knots[m++] = 0.0;
  for (int k = 0; k < n; ++k) {
    if (crit[k] > 0.0 && crit[k] < t_end) knots[m++] = crit[k];
  }
  knots[m++] = t_end;
  double f_prev = c[0];
  for (int k = 1; k < m; ++k) {
    const double f_next = eval_quartic(c, knots[k]);
    if (f_prev > 0.0 && f_next <= 0.0) return refine_descending(c, knots[k - 1], knots[k], f_prev, f_next);
    f_prev = f_next;
  }
  return never;
}

}  // namespace funnel
