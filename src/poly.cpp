// Root isolation for polynomials up to degree 8 (event times in the 3D funnel).
#include "funnel/poly.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace funnel {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

/// Degree after dropping zero leading coefficients.
int true_degree(const Poly& p) {
  int n = p.degree;
  while (n > 0 && p.c[static_cast<std::size_t>(n)] == 0.0) --n;
  return n;
}

/// Root of p on [lo, hi] where p is monotone with sign(p(lo)) = s_lo != sign(p(hi)): safeguarded
/// regula falsi (every third step a bisection) down to adjacent doubles. Returns the end on the
/// side of hi's sign (the first double at which the sign has changed).
double refine(const Poly& p, double lo, double hi, double f_lo, double f_hi) {
  const bool lo_positive = f_lo > 0.0;
  for (int it = 0; it < 400; ++it) {
    double mid = lo + (hi - lo) * (f_lo / (f_lo - f_hi));
    if (!(mid > lo && mid < hi) || it % 3 == 2) mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const double fm = p(mid);
    if ((fm > 0.0) == lo_positive && fm != 0.0) {
      lo = mid;
      f_lo = fm;
    } else {
      hi = mid;
      f_hi = fm;
      if (fm == 0.0) break;
    }
  }
  return hi;
}

/// Sign of p just after t = 0 when p(0) = 0: that of the lowest nonzero coefficient.
double sign_after_zero(const Poly& p) {
  for (int k = 1; k <= p.degree; ++k) {
    const double ck = p.c[static_cast<std::size_t>(k)];
    if (ck != 0.0) return ck > 0.0 ? 1.0 : -1.0;
  }
  return 0.0;
}

/// The knots that split [lo, hi] into pieces where p is monotone: lo, the roots of p' inside, hi.
int monotone_knots(const Poly& p, double lo, double hi, std::array<double, 9>& knots) {
  int m = 0;
  knots[static_cast<std::size_t>(m++)] = lo;
  if (true_degree(p) >= 2) {
    std::array<double, 8> crit{};
    const int n = real_roots(p.derivative(), lo, hi, crit);
    for (int k = 0; k < n; ++k) {
      if (crit[static_cast<std::size_t>(k)] > lo && crit[static_cast<std::size_t>(k)] < hi) {
        knots[static_cast<std::size_t>(m++)] = crit[static_cast<std::size_t>(k)];
      }
    }
  }
  knots[static_cast<std::size_t>(m++)] = hi;
  return m;
}

}  // namespace

double Poly::operator()(double t) const {
  double v = c[static_cast<std::size_t>(degree)];
  for (int k = degree - 1; k >= 0; --k) v = v * t + c[static_cast<std::size_t>(k)];
  return v;
}

Poly Poly::derivative() const {
  Poly d;
  d.degree = std::max(degree - 1, 0);
  for (int k = 1; k <= degree; ++k) d.c[static_cast<std::size_t>(k - 1)] = k * c[static_cast<std::size_t>(k)];
  return d;
}

Poly Poly::operator*(const Poly& o) const {
  Poly r;
  r.degree = std::min(degree + o.degree, 8);
  for (int i = 0; i <= degree; ++i) {
    for (int j = 0; j <= o.degree && i + j <= 8; ++j) {
      r.c[static_cast<std::size_t>(i + j)] += c[static_cast<std::size_t>(i)] * o.c[static_cast<std::size_t>(j)];
    }
  }
  return r;
}

int real_roots(const Poly& p, double lo, double hi, std::array<double, 8>& roots) {
  const int n = true_degree(p);
  int count = 0;
  auto push = [&](double t) {
    if (count > 0 && roots[static_cast<std::size_t>(count - 1)] >= t) return;  // a root at a shared knot
    if (count < 8) roots[static_cast<std::size_t>(count++)] = t;
  };
  if (n == 0 || !(lo <= hi)) return 0;
  if (n == 1) {
    const double t = -p.c[0] / p.c[1];
    if (t >= lo && t <= hi) push(t);
    return count;
  }
  std::array<double, 9> knots{};
  const int m = monotone_knots(p, lo, hi, knots);
  double f_prev = p(knots[0]);
  if (f_prev == 0.0) push(knots[0]);
  for (int k = 1; k < m; ++k) {
    const double a = knots[static_cast<std::size_t>(k - 1)], b = knots[static_cast<std::size_t>(k)];
    const double f_next = p(b);
    if (f_next == 0.0) {
      push(b);
    } else if (f_prev != 0.0 && (f_prev > 0.0) != (f_next > 0.0)) {
      push(refine(p, a, b, f_prev, f_next));
    }
    f_prev = f_next;
  }
  return count;
}

double first_descending_root(const Poly& p, double t_end) {
  if (!(t_end > 0.0)) return inf;
  std::array<double, 9> knots{};
  const int m = monotone_knots(p, 0.0, t_end, knots);
  double f_prev = p.c[0];
  if (f_prev == 0.0) f_prev = sign_after_zero(p) * std::numeric_limits<double>::min();
  for (int k = 1; k < m; ++k) {
    const double f_next = p(knots[static_cast<std::size_t>(k)]);
    if (f_prev > 0.0 && f_next <= 0.0) {
      if (f_next == 0.0) return knots[static_cast<std::size_t>(k)];
      return refine(p, knots[static_cast<std::size_t>(k - 1)], knots[static_cast<std::size_t>(k)], f_prev, f_next);
    }
    f_prev = f_next;
  }
  return inf;
}

}  // namespace funnel
