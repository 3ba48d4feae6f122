#include "msd/experiments/loading_path.hpp"

#include <algorithm>
#include <cmath>

namespace msd {

LoadingPath::LoadingPath(std::vector<std::pair<double, double>> points, const std::string& where) {
  if (points.size() < 2) throw Error(where + ": a loading path needs at least two way-points");
  if (points.front().first != 0.0) throw Error(where + ": the loading path must start at time 0");
  for (size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i].first) || !std::isfinite(points[i].second))
      throw Error(where + ": way-point " + std::to_string(i) + " is not finite");
    if (i > 0 && !(points[i].first > points[i - 1].first))
      throw Error(where + ": way-point times must increase strictly (way-point " +
                  std::to_string(i) + ")");
    curve_.add(points[i].first, points[i].second);
  }
}

double LoadingPath::min_value() const {
  const auto& v = curve_.values();
  return *std::min_element(v.begin(), v.end());
}

double LoadingPath::max_value() const {
  const auto& v = curve_.values();
  return *std::max_element(v.begin(), v.end());
}

LoadingPath LoadingPath::thesis_cycle() {
  return LoadingPath({{0.0, 0.0}, {2.0, -0.5}, {4.0, 0.0}, {8.0, 1.0}, {12.0, 0.0}}, "thesis cycle");
}

}  // namespace msd
