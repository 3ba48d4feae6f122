#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace app {

namespace {

std::string seconds_text(double s) {
  char b[32];
  if (s < 60.0)
    std::snprintf(b, sizeof b, "%.1f s", s);
  else if (s < 3600.0)
    std::snprintf(b, sizeof b, "%dm%02ds", static_cast<int>(s / 60.0), static_cast<int>(std::fmod(s, 60.0)));
  else
    std::snprintf(b, sizeof b, "%dh%02dm", static_cast<int>(s / 3600.0), static_cast<int>(std::fmod(s, 3600.0) / 60.0));
  return b;
}

}  // namespace

std::string format_progress(const std::string& label, double t, double end, double elapsed, bool bar) {
  const double fraction = end > 0.0 ? std::clamp(t / end, 0.0, 1.0) : 1.0;
  const std::string left =
      fraction > 0.0 ? "~" + seconds_text(elapsed * (1.0 - fraction) / fraction) + " left" : "time left unknown";
  char line[512];
  if (bar) {
    constexpr int kWidth = 20;
    const int filled = static_cast<int>(std::floor(fraction * kWidth + 1e-9));
    const std::string drawn = std::string(static_cast<size_t>(filled), '#') + std::string(static_cast<size_t>(kWidth - filled), '-');
    std::snprintf(line, sizeof line, "%s [%s] %3.0f%%  t %.2f/%.2f s  %s, %s", label.c_str(), drawn.c_str(),
                  100.0 * fraction, t, end, seconds_text(elapsed).c_str(), left.c_str());
  } else {
    std::snprintf(line, sizeof line, "%s: %.0f%% (t %.2f / %.2f s), %s elapsed, %s", label.c_str(), 100.0 * fraction,
                  t, end, seconds_text(elapsed).c_str(), left.c_str());
  }
  return line;
}

ProgressLine::ProgressLine(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

ProgressLine::~ProgressLine() { done(); }

void ProgressLine::update(double t, double end) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < kQuietStart) return;
  const double since = std::chrono::duration<double>(now - last_).count();
  if (tty_) {
    if (shown_ && since < 0.2) return;
    last_text_ = format_progress(label_, t, end, elapsed, true);
    std::fprintf(stderr, "\r%s\x1b[K", last_text_.c_str());  // redraw in place, clear the rest of the line
  } else {
    if (shown_ ? since < kLogInterval : elapsed < kLogInterval / 3.0) return;
    std::fprintf(stderr, "%s\n", format_progress(label_, t, end, elapsed, false).c_str());
  }
  std::fflush(stderr);
  shown_ = true;
  last_ = now;
}

void ProgressLine::done() {
  if (shown_ && tty_) std::fprintf(stderr, "\n");  // the last bar stays as the run's line
  shown_ = false;
}

}  // namespace app
