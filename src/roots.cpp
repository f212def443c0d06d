// Root finders for event times: quadratics in closed form, the edge quartic by monotone pieces.
#include "funnel/roots.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstddef>
#include <limits>
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

namespace detail {

double refine_reference(const std::array<double, 5>& c, double lo, double hi, double flo, double fhi) {
  // The loop is: a regula falsi guess (bisection when it falls outside, and at every third step),
  // stop when lo and hi are adjacent, keep the side by the sign of f there. Written out one step
  // at a time it is a chain of dependent evaluations; here the bisection that follows a regula
  // falsi step (it % 3 == 1) is evaluated at both of its possible midpoints while that step's
  // own value is computed, and the one the sign selects is used: the same operations on the same
  // values, a third fewer evaluations waiting on each other (tests/test_roots.cpp compares with
  // the plain loop).
  bool have_next = false;
  double f_next = 0.0;
  for (int it = 0; it < 200; ++it) {
    double mid = lo + (hi - lo) * (flo / (flo - fhi));  // regula falsi guess
    if (!(mid > lo && mid < hi) || it % 3 == 2) mid = 0.5 * (lo + hi);  // guarantee shrinking
    if (mid <= lo || mid >= hi) break;  // adjacent doubles: converged
    double fm;
    if (have_next) {
      fm = f_next;  // evaluated at this very mid, 0.5 * (lo + hi), in the step before
      have_next = false;
    } else if (it % 3 == 1) {
      const double mid_up = 0.5 * (mid + hi), mid_down = 0.5 * (lo + mid);
      fm = eval_quartic(c, mid);
      const double f_up = eval_quartic(c, mid_up), f_down = eval_quartic(c, mid_down);
      f_next = fm > 0.0 ? f_up : f_down;
      have_next = true;
    } else {
      fm = eval_quartic(c, mid);
    }
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

}  // namespace detail

namespace {

// ---------------------------------------------------------------------------------------------
// The certified refinement (docs/performance.md, "The edge quartic's root").
//
// refine_reference keeps lo with fl(f(lo)) > 0 and hi with fl(f(hi)) <= 0 (fl: eval_quartic's
// rounded value) and stops when they are adjacent doubles, returning hi. So it returns a
// "switch": a double r with fl(f(prev r)) > 0 >= fl(f(r)). Which switch it finds depends on its
// path when rounding makes the sign of fl(f) flicker near the root; when there is exactly one
// switch in (lo, hi] it can only return that one. refine_certified finds a switch by Newton's
// method and then proves it is the only one:
//  - near r, f is strictly decreasing (a bound on f'' around r), and the doubles next to r are
//    evaluated one by one until |fl(f)| exceeds twice a bound E_near on its rounding there,
//    beyond which the sign of fl(f) is that of f;
//  - on the rest of the bracket, the Bernstein coefficients of f (with a bound on their own
//    rounding) show f > E on the left and f < -E on the right (E: Horner's error bound over the
//    bracket).
// It also checks that the reference converges (reaches adjacent doubles within its 200
// iterations). Whenever a step of the proof fails it returns NaN and the reference runs.

constexpr double unit_roundoff = 0x1p-53;
/// gamma_8 = 8u / (1 - 8u): the relative error bound of eight roundings (Horner at degree 4).
constexpr double gamma8 = 8.0 * unit_roundoff / (1.0 - 8.0 * unit_roundoff);

/// Below the normal range a rounding is off by up to half the smallest subnormal (2^-1075), in
/// absolute terms, not by u relatively. The bounds below add a term for that: at most 16 such
/// roundings, each carried through factors of at most 1 + b (b >= every t, a and w involved),
/// for each quantity, which 2^-1071 (1 + b)^4 covers; 2^-1000 is used instead, as arithmetic on
/// subnormal numbers is slow (a 40% slower proof when this was 2^-1070) and the term is far
/// below anything at the engine's scales either way. It keeps the proof sound near underflow
/// (found in review: with terms of f near 2^-1022, fl(f) steps by whole subnormals).
double underflow_allowance(double b) {
  const double g = 1.0 + b;
  return 0x1p-1000 * (g * g) * (g * g);
}

/// sum |c_i| t^i for t >= 0: the size of f's terms, which Horner's rounding is relative to.
double abs_terms(const std::array<double, 5>& c, double t) {
  return (((std::fabs(c[4]) * t + std::fabs(c[3])) * t + std::fabs(c[2])) * t + std::fabs(c[1])) * t + std::fabs(c[0]);
}

/// Bound on |fl(f(t)) - f(t)| for every double t in [0, h]: Horner's gamma_8 sum |c_i| t^i
/// (degree 4, no fused multiply-add), doubled to cover the rounding of the bound itself.
double horner_error(const std::array<double, 5>& c, double h) {
  return 2.0 * gamma8 * abs_terms(c, h) + underflow_allowance(h);
}

/// True when f > bound on all of [a, a + w] (sign > 0), or f < -bound there (sign < 0), shown by
/// the Bernstein coefficients of f on the interval (f is a convex combination of them). Each
/// coefficient is a sum of products of the inputs with at most 13 roundings on any path, so its
/// error is below gamma_13 times the same computation on absolute values; 8e-15 bounds that
/// generously (gamma_13 = 1.4e-15). Requires a >= 0, w > 0.
bool bernstein_bound(const std::array<double, 5>& c, double a, double w, double bound, int sign) {
  std::array<double, 5> d = c, da{};
  for (std::size_t i = 0; i < 5; ++i) da[i] = std::fabs(c[i]);
  // Taylor shift to a: d_k = sum_i C(i, k) c_i a^(i - k), by repeated synthetic division
  // (nothing to do from a = 0, the usual left end of a bracket).
  if (a != 0.0) {
    for (std::size_t k = 0; k < 4; ++k) {
      for (std::size_t i = 4; i-- > k;) {
        d[i] += a * d[i + 1];
        da[i] += a * da[i + 1];
      }
    }
  }
  // Scaled to s = (t - a) / w in [0, 1], then 12 b_j = sum_k 12 C(j, k) / C(4, k) d_k w^k
  // (integer weights, so that only the products round).
  double wk = 1.0;
  for (std::size_t k = 1; k < 5; ++k) {
    wk *= w;
    d[k] *= wk;
    da[k] *= wk;
  }
  static constexpr double weight[5][5] = {
      {12, 0, 0, 0, 0}, {12, 3, 0, 0, 0}, {12, 6, 2, 0, 0}, {12, 9, 6, 3, 0}, {12, 12, 12, 12, 12}};
  const double limit = 12.0 * bound;
  for (std::size_t j = 0; j < 5; ++j) {
    double b = 0.0, b_abs = 0.0;
    for (std::size_t k = 0; k <= j; ++k) {
      b += weight[j][k] * d[k];
      b_abs += weight[j][k] * da[k];
    }
    const double err = 8e-15 * b_abs + 256.0 * underflow_allowance(a + w);
    if (sign > 0 ? !(b - err > limit) : !(b + err < -limit)) return false;
  }
  return true;
}

/// Bound on |fl(f(t)) - f(t)| for every double t with |t - r| <= rho and 0 <= t <= b. Horner's
/// computed partial sums y_k = fl(fl(y_(k+1) t) + c_k) give exactly
///   fl(f(t)) - f(t) = sum_k t^k (y_(k+1) t alpha_k + y_k beta_k / (1 + beta_k))
/// with |alpha_k|, |beta_k| <= u, so |error| <= u / (1 - u) sum_k b^k (|y_(k+1)| b + |y_k|)
/// (plus the underflow allowance).
/// Each |y_k| at t is bounded by its computed value at r, the rounding at r and at t (gamma_8
/// times the same sum on absolute values, each) and its largest change over the distance rho.
double near_error(const std::array<double, 5>& c, double r, double b, double rho) {
  std::array<double, 5> y{};  // |y_k| bounds
  double yk = c[4];           // computed partial sum at r
  double abs_k = std::fabs(c[4]), slope_k = 0.0;  // sum_i |c_i| b^(i-k) and its derivative in b
  y[4] = std::fabs(c[4]);
  for (std::size_t k = 4; k-- > 0;) {
    yk = yk * r + c[k];
    slope_k = slope_k * b + abs_k;
    abs_k = abs_k * b + std::fabs(c[k]);
    y[k] = std::fabs(yk) + 2.0 * gamma8 * abs_k + slope_k * rho;
  }
  double sum = 0.0, bk = 1.0;
  for (std::size_t k = 0; k < 4; ++k) {
    sum += bk * (y[k + 1] * b + y[k]);
    bk *= b;
  }
  return unit_roundoff * sum * (1.0 + 1e-9) + underflow_allowance(b);
}

/// The next double above / below a finite x > 0 (walk may form next_down(0), a NaN pattern, one
/// step past a bracket end of 0; it stops at the end before looking at it).
double next_up(double x) { return std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) + 1); }
double next_down(double x) { return std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) - 1); }

