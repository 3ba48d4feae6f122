#include "msd/skeleton/rigid_motion.hpp"

#include <Eigen/Geometry>

namespace msd {

RigidMotion rigid_motion_before(const RigidMotion& m, double h) {
  RigidMotion e = m;
  const Vec3 phi = -h * m.angular_velocity + 0.5 * h * h * m.angular_acceleration;
  const double angle = phi.norm();
  if (angle > 0.0) e.rotation = Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix() * m.rotation;
  e.offset = m.offset - h * m.velocity + 0.5 * h * h * m.acceleration;
  e.velocity = m.velocity - h * m.acceleration;
  e.angular_velocity = m.angular_velocity - h * m.angular_acceleration;
  return e;
}

}  // namespace msd
