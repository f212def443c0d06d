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

namespace detail {

/// True when Horner's value of p (Poly::operator()) is nonzero and of one sign at every double
/// t in [0, hi], proved from p's Bernstein coefficients on [0, hi] with a margin for every
/// rounding; false when that cannot be shown (it may still be so).
bool one_sign_from_zero(const Poly& p, double hi);

/// real_roots and first_descending_root without the shortcut of one_sign_from_zero: the whole
/// chain of derivatives searched. The same bits (tests/test_poly.cpp compares them).
int real_roots_reference(const Poly& p, double lo, double hi, std::array<double, 8>& roots);
double first_descending_root_reference(const Poly& p, double t_end);

}  // namespace detail

}  // namespace funnel