/// Step 4 of refine_certified on one side of the switch r (dir -1: the doubles below r, which
/// must give fl(f) > 0; dir +1: r and those above, fl(f) <= 0), up to the first whose sign is
/// certain (|fl(f)| > 2 E_near: f itself has that sign, and f is monotone up to `stop`) or the
/// bracket's end `end` (whose sign is given). False if a sign is wrong or the walk is too long.
bool walk(const std::array<double, 5>& c, double r, double end, double stop, double E_near, int dir) {
  const double certain = 2.0 * E_near;
  double t = dir < 0 ? next_down(r) : r;
  for (int block = 0; block < 16; ++block) {
    std::array<double, 4> ts{}, fs{};
    for (std::size_t i = 0; i < 4; ++i) {
      ts[i] = t;
      fs[i] = eval_quartic(c, t);
      t = dir < 0 ? next_down(t) : next_up(t);
    }
    for (std::size_t i = 0; i < 4; ++i) {
      if (dir < 0 ? ts[i] <= end : ts[i] >= end) return true;  // the bracket's end: its sign is given
      if (dir < 0 ? ts[i] < stop : ts[i] > stop) return false;  // beyond the monotone stretch
      if (dir < 0 ? !(fs[i] > 0.0) : !(fs[i] <= 0.0)) return false;
      if (dir < 0 ? fs[i] > certain : fs[i] < -certain) return true;
    }
  }
  return false;
}

