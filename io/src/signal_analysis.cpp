#include "tbio/signal_analysis.hpp"

#include <cmath>

namespace tbio {

RingDown analyse_ring_down(const std::vector<double>& t, const std::vector<double>& x) {
  RingDown r;
  const size_t n = std::min(t.size(), x.size());
  if (n < 3) return r;
  // Oscillation about the mean of the last third (the static offset, if any).
  double mean = 0.0;
  size_t count = 0;
  for (size_t i = 2 * n / 3; i < n; ++i, ++count) mean += x[i];
  mean /= static_cast<double>(count);
  // Positive peaks about the mean, kept while they stay above kFloor of the
  // first: once the ring-down has decayed to the level of the offset's own
  // estimation error (a part of a decaying cycle left in the last third), its
  // peaks and crossings would measure that error, not the oscillation.
  constexpr double kFloor = 0.02;
  std::vector<double> peaks;
  double t_end = t[n - 1];
  for (size_t i = 1; i + 1 < n; ++i) {
    const double v = x[i] - mean;
    if (v > 0.0 && v >= x[i - 1] - mean && v > x[i + 1] - mean) {
      if (!peaks.empty() && v < kFloor * peaks.front()) {
        t_end = t[i];
        break;
      }
      peaks.push_back(v);
    }
  }
  std::vector<double> up;
  for (size_t i = 1; i < n && t[i] <= t_end; ++i) {
    const double a = x[i - 1] - mean, b = x[i] - mean;
    if (a < 0.0 && b >= 0.0) up.push_back(t[i - 1] + (t[i] - t[i - 1]) * (-a) / (b - a));
  }
  r.crossings = static_cast<int>(up.size());
  if (up.size() >= 2) r.frequency = static_cast<double>(up.size() - 1) / (up.back() - up.front());
  r.peaks = static_cast<int>(peaks.size());
  if (peaks.size() >= 2) {
    const double delta = std::log(peaks.front() / peaks.back()) / static_cast<double>(peaks.size() - 1);
    r.damping_ratio = delta / std::sqrt(4.0 * M_PI * M_PI + delta * delta);
  }
  return r;
}

RingDown analyse_ring_down_after(const std::vector<double>& time, const std::vector<double>& signal, double start) {
  std::vector<double> t, x;
  for (size_t i = 0; i < time.size(); ++i)
    if (time[i] >= start - 1e-12) {
      t.push_back(time[i]);
      x.push_back(signal[i]);
    }
  return analyse_ring_down(t, x);
}

}  // namespace tbio
