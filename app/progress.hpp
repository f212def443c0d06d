// A progress bar on standard error, drawn only when it is a terminal.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace funnel::cli {

/// Draws "label [#####.....]  45%  eta 12 s" at most ten times a second.
class ProgressBar {
 public:
  /// `force` draws even when stderr is not a terminal (for tests); otherwise only on a tty.
  explicit ProgressBar(std::string label, bool force = false);
  ~ProgressBar();
  /// Reports `done` of `total` work units.
  void update(std::int64_t done, std::int64_t total);

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace funnel::cli
