// Cancellation-free polynomial root finders used for event times (docs/model.md §3).
#pragma once

#include <array>
#include <limits>
#include <optional>

namespace funnel {

/// No root: an event that never happens.
inline constexpr double never = std::numeric_limits<double>::infinity();

/// Time at which a signed distance delta(t) = delta0 + p t - c t^2 / 2 (c > 0) next falls to 0
/// from above: the particle reaching a centre line. delta0 >= 0 uses the roots of docs/model.md §3
/// (exactly 2p/c when delta0 = 0); delta0 < 0 (behind the line) needs p > 0. `never` if none.
double line_arrival_time(double delta0, double p, double c);

/// Smallest positive root of a2 t^2 + a1 t + a0 = 0 (any signs), `never` if none.
double first_positive_root(double a2, double a1, double a0);

/// Real roots of the monic cubic t^3 + b t^2 + c t + d, ascending; returns their count (1..3).
int cubic_real_roots(double b, double c, double d, std::array<double, 3>& roots);

/// Value of the polynomial c[0] + c[1] t + ... + c[4] t^4.
double eval_quartic(const std::array<double, 5>& c, double t);

/// First t in (0, t_end] where the quartic f (leading coefficient > 0) crosses from f > 0 to
/// f <= 0: the first approach of a circle. The interval is split at the real roots of f' into
/// monotone pieces; the root is then bracketed and refined to full precision. `never` if none.
double first_descending_root(const std::array<double, 5>& c, double t_end);

namespace detail {

/// A bracket [lo, hi] of a root of the quartic f, with flo = fl(f(lo)) > 0 >= fhi = fl(f(hi)).
struct Bracket {
  double lo, hi, flo, fhi;
};

/// The bracket first_descending_root refines: between consecutive knots (0, the real roots of
/// f' inside (0, t_end), t_end), the first where fl(f) goes from > 0 to <= 0; none if no root.
std::optional<Bracket> descending_bracket(const std::array<double, 5>& c, double t_end);

/// The root of the quartic f in a bracket [lo, hi] with flo = fl(f(lo)) > 0 >= fhi = fl(f(hi))
/// (fl: eval_quartic's rounded values), to the last bit: regula falsi and bisection until lo and
/// hi are adjacent doubles; returns hi. This defines the root's last bit.
double refine_reference(const std::array<double, 5>& c, double lo, double hi, double flo, double fhi);

/// refine_reference's result found by Newton's method and proved to be the only double it can
/// return (docs/performance.md); NaN when the proof does not go through. first_descending_root
/// uses it, and refine_reference when it gives NaN.
double refine_certified(const std::array<double, 5>& c, double lo, double hi, double flo, double fhi);

}  // namespace detail

}  // namespace funnel