double derivative(const std::array<double, 5>& c, double t) {
  return ((4.0 * c[4] * t + 3.0 * c[3]) * t + 2.0 * c[2]) * t + c[1];
}

}  // namespace

namespace detail {

double refine_certified(const std::array<double, 5>& c, double lo, double hi, double flo, double fhi) {
  constexpr double fail = std::numeric_limits<double>::quiet_NaN();
  lo += 0.0;  // -0 as +0: the steps below move between doubles by their bit patterns
  const double L = lo, H = hi;
  if (!(L >= 0.0 && H > L && std::isfinite(H) && flo > 0.0 && fhi <= 0.0 && std::isfinite(flo) && std::isfinite(fhi)))
    return fail;
  for (const double ci : c) {
    if (!std::isfinite(ci)) return fail;
  }
  // 1. A switch by Newton steps, kept inside the bracket of the signs of fl(f) (a step that
  // leaves it becomes an Illinois secant step on the bracket).
  double x = lo + (hi - lo) * (flo / (flo - fhi));
  if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
  // Where the rounding of fl(f) spans many doubles (|fl(f) - f| / |f'| estimated above 32 ulps
  // at the first guess), fl(f) mostly changes sign more than once near the root: the
  // reference's path decides the last bit, so it is left to run at once (the threshold that
  // measured fastest on the roots of Fig. 3's sweep: 16 and 64 were slower).
  if (!(unit_roundoff * abs_terms(c, x) < 32.0 * std::fabs(derivative(c, x)) * (next_up(x) - x))) return fail;
  int side = 0;  // the end kept by the last secant step (Illinois: halve its value)
  int it = 0;
  for (; it < 40; ++it) {
    const double fx = eval_quartic(c, x);
    const double dx = derivative(c, x);
    if (fx > 0.0) {
      lo = x;
      flo = fx;
      if (side == +1) fhi *= 0.5;
      side = +1;
    } else {
      hi = x;
      fhi = fx;
      if (side == -1) flo *= 0.5;
      side = -1;
    }
    if (next_up(lo) >= hi) break;
    // Within rounding of the root (|fl(f)| near its error bound): walk the doubles from here.
    if (std::fabs(fx) <= 8.0 * unit_roundoff * abs_terms(c, x)) break;
    double next = x - fx / dx;
    if (!(next > lo && next < hi)) {
      next = lo + (hi - lo) * (flo / (flo - fhi));
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    } else {
      side = 0;
    }
    // Within a few ulps: walk the doubles from there.
    const bool close = std::fabs(next - x) <= 4.0 * (next_up(x) - x);
    x = next;
    if (close) break;
  }
  if (it == 40) return fail;
  double r;
  if (next_up(lo) >= hi) {
    r = hi;
  } else {
    int steps = 0;
    r = x;
    if (eval_quartic(c, r) > 0.0) {
      do {
        r = next_up(r);
        if (++steps > 64 || r > H) return fail;
      } while (eval_quartic(c, r) > 0.0);
    } else {
      while (r > L && eval_quartic(c, next_down(r)) <= 0.0) {
        r = next_down(r);
        if (++steps > 64) return fail;
      }
      if (r <= L) return fail;
    }
  }
  // 2. The reference converges: every third of its 200 steps halves the bracket, and 66 halvings
  // from H - L <= 2^8 r leave it well within the spacing of the doubles near r (2^-53 r or more),
  // so it stops at adjacent doubles, not at its step limit.
  if (!(r >= 0x1p-1000 && H - L <= 0x1p8 * r)) return fail;
  // 3. Near r, on [a1, b1] = [r - rho, r + rho] within the bracket (rho = 2^-20 r): f is strictly
  // decreasing (f'(r) plus a bound on |f''| times the distance stays negative), and E_near bounds
  // the rounding of fl(f) there (Horner's error in terms of the partial sums, bounded near r).
  // Far tighter than E: the terms of f cancel near its root.
  const double rho = 0x1p-20 * r;
  const double a1 = std::fmax(L, r - rho), b1 = std::fmin(H, r + rho);
  const double reach = std::fmax(r - a1, b1 - r);  // exact (Sterbenz): the farthest t from r
  const double d1 = derivative(c, r);
  const double d1_err = 1e-14 * (((4.0 * std::fabs(c[4]) * r + 3.0 * std::fabs(c[3])) * r + 2.0 * std::fabs(c[2])) * r +
                                 std::fabs(c[1])) +
                        4.0 * underflow_allowance(b1);
  const double f2_max =
      ((12.0 * std::fabs(c[4]) * b1 + 6.0 * std::fabs(c[3])) * b1 + 2.0 * std::fabs(c[2])) * (1.0 + 1e-12) +
      16.0 * underflow_allowance(b1);
  if (!(d1 + d1_err + f2_max * reach * (1.0 + 1e-12) < 0.0)) return fail;
  const double E_near = near_error(c, r, b1, reach);
  const double E = horner_error(c, H);
  // 4. The doubles next to r, one by one (four at a time): positive below it, non-positive from
  // it, until the sign of fl(f) is certain (|fl(f)| > 2 E_near), or the bracket's end.
  if (!walk(c, r, L, a1, E_near, -1) || !walk(c, r, H, b1, E_near, +1)) return fail;
  // 5. The rest of the bracket: f > E on [L, a1] and f < -E on [b1, H] (then fl(f) has f's sign).
  if (a1 > L && !bernstein_bound(c, L, next_up(a1 - L), E, +1)) return fail;
  if (b1 < H && !bernstein_bound(c, b1, next_up(H - b1), E, -1)) return fail;
  return r;
}

}  // namespace detail

namespace {

double refine(const std::array<double, 5>& c, double lo, double hi, double flo, double fhi) {
  const double r = detail::refine_certified(c, lo, hi, flo, fhi);
  return r == r ? r : detail::refine_reference(c, lo, hi, flo, fhi);
}

}  // namespace

namespace detail {

std::optional<Bracket> descending_bracket(const std::array<double, 5>& c, double t_end) {
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
    if (f_prev > 0.0 && f_next <= 0.0) return Bracket{knots[k - 1], knots[k], f_prev, f_next};
    f_prev = f_next;
  }
  return std::nullopt;
}

}  // namespace detail

double first_descending_root(const std::array<double, 5>& c, double t_end) {
  const std::optional<detail::Bracket> b = detail::descending_bracket(c, t_end);
  return b ? refine(c, b->lo, b->hi, b->flo, b->fhi) : never;
}

}  // namespace funnel
