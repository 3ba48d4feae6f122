#include "msd/skeleton/hinge.hpp"

#include <Eigen/Geometry>

#include <string>

namespace msd {

void check_hinge(const Hinge& h) {
  if (!(h.axis.norm() > 0.0) || !h.axis.allFinite()) throw Error("hinge: the axis must be a nonzero vector");
  if (!(h.max_angle > h.min_angle)) throw Error("hinge: the flexion range must have max_angle > min_angle");
  if (!(h.inertia > 0.0)) throw Error("hinge: the moment of inertia must be positive, got " + std::to_string(h.inertia));
}

Mat3 hinge_rotation(const Hinge& h, double angle) {
  return Eigen::AngleAxisd(angle, h.axis.normalized()).toRotationMatrix();
}

void place_attached(const Hinge& h, const HingeState& s, const Points& rest, const std::vector<int>& nodes, Points& x,
                    Points& v) {
  const Mat3 r = hinge_rotation(h, s.angle);
  const Vec3 w = s.velocity * h.axis.normalized();
  for (int i : nodes) {
    const Vec3 p = h.centre + r * (Vec3(rest.col(i)) - h.centre);
    x.col(i) = p;
    v.col(i) = w.cross(p - h.centre);
  }
}

void step_hinge(const Hinge& h, double tau, double dt, HingeState& s) {
  s.velocity += dt * tau / h.inertia;
  s.angle += dt * s.velocity;
  if (s.angle < h.min_angle) {
    s.angle = h.min_angle;
    if (s.velocity < 0.0) s.velocity = 0.0;
  } else if (s.angle > h.max_angle) {
    s.angle = h.max_angle;
    if (s.velocity > 0.0) s.velocity = 0.0;
  }
}

}  // namespace msd
