// Tests for msd/skeleton/rigid_motion.hpp: a rigid placement and its rates.
#include "msd/skeleton/rigid_motion.hpp"

#include "msd/control/pose_keyframes.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using msd::Vec3;
using Q = Eigen::Quaterniond;

Q about(double deg, const Vec3& axis) { return Q(Eigen::AngleAxisd(deg * M_PI / 180.0, axis.normalized())); }

// A thigh swinging and turning about a moving hip.
msd::PoseKeyframes swing() {
  msd::PoseKeyframes k(Vec3(0.0, 0.0, 0.9));
  k.add(0.0, Vec3(0.0, 0.0, 0.9), Q::Identity());
  k.add(0.4, Vec3(0.05, 0.0, 0.92), about(30.0, Vec3::UnitY()));
  k.add(0.7, Vec3(0.08, 0.01, 0.9), about(-20.0, Vec3(0.1, 1.0, 0.2)));
  k.add(1.2, Vec3(0.1, 0.0, 0.88), about(45.0, Vec3(0.0, 1.0, -0.3)));
  return k;
}

}  // namespace

TEST(RigidMotion, PlacesMovesAndAcceleratesABodyPointAsARigidBody) {
  msd::RigidMotion m;
  m.rotation = about(90.0, Vec3::UnitZ()).toRotationMatrix();
  m.offset = Vec3(1, 0, 0);
  m.velocity = Vec3(0, 0, 2);
  m.acceleration = Vec3(0, 1, 0);
  m.angular_velocity = Vec3(0, 0, 3);
  m.angular_acceleration = Vec3(0, 0, 0.5);
  const Vec3 x = m.place(Vec3(1, 0, 0));
  EXPECT_LT((x - Vec3(1, 1, 0)).norm(), 1e-15);
  // r = (0, 1, 0) from the offset: omega x r = (-3, 0, 0), plus d'.
  EXPECT_LT((m.velocity_at(x) - Vec3(-3, 0, 2)).norm(), 1e-15);
  // d'' + alpha x r - omega^2 r = (0, 1, 0) + (-0.5, 0, 0) + (0, -9, 0).
  EXPECT_LT((m.acceleration_at(x) - Vec3(-0.5, -8, 0)).norm(), 1e-14);
}

TEST(RigidMotion, TheMotionBeforeIsTheKeyframesEarlierPoseToSecondOrder) {
  const msd::PoseKeyframes k = swing();
  const Vec3 X(0.03, -0.02, 0.5);
  for (double t : {0.2, 0.6, 1.0}) {
    double last = 0.0;
    for (double h : {1e-2, 5e-3}) {
      const msd::RigidMotion est = msd::rigid_motion_before(k.at(t), h), exact = k.at(t - h);
      const double err = (est.place(X) - exact.place(X)).norm();
      if (last > 0.0) {
        EXPECT_LT(err, last / 6.0) << t;  // third order: halving h divides by about 8
      }
      last = err;
      EXPECT_LT(err, 1e-4) << t;
    }
  }
}
