// A rigid body's placement and its rates: the prescribed motion of a bone
// (a kinematic group that turns as well as translates, e.g. the femur moved
// from the hip, msd/control/pose_keyframes.hpp). A body point with rest
// position X (3-vector, m) is at
//
//   x = R X + d,
//   v = omega x (R X) + d',
//   a = d'' + alpha x (R X) + omega x (omega x (R X)),
//
// R the rotation from the rest pose, d the offset (the image of the origin),
// omega and alpha the angular velocity and acceleration in the world's axes.
// The default is the rest pose at rest.
#pragma once

#include "msd/core/types.hpp"

namespace msd {

struct RigidMotion {
  Mat3 rotation{Mat3::Identity()};
  Vec3 offset{Vec3::Zero()};                ///< d, m
  Vec3 velocity{Vec3::Zero()};              ///< d', m/s
  Vec3 acceleration{Vec3::Zero()};          ///< d'', m/s^2
  Vec3 angular_velocity{Vec3::Zero()};      ///< omega, rad/s
  Vec3 angular_acceleration{Vec3::Zero()};  ///< alpha, rad/s^2

  /// x of the body point at rest position X.
  Vec3 place(const Vec3& rest) const { return rotation * rest + offset; }
  /// v of the body point now at x.
  Vec3 velocity_at(const Vec3& x) const { return angular_velocity.cross(x - offset) + velocity; }
  /// a of the body point now at x.
  Vec3 acceleration_at(const Vec3& x) const {
    const Vec3 r = x - offset;
    return acceleration + angular_acceleration.cross(r) + angular_velocity.cross(angular_velocity.cross(r));
  }
};

/// The same motion h seconds earlier, to second order in h (Taylor):
/// R(t - h) = exp([-h omega + h^2/2 alpha]) R, d(t - h) = d - h d' + h^2/2 d'',
/// d'(t - h) = d' - h d'', omega(t - h) = omega - h alpha; the accelerations kept.
/// (The implicit step's halved steps take their halfway placement from it.)
RigidMotion rigid_motion_before(const RigidMotion& m, double h);

}  // namespace msd
