// Basic numeric types shared by every msd module, and the library's exception.
// SI units throughout (m, kg, s, N, Pa). Point sets are 3 x N column matrices:
// column i is the position (or velocity, force) of node i.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace msd {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
/// 3 x N: column i belongs to node i.
using Points = Eigen::Matrix3Xd;
using Tet = std::array<int, 4>;
using Tri = std::array<int, 3>;

/// v^: the matrix with v^ w = v x w.
inline Mat3 cross_matrix(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// Every error the library reports at a boundary (file, spec, parameter) is an
/// msd::Error whose message names the offending file, field or element.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace msd
