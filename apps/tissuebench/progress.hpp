// Progress of a long run on stderr, silent for its first two seconds. On a
// terminal: one bar per run, redrawn in place -
//   "hamstrings (leg) [########------------]  41%  t 4.51/11.00 s  6.2 s, ~8.9 s left"
// and left on its own line when the run ends. Not on a terminal (a log, CI):
// a plain line every kLogInterval seconds, so a five-minute suite writes a few
// lines per long run and none for the short ones.
#pragma once

#include <chrono>
#include <string>

namespace app {

/// The bar's text for a run `fraction` done (0...1) at simulated time t of
/// `end` after `elapsed` wall seconds; `bar` draws the bar (a terminal),
/// else a plain log line. Time left = elapsed (1 - fraction) / fraction.
std::string format_progress(const std::string& label, double t, double end, double elapsed, bool bar);

class ProgressLine {
 public:
  static constexpr double kQuietStart = 2.0;   ///< s before anything is shown
  static constexpr double kLogInterval = 30.0;  ///< s between log lines (not a terminal)

  explicit ProgressLine(std::string label, bool enabled = true);
  ~ProgressLine();
  void update(double t, double end);
  void done();

 private:
  std::string label_, last_text_;
  bool enabled_, tty_, shown_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace app
