// A progress line on stderr for runs longer than a couple of seconds: silent for
// the first two seconds, then "name: t = 3.20 / 12.00 s (27%), 1.9 s elapsed"
// refreshed in place on a terminal, or a new line every 10% otherwise.
#pragma once

#include <chrono>
#include <string>

namespace app {

class ProgressLine {
 public:
  explicit ProgressLine(std::string label, bool enabled = true);
  ~ProgressLine();
  void update(double t, double end);
  void done();

 private:
  std::string label_;
  bool enabled_, tty_, shown_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace app
