// Summary statistics that merge in a fixed order, so parallel results are bit-identical.
#pragma once

#include <cstdint>

namespace funnel {

/// Running mean and variance (Welford), with min and max.
struct Accumulator {
  std::int64_t n = 0;  ///< number of values
  double mean = 0.0;   ///< running mean
  double m2 = 0.0;     ///< sum of squared deviations from the mean
  double min = 0.0;    ///< smallest value (0 when empty)
  double max = 0.0;    ///< largest value (0 when empty)

  /// Adds one value.
  void add(double x);
  /// Merges another accumulator (Chan et al.); the result depends on the order of merges.
  void merge(const Accumulator& other);
};

/// Mean, sample standard deviation, standard error of the mean, min and max.
struct Summary {
  double mean = 0.0;
  double std = 0.0;  ///< sample standard deviation (N - 1 in the denominator; 0 for N = 1)
  double sem = 0.0;  ///< std / sqrt(N)
  double min = 0.0;
  double max = 0.0;
};

/// The summary of an accumulator.
Summary summarize(const Accumulator& acc);

}  // namespace funnel
