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

/// C(j, k) / C(n, k) for n = degree, 0 <= k <= j <= n <= 8: the weights of the power basis's
/// scaled coefficients in the Bernstein coefficients, b_j = sum_k w[n][j][k] c_k hi^k.
constexpr std::array<std::array<std::array<double, 9>, 9>, 9> bernstein_weights() {
  std::array<std::array<double, 9>, 9> choose{};
  for (std::size_t n = 0; n < 9; ++n) {
    choose[n][0] = 1.0;
    for (std::size_t k = 1; k <= n; ++k) choose[n][k] = choose[n - 1][k - 1] + (k < n ? choose[n - 1][k] : 0.0);
  }
  std::array<std::array<std::array<double, 9>, 9>, 9> w{};
  for (std::size_t n = 0; n < 9; ++n) {
    for (std::size_t j = 0; j <= n; ++j) {
      for (std::size_t k = 0; k <= j; ++k) w[n][j][k] = choose[j][k] / choose[n][k];
    }
  }
  return w;
}

constexpr auto weights = bernstein_weights();

}  // namespace

namespace detail {

bool one_sign_from_zero(const Poly& p, double hi) {
  // With d_k = c_k hi^k and A = sum_k |d_k|, for t in [0, hi]:
  // - Horner's value (Poly::operator()) is within gamma_16 A of p(t) (degree <= 8, t >= 0);
  // - p(t) = sum_j b_j B_j(t / hi) with Bernstein polynomials B_j >= 0 that sum to 1, so p(t)
  //   lies between the least and the greatest b_j;
  // - each computed b_j (d_k's rounding, the weight's, the sum's) is within 19 u A of b_j.
  // So b_j > 64 u A for every j gives fl(p(t)) > (64 - 19 - 17) u A > 0 at every double t in
  // [0, hi], and b_j < -64 u A for every j the opposite sign. The bounds on hi and A keep
  // underflow's absolute errors (2^-1074 per operation) far below that margin, and the bound on
  // the coefficients overflow out of Horner's partial sums.
  if (!(hi > 0.0 && hi <= 0x1p64) || p.degree < 0 || p.degree > 8) return false;
  const auto n = static_cast<std::size_t>(p.degree);
  std::array<double, 9> d{};
  double a_sum = 0.0, hk = 1.0;
  for (std::size_t k = 0; k <= n; ++k) {
    if (!(std::fabs(p.c[k]) <= 0x1p1000)) return false;  // no overflow in Horner's partial sums
    d[k] = p.c[k] * hk;
    a_sum += std::fabs(d[k]);
    hk *= hi;
  }
  if (!(a_sum >= 0x1p-800 && a_sum <= 0x1p800)) return false;
  const double margin = 64.0 * 0x1p-53 * a_sum;
  const auto& w = weights[n];
  const bool positive = d[0] > 0.0;
  for (std::size_t j = 0; j <= n; ++j) {
    double b = 0.0;
    for (std::size_t k = 0; k <= j; ++k) b += w[j][k] * d[k];
    if (positive ? !(b > margin) : !(b < -margin)) return false;
  }
  return true;
}

}  // namespace detail

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

namespace {

template <bool Certify>
int real_roots_impl(const Poly& p, double lo, double hi, std::array<double, 8>& roots);

/// The knots that split [lo, hi] into pieces where p is monotone: lo, the roots of p' inside, hi.
/// From lo = 0, a derivative whose Horner value has one sign all over [0, hi] (proved by
/// detail::one_sign_from_zero) has no root for real_roots to find: with Certify its search, down
/// the chain of derivatives, is skipped (the same knots, so the same bits).
template <bool Certify>
int monotone_knots(const Poly& p, double lo, double hi, std::array<double, 9>& knots) {
  int m = 0;
  knots[static_cast<std::size_t>(m++)] = lo;
  if (true_degree(p) >= 2) {
    const Poly dp = p.derivative();
    if (!(Certify && lo == 0.0 && detail::one_sign_from_zero(dp, hi))) {
      std::array<double, 8> crit{};
      const int n = real_roots_impl<Certify>(dp, lo, hi, crit);
      for (int k = 0; k < n; ++k) {
        if (crit[static_cast<std::size_t>(k)] > lo && crit[static_cast<std::size_t>(k)] < hi) {
          knots[static_cast<std::size_t>(m++)] = crit[static_cast<std::size_t>(k)];
        }
      }
    }
  }
  knots[static_cast<std::size_t>(m++)] = hi;
  return m;
}

template <bool Certify>
int real_roots_impl(const Poly& p, double lo, double hi, std::array<double, 8>& roots) {
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
  const int m = monotone_knots<Certify>(p, lo, hi, knots);
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

template <bool Certify>
double first_descending_root_impl(const Poly& p, double t_end) {
  if (!(t_end > 0.0)) return inf;
  std::array<double, 9> knots{};
  const int m = monotone_knots<Certify>(p, 0.0, t_end, knots);
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

}  // namespace

int real_roots(const Poly& p, double lo, double hi, std::array<double, 8>& roots) {
  return real_roots_impl<true>(p, lo, hi, roots);
}

double first_descending_root(const Poly& p, double t_end) { return first_descending_root_impl<true>(p, t_end); }

namespace detail {

int real_roots_reference(const Poly& p, double lo, double hi, std::array<double, 8>& roots) {
  return real_roots_impl<false>(p, lo, hi, roots);
}

double first_descending_root_reference(const Poly& p, double t_end) { return first_descending_root_impl<false>(p, t_end); }

}  // namespace detail

}  // namespace funnel
