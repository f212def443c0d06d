// Terminal progress bar and per-stage summaries.
#include "progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>

namespace funnel::cli {

namespace {

enum class Mode { Auto, Always, Never };

Mode mode_from_environment() {
  const char* env = std::getenv("FUNNEL_PROGRESS");
  if (env == nullptr) return Mode::Auto;
  const std::string v = env;
  if (v == "always") return Mode::Always;
  if (v == "never") return Mode::Never;
  // A misspelt value ("nevr") would silently draw the bar or not: said once per process.
  static bool said = false;
  if (!said && !v.empty() && v != "auto") {
    said = true;
    std::fprintf(stderr, "funnel: warning: FUNNEL_PROGRESS = '%s' is not always, never or auto; using auto\n", v.c_str());
  }
  return Mode::Auto;
}

}  // namespace

ProgressBar::ProgressBar(std::string label, bool summary)
    : label_(std::move(label)), start_(std::chrono::steady_clock::now()), last_(start_) {
  const Mode mode = mode_from_environment();
  const bool tty = isatty(STDERR_FILENO) != 0;
  bar_ = mode == Mode::Always || (mode == Mode::Auto && tty);
  summary_ = summary && mode != Mode::Never && !bar_;
}

ProgressBar::~ProgressBar() {
  if (std::uncaught_exceptions() > 0) {
    if (drawn_) std::fputc('\n', stderr);
    return;
  }
  finish();
}

void ProgressBar::finish(const std::string& what) {
  if (finished_) return;
  finished_ = true;
  if (drawn_) std::fputc('\n', stderr);
  if (summary_) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::fprintf(stderr, "%s: %s in %.1f s\n", label_.c_str(), what.c_str(), elapsed);
  }
  std::fflush(stderr);
}

void ProgressBar::update(std::int64_t done, std::int64_t total) {
  if (!bar_ || finished_ || total <= 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total && drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  const double frac = static_cast<double>(done) / static_cast<double>(total);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0;
  constexpr int width = 30;
  const int filled = static_cast<int>(frac * width);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(width - filled), '.');
  std::fprintf(stderr, "\r%s [%s] %3d%%  %.0f s elapsed, eta %.0f s ", label_.c_str(), bar.c_str(),
               static_cast<int>(frac * 100.0), elapsed, eta);
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace funnel::cli
