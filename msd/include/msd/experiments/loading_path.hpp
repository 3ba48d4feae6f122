// A loading path: a quantity (e.g. nominal strain) prescribed as a piecewise
// linear function of time through (time, value) way-points (thesis 5.2.1: the
// upper block moved slowly down to half the sample length, back, up to twice
// the length and back, in about 12 s).
#pragma once

#include "msd/control/keyframes.hpp"
#include "msd/core/types.hpp"

#include <string>
#include <utility>
#include <vector>

namespace msd {

class LoadingPath {
 public:
  /// Way-points with strictly increasing times, starting at t = 0. Throws
  /// msd::Error naming `where` otherwise.
  LoadingPath(std::vector<std::pair<double, double>> points, const std::string& where);

  double value(double t) const { return curve_.at(t); }  ///< clamped to the end values outside the path
  double rate(double t) const { return curve_.rate(t); }   ///< slope of the segment containing t (0 outside)
  double end_time() const { return curve_.times().back(); }
  double min_value() const;
  double max_value() const;
  const Keyframes<double>& keyframes() const { return curve_; }

  /// The thesis cycle: 0 -> -0.5 -> 0 -> +1.0 -> 0 at a constant strain rate
  /// over 12 s (way-points at 0, 2, 4, 8, 12 s).
  static LoadingPath thesis_cycle();

 private:
  Keyframes<double> curve_;
};

}  // namespace msd
