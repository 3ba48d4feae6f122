#include "msd/control/pose_keyframes.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

namespace msd {

namespace {

// One segment's cubic Hermite: value, first and second derivative in t at
// s = (t - t0) / h (s may leave [0, 1] for the central difference).
struct Hermite {
  Vec3 p0, p1, m0, m1;
  double h;
  Vec3 value(double s) const {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * h * m1;
  }
  Vec3 rate(double s) const {
    const double s2 = s * s;
    return ((6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * h * m0 + (-6 * s2 + 6 * s) * p1 + (3 * s2 - 2 * s) * h * m1) / h;
  }
  Vec3 curvature(double s) const {
    return ((12 * s - 6) * p0 + (6 * s - 4) * h * m0 + (-12 * s + 6) * p1 + (6 * s - 2) * h * m1) / (h * h);
  }
};

// Catmull-Rom tangent at way-point i (zero at the ends).
Vec3 tangent(const std::vector<double>& t, const std::vector<Vec3>& p, size_t i) {
  if (i == 0 || i + 1 >= t.size()) return Vec3::Zero();
  return (p[i + 1] - p[i - 1]) / (t[i + 1] - t[i - 1]);
}

}  // namespace

Vec3 rotation_vector(const Eigen::Quaterniond& q) {
  const Eigen::AngleAxisd aa(q);
  double angle = aa.angle();
  Vec3 axis = aa.axis();
  if (angle > M_PI) {  // the shorter way round
    angle = 2.0 * M_PI - angle;
    axis = -axis;
  }
  return angle * axis;
}

Mat3 rotation_from_vector(const Vec3& phi) {
  const double a = phi.norm();
  if (a == 0.0) return Mat3::Identity();
  return Eigen::AngleAxisd(a, phi / a).toRotationMatrix();
}

Mat3 so3_left_jacobian(const Vec3& phi) {
  const double a = phi.norm();
  const Mat3 k = cross_matrix(phi);
  if (a < 1e-6) return Mat3::Identity() + 0.5 * k + k * k / 6.0;  // the series, to O(a^3)
  return Mat3::Identity() + (1.0 - std::cos(a)) / (a * a) * k + (a - std::sin(a)) / (a * a * a) * k * k;
}

void PoseKeyframes::add(double time, const Vec3& position, const Eigen::Quaterniond& orientation) {
  const std::string which = "way-point " + std::to_string(times_.size() + 1) + ": ";
  if (!std::isfinite(time) || !position.allFinite() || !orientation.coeffs().allFinite())
    throw Error(which + "needs finite numbers");
  if (!times_.empty() && !(time > times_.back()))
    throw Error(which + "its time " + std::to_string(time) + " s does not come after the previous way-point's " +
                std::to_string(times_.back()) + " s (way-points must be in order of time)");
  const double norm = orientation.norm();
  if (std::abs(norm - 1.0) > 1e-3)
    throw Error(which + "the orientation quaternion has length " + std::to_string(norm) +
                ", not 1: a rotation is a unit quaternion (w, x, y, z)");
  // (q and -q give the same rotation vector: rotation_vector takes the shorter way.)
  Vec3 phi = rotation_vector(orientation.normalized());
  // Keep phi continuous across the log's branch: of phi and its image
  // phi - 2 pi phi/|phi| (the same rotation), the one nearest the predecessor.
  // (One image: way-points less than a half turn apart, as a hip's are.)
  if (!rotations_.empty() && phi.norm() > 0.0) {
    const Vec3 alt = phi - 2.0 * M_PI * phi.normalized();
    if ((alt - rotations_.back()).norm() < (phi - rotations_.back()).norm()) phi = alt;
  }
  times_.push_back(time);
  positions_.push_back(position);
  rotations_.push_back(phi);
}

RigidMotion PoseKeyframes::at(double t) const {
  RigidMotion m;
  if (times_.empty()) return m;
  Vec3 p, p_rate = Vec3::Zero(), p_acc = Vec3::Zero(), phi;
  if (times_.size() == 1 || t <= times_.front() || t >= times_.back()) {
    const size_t i = t <= times_.front() ? 0 : times_.size() - 1;
    p = positions_[i];
    phi = rotations_[i];
  } else {
    const size_t k = static_cast<size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
    const double h = times_[k + 1] - times_[k], s = (t - times_[k]) / h;
    const Hermite pos{positions_[k], positions_[k + 1], tangent(times_, positions_, k), tangent(times_, positions_, k + 1), h};
    const Hermite rot{rotations_[k], rotations_[k + 1], tangent(times_, rotations_, k), tangent(times_, rotations_, k + 1), h};
    p = pos.value(s);
    p_rate = pos.rate(s);
    p_acc = pos.curvature(s);
    phi = rot.value(s);
    m.angular_velocity = so3_left_jacobian(phi) * rot.rate(s);
    const double ds = 1e-5;
    const Vec3 w_plus = so3_left_jacobian(rot.value(s + ds)) * rot.rate(s + ds);
    const Vec3 w_minus = so3_left_jacobian(rot.value(s - ds)) * rot.rate(s - ds);
    m.angular_acceleration = (w_plus - w_minus) / (2.0 * ds * h);
  }
  m.rotation = rotation_from_vector(phi);
  const Vec3 r = m.rotation * pivot_;  // the pivot from the offset
  m.offset = p - r;
  m.velocity = p_rate - m.angular_velocity.cross(r);
  m.acceleration = p_acc - m.angular_acceleration.cross(r) - m.angular_velocity.cross(m.angular_velocity.cross(r));
  return m;
}

}  // namespace msd
