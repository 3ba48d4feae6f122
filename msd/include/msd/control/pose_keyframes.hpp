// A bone's pose prescribed through keyframes (the femur moved from the hip,
// issue 18): at each way-point time t_i, where a chosen body point - the
// pivot, e.g. the hip's centre - is (p_i) and the body's orientation (a unit
// quaternion q_i, the rotation from the rest pose). Between way-points:
//
//  - the pivot's path is a cubic Hermite spline with Catmull-Rom tangents
//    m_i = (p_{i+1} - p_{i-1}) / (t_{i+1} - t_{i-1}) (non-uniform times) and
//    zero tangents at the first and last way-points, so the motion starts and
//    ends at rest, and position, velocity are continuous (C1) everywhere;
//  - the orientation is the same spline through the rotation vectors
//    phi_i = log(q_i) (each the image nearest its predecessor's: way-points
//    less than a half turn apart),
//    R = exp([phi]); its angular velocity omega = J_l(phi) phi' with the left
//    Jacobian of SO(3), J_l = I + (1 - cos a)/a^2 [phi] + (a - sin a)/a^3 [phi]^2,
//    a = |phi| (exact); its angular acceleration by a central difference of
//    omega on the segment's own polynomials (relative step 1e-5).
//
// Before the first way-point the first pose is held, after the last the last.
// The result is a RigidMotion (msd/skeleton/rigid_motion.hpp) with
// d = p - R p_rest, so that x = R X + d puts the pivot at p.
#pragma once

#include "msd/core/types.hpp"
#include "msd/skeleton/rigid_motion.hpp"

#include <vector>

namespace msd {

class PoseKeyframes {
 public:
  /// `pivot`: the body point the way-points place, at its rest position (m).
  explicit PoseKeyframes(const Vec3& pivot = Vec3::Zero()) : pivot_(pivot) {}

  /// Appends a way-point: time (s), the pivot's position (m) and the
  /// orientation as a quaternion (w, x, y, z). Throws msd::Error when the time
  /// does not exceed the last one, or when |q| differs from 1 by more than
  /// 1e-3 (within it, q is normalised). The message names the way-point.
  void add(double time, const Vec3& position, const Eigen::Quaterniond& orientation);

  bool empty() const { return times_.empty(); }
  std::size_t size() const { return times_.size(); }
  const Vec3& pivot() const { return pivot_; }

  /// The pose, velocities and accelerations at time t; the rest pose at rest
  /// when empty.
  RigidMotion at(double t) const;

 private:
  Vec3 pivot_;
  std::vector<double> times_;
  std::vector<Vec3> positions_, rotations_;  ///< p_i, phi_i
};

/// Rotation vector of a unit quaternion (its axis times its angle, |phi| <= pi).
Vec3 rotation_vector(const Eigen::Quaterniond& q);

/// exp([phi]): the rotation by |phi| about phi.
Mat3 rotation_from_vector(const Vec3& phi);

/// J_l(phi), the left Jacobian of SO(3): d/dt exp([phi]) = [J_l(phi) phi'] exp([phi]).
Mat3 so3_left_jacobian(const Vec3& phi);

}  // namespace msd
