// Welford accumulation and Chan's pairwise merge.
#include "funnel/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace funnel {

void Accumulator::add(double x) {
  ++n;
  if (n == 1) {
    mean = x;
    m2 = 0.0;
    min = max = x;
    return;
  }
  const double delta = x - mean;
  mean += delta / static_cast<double>(n);
  m2 += delta * (x - mean);
  min = std::min(min, x);
  max = std::max(max, x);
}

void Accumulator::merge(const Accumulator& other) {
  if (other.n == 0) return;
  if (n == 0) {
    *this = other;
    return;
  }
  const double na = static_cast<double>(n);
  const double nb = static_cast<double>(other.n);
  const double total = na + nb;
  const double delta = other.mean - mean;
  mean += delta * (nb / total);
  m2 += other.m2 + delta * delta * (na * nb / total);
  n += other.n;
  min = std::min(min, other.min);
  max = std::max(max, other.max);
}

Summary summarize(const Accumulator& acc) {
  Summary s;
  if (acc.n == 0) return s;
  s.mean = acc.mean;
  // One sample has no spread to estimate (n - 1 = 0): undefined, not 0, which read as no error.
  s.std = acc.n > 1 ? std::sqrt(acc.m2 / static_cast<double>(acc.n - 1)) : std::numeric_limits<double>::quiet_NaN();
  s.sem = s.std / std::sqrt(static_cast<double>(acc.n));
  s.min = acc.min;
  s.max = acc.max;
  return s;
}

}  // namespace funnel
