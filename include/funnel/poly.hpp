// Real roots of polynomials up to degree 8 on an interval, isolated between the roots of the
// derivative (recursively) and refined to the last bit: no root is skipped, grazing ones included.
#pragma once

#include <array>

namespace funnel {

/// A real polynomial c[0] + c[1] t + ... + c[degree] t^degree of degree at most 8.
struct Poly {
  std::array<double, 9> c{};  ///< coefficients, lowest order first
  int degree = 0;             ///< index of the highest coefficient used (0..8)

  /// Value at t (Horner).
  double operator()(double t) const;
  /// The derivative.
  Poly derivative() const;
  /// The product with another polynomial (the degrees must add up to at most 8).
  Poly operator*(const Poly& other) const;
};

/// Every real root of p in [lo, hi], ascending, each refined to adjacent doubles; returns the
/// count. A root of even multiplicity is found where p touches 0 at a critical point (its value
/// there is <= 0 for p >= 0 around it, or >= 0 for p <= 0).
int real_roots(const Poly& p, double lo, double hi, std::array<double, 8>& roots);

/// First t in (0, t_end] where p crosses (or touches) from p > 0 to p <= 0: the first approach
/// of a surface whose inside is p <= 0. When p(0) = 0 exactly the sign just after 0 is that of the
/// lowest nonzero coefficient. Returns +infinity if there is none.
double first_descending_root(const Poly& p, double t_end);

}  // namespace funnel
