// Piecewise-linear keyframes: a quantity (a strain, a knee angle, a torque, an
// obstacle's offset) prescribed through (time, value) way-points, held at the
// end values outside them. One interpolation for the benchmarks' loading paths
// (msd/experiments/loading_path.hpp) and the leg scenes' scripted motions.
#pragma once

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace msd {

/// T is a scalar or a fixed-size Eigen vector.
template <class T>
class Keyframes {
 public:
  /// Appends a way-point; callers keep times strictly increasing (readers check).
  void add(double time, const T& value) {
    times_.push_back(time);
    values_.push_back(value);
  }
  bool empty() const { return times_.empty(); }
  std::size_t size() const { return times_.size(); }
  const std::vector<double>& times() const { return times_; }
  const std::vector<T>& values() const { return values_; }

  /// v0 + s (v1 - v0), s = (t - t0) / (t1 - t0), on the segment holding t;
  /// the first value before it, the last after it; zero when empty.
  T at(double t) const {
    if (times_.empty()) return zero();
    if (t <= times_.front()) return values_.front();
    if (t >= times_.back()) return values_.back();
    const std::size_t i = segment(t);
    const double s = (t - times_[i]) / (times_[i + 1] - times_[i]);
    return T(values_[i] + s * (values_[i + 1] - values_[i]));
  }

  /// The slope of the segment holding t; zero before the first and from the
  /// last way-point on.
  T rate(double t) const {
    if (times_.size() < 2 || t < times_.front() || t >= times_.back()) return zero();
    const std::size_t i = segment(t);
    return T((values_[i + 1] - values_[i]) / (times_[i + 1] - times_[i]));
  }

 private:
  // The way-point starting the segment that holds t (times_.front() <= t < times_.back()).
  std::size_t segment(double t) const {
    const auto k = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
    return std::clamp<std::size_t>(k, 1, times_.size() - 1) - 1;
  }
  static T zero() {
    if constexpr (std::is_arithmetic_v<T>)
      return T(0);
    else
      return T::Zero();
  }
  std::vector<double> times_;
  std::vector<T> values_;
};

}  // namespace msd
