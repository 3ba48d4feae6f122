#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace app {

ProgressLine::ProgressLine(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

ProgressLine::~ProgressLine() { done(); }

void ProgressLine::update(double t, double end) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < 2.0) return;
  const double frac = end > 0.0 ? t / end : 1.0;
  if (tty_) {
    if (std::chrono::duration<double>(now - last_).count() < 0.2) return;
    std::fprintf(stderr, "\r%s: t = %.2f / %.2f s (%3.0f%%), %.1f s elapsed   ", label_.c_str(), t, end,
                 100.0 * frac, elapsed);
  } else {
    const int decile = static_cast<int>(frac * 10.0);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s: t = %.2f / %.2f s (%.0f%%), %.1f s elapsed\n", label_.c_str(), t, end,
                 100.0 * frac, elapsed);
  }
  std::fflush(stderr);
  shown_ = true;
  last_ = now;
}

void ProgressLine::done() {
  if (shown_ && tty_) std::fprintf(stderr, "\n");
  shown_ = false;
}

}  // namespace app
