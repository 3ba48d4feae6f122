// Small helpers shared by the comparison, calibration, sweep and stability
// code: linear interpolation of a sampled series, and JSON text.
#pragma once

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace tbio {

/// y(at) by linear interpolation of the samples (t ascending, same length as
/// y); NaN outside [t.front(), t.back()] (with 1e-9 s of slack) or when empty.
inline double interpolate(const std::vector<double>& t, const std::vector<double>& y, double at) {
  if (t.empty() || at < t.front() - 1e-9 || at > t.back() + 1e-9) return std::numeric_limits<double>::quiet_NaN();
  const auto it = std::lower_bound(t.begin(), t.end(), at);
  if (it == t.begin()) return y.front();
  if (it == t.end()) return y.back();
  const size_t i = static_cast<size_t>(it - t.begin());
  const double w = (at - t[i - 1]) / (t[i] - t[i - 1]);
  return (1 - w) * y[i - 1] + w * y[i];
}

/// A JSON number (`null` for NaN) with `precision` significant digits.
inline std::string json_number(double v, int precision = 10) {
  if (std::isnan(v)) return "null";
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

}  // namespace tbio
