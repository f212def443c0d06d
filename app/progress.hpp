// Progress on standard error: a bar on a terminal, a one-line summary per stage in a log.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace funnel::cli {

/// Draws "label [#####.....]  45%  3 s elapsed, eta 4 s" at most ten times a second when standard
/// error is a terminal. When it is not (a log file, a pipe), draws nothing, and with `summary`
/// prints one line "label: <what> in 12.3 s" when the stage ends. The environment variable
/// FUNNEL_PROGRESS=always draws the bar even when standard error is not a terminal; =never
/// disables both the bar and the summary.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool summary = false);
  /// Ends the stage as finish() does, unless an exception is unwinding (then only ends the line).
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// Reports `done` of `total` work units (any unit; only the fraction is shown).
  void update(std::int64_t done, std::int64_t total);
  /// Ends the stage: ends the bar's line, or prints the summary line "label: <what> in X s".
  void finish(const std::string& what = "done");

 private:
  std::string label_;
  bool bar_;      ///< draw the bar
  bool summary_;  ///< print the summary line at the end
  bool drawn_ = false;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace funnel::cli
