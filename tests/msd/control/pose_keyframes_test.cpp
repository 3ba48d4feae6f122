// Tests for msd/control/pose_keyframes.hpp: a bone's pose through keyframes.
#include "msd/control/pose_keyframes.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using msd::Mat3;
using msd::Vec3;
using Q = Eigen::Quaterniond;

Q about(double deg, const Vec3& axis) { return Q(Eigen::AngleAxisd(deg * M_PI / 180.0, axis.normalized())); }

// A thigh swinging about a hip at (0, 0, 0.9): forward, back, forward, with
// the hip moving too - every kind of way-point the spline meets.
msd::PoseKeyframes swing() {
  msd::PoseKeyframes k(Vec3(0.0, 0.0, 0.9));
  k.add(0.0, Vec3(0.0, 0.0, 0.9), Q::Identity());
  k.add(0.4, Vec3(0.05, 0.0, 0.92), about(30.0, Vec3::UnitY()));
  k.add(0.7, Vec3(0.08, 0.01, 0.9), about(-20.0, Vec3(0.1, 1.0, 0.2)));
  k.add(1.2, Vec3(0.1, 0.0, 0.88), about(45.0, Vec3(0.0, 1.0, -0.3)));
  return k;
}

}  // namespace

TEST(PoseKeyframes, PassesThroughEachWayPointAndHoldsTheEndsAtRest) {
  const msd::PoseKeyframes k = swing();
  const Vec3 pivot = k.pivot();
  const double times[] = {0.0, 0.4, 0.7, 1.2};
  const Vec3 positions[] = {Vec3(0.0, 0.0, 0.9), Vec3(0.05, 0.0, 0.92), Vec3(0.08, 0.01, 0.9), Vec3(0.1, 0.0, 0.88)};
  const Q rotations[] = {Q::Identity(), about(30.0, Vec3::UnitY()), about(-20.0, Vec3(0.1, 1.0, 0.2)),
                         about(45.0, Vec3(0.0, 1.0, -0.3))};
  for (int i = 0; i < 4; ++i) {
    const msd::RigidMotion m = k.at(times[i]);
    EXPECT_LT((m.place(pivot) - positions[i]).norm(), 1e-12) << "way-point " << i;
    EXPECT_LT((m.rotation - rotations[i].toRotationMatrix()).norm(), 1e-12) << "way-point " << i;
  }
  for (double t : {-1.0, 0.0, 1.2, 3.0}) {
    const msd::RigidMotion m = k.at(t);
    EXPECT_LT(m.velocity.norm() + m.angular_velocity.norm(), 1e-12) << t;
  }
  EXPECT_LT((k.at(-1.0).rotation - Mat3::Identity()).norm(), 1e-15);
  EXPECT_LT((k.at(5.0).place(pivot) - positions[3]).norm(), 1e-12);
  // Empty: the rest pose at rest.
  const msd::RigidMotion rest = msd::PoseKeyframes().at(0.3);
  EXPECT_EQ(rest.rotation, Mat3::Identity());
  EXPECT_EQ(rest.offset, Vec3::Zero());
}

TEST(PoseKeyframes, VelocitiesAndAccelerationsAreTheDerivativesOfThePlacement) {
  const msd::PoseKeyframes k = swing();
  const Vec3 X(0.03, -0.02, 0.5);  // a point of the thigh, at rest
  const double h = 1e-5;
  for (double t : {0.1, 0.3, 0.55, 0.69, 0.9, 1.1}) {
    const msd::RigidMotion m = k.at(t), mp = k.at(t + h), mm = k.at(t - h);
    const Vec3 x = m.place(X);
    const Vec3 v_fd = (mp.place(X) - mm.place(X)) / (2 * h);
    EXPECT_LT((m.velocity_at(x) - v_fd).norm(), 1e-6 * (1.0 + v_fd.norm())) << t;
    const Vec3 a_fd = (mp.velocity_at(mp.place(X)) - mm.velocity_at(mm.place(X))) / (2 * h);
    EXPECT_LT((m.acceleration_at(x) - a_fd).norm(), 1e-4 * (1.0 + a_fd.norm())) << t;
    // dR/dt R^T = [omega].
    const Mat3 w = (mp.rotation - mm.rotation) / (2 * h) * m.rotation.transpose();
    EXPECT_LT((Vec3(w(2, 1), w(0, 2), w(1, 0)) - m.angular_velocity).norm(), 1e-6 * (1.0 + m.angular_velocity.norm())) << t;
    const Vec3 alpha_fd = (mp.angular_velocity - mm.angular_velocity) / (2 * h);
    EXPECT_LT((m.angular_acceleration - alpha_fd).norm(), 1e-4 * (1.0 + alpha_fd.norm())) << t;
    EXPECT_GT(m.angular_velocity.norm(), 0.1) << t;  // the thigh does turn here
  }
}

