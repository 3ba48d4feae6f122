// Frequency and damping of a ringing signal (vibration benchmarks): the period
// from linearly interpolated upward zero crossings (about the signal's final
// mean), the damping ratio from the logarithmic decrement of successive
// positive peaks - both over the part of the signal whose peaks stay above 2%
// of the first (below that, the offset's estimate dominates what is left).
#pragma once

#include <vector>

namespace tbio {

struct RingDown {
  double frequency = 0.0;      ///< Hz (0 when fewer than two upward crossings)
  double damping_ratio = 0.0;  ///< zeta from delta = ln(x_k / x_{k+1}) (0 without two peaks)
  int crossings = 0;           ///< upward zero crossings used
  int peaks = 0;
};

RingDown analyse_ring_down(const std::vector<double>& time, const std::vector<double>& signal);

/// The same over the samples at and after `start` (s): a ring-down from its
/// release, without the preload before it.
RingDown analyse_ring_down_after(const std::vector<double>& time, const std::vector<double>& signal, double start);

}  // namespace tbio
