#include "msd/experiments/loading_path.hpp"

#include <algorithm>
#include <cmath>

namespace msd {

LoadingPath::LoadingPath(std::vector<std::pair<double, double>> points, const std::string& where)
    : points_(std::move(points)) {
  if (points_.size() < 2) throw Error(where + ": a loading path needs at least two way-points");
  if (points_.front().first != 0.0) throw Error(where + ": the loading path must start at time 0");
  for (size_t i = 0; i < points_.size(); ++i) {
    if (!std::isfinite(points_[i].first) || !std::isfinite(points_[i].second))
      throw Error(where + ": way-point " + std::to_string(i) + " is not finite");
    if (i > 0 && !(points_[i].first > points_[i - 1].first))
      throw Error(where + ": way-point times must increase strictly (way-point " +
                  std::to_string(i) + ")");
  }
}

size_t LoadingPath::segment(double t) const {
  const auto it = std::upper_bound(points_.begin(), points_.end(), t,
                                   [](double v, const std::pair<double, double>& p) { return v < p.first; });
  const size_t i = static_cast<size_t>(it - points_.begin());
  return std::clamp<size_t>(i, 1, points_.size() - 1) - 1;
}

double LoadingPath::value(double t) const {
  if (t <= points_.front().first) return points_.front().second;
  if (t >= points_.back().first) return points_.back().second;
  const size_t i = segment(t);
  const auto& [t0, v0] = points_[i];
  const auto& [t1, v1] = points_[i + 1];
  return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
}

double LoadingPath::rate(double t) const {
  if (t < points_.front().first || t >= points_.back().first) return 0.0;
  const size_t i = segment(t);
  return (points_[i + 1].second - points_[i].second) / (points_[i + 1].first - points_[i].first);
}

double LoadingPath::min_value() const {
  double v = points_.front().second;
  for (const auto& p : points_) v = std::min(v, p.second);
  return v;
}

double LoadingPath::max_value() const {
  double v = points_.front().second;
  for (const auto& p : points_) v = std::max(v, p.second);
  return v;
}

LoadingPath LoadingPath::thesis_cycle() {
  return LoadingPath({{0.0, 0.0}, {2.0, -0.5}, {4.0, 0.0}, {8.0, 1.0}, {12.0, 0.0}}, "thesis cycle");
}

}  // namespace msd