TEST(PoseKeyframes, VelocityIsContinuousThroughAWayPoint) {
  const msd::PoseKeyframes k = swing();
  const Vec3 X(0.0, 0.05, 0.4);
  for (double knot : {0.4, 0.7}) {
    const msd::RigidMotion before = k.at(knot - 1e-9), after = k.at(knot + 1e-9);
    EXPECT_LT((before.velocity_at(before.place(X)) - after.velocity_at(after.place(X))).norm(), 1e-6) << knot;
    EXPECT_LT((before.angular_velocity - after.angular_velocity).norm(), 1e-6) << knot;
  }
}

TEST(PoseKeyframes, AQuarterTurnAboutOneAxisTurnsThroughEveryAngleBetween) {
  // Two way-points about one fixed axis: the angle is the Hermite smoothstep
  // 90 deg (3 s^2 - 2 s^3) and omega is along the axis.
  msd::PoseKeyframes k(Vec3(1.0, 2.0, 3.0));
  k.add(1.0, Vec3(1.0, 2.0, 3.0), Q::Identity());
  k.add(3.0, Vec3(1.0, 2.0, 3.0), about(90.0, Vec3::UnitZ()));
  for (double s : {0.25, 0.5, 0.8}) {
    const msd::RigidMotion m = k.at(1.0 + 2.0 * s);
    const double angle = 0.5 * M_PI * (3 * s * s - 2 * s * s * s);
    EXPECT_LT((m.rotation - about(angle * 180.0 / M_PI, Vec3::UnitZ()).toRotationMatrix()).norm(), 1e-12);
    EXPECT_LT((m.angular_velocity - Vec3(0, 0, 0.5 * M_PI * (6 * s - 6 * s * s) / 2.0)).norm(), 1e-12);
    EXPECT_LT((m.place(k.pivot()) - Vec3(1.0, 2.0, 3.0)).norm(), 1e-12);  // the pivot stays
    EXPECT_LT(m.velocity_at(m.place(k.pivot())).norm(), 1e-12);
  }
}

TEST(PoseKeyframes, WayPointsOutOfOrderOrANonUnitRotationAreRefusedByNumber) {
  msd::PoseKeyframes k;
  k.add(0.0, Vec3::Zero(), Q::Identity());
  k.add(0.5, Vec3::Zero(), Q::Identity());
  try {
    k.add(0.5, Vec3::Zero(), Q::Identity());
    FAIL() << "a repeated time was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("way-point 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("in order of time"), std::string::npos) << e.what();
  }
  try {
    k.add(1.0, Vec3::Zero(), Q(1.0, 0.2, 0.0, 0.0));
    FAIL() << "a non-unit quaternion was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("way-point 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unit quaternion"), std::string::npos) << e.what();
  }
  EXPECT_THROW(k.add(std::nan(""), Vec3::Zero(), Q::Identity()), msd::Error);
  EXPECT_EQ(k.size(), 2u);
  // Rounded to 7 digits, as a scene writes cos and sin of 15 deg: accepted.
  EXPECT_NO_THROW(k.add(1.0, Vec3::Zero(), Q(0.9914449, 0.0, 0.1305262, 0.0)));
}
