// The knee hinge: attached nodes turn rigidly about the axis with v = omega x r;
// a lower leg swinging freely under gravity has the pendulum's period; the
// flexion range holds.
#include "msd/skeleton/hinge.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

TEST(Hinge, AttachedNodesTurnRigidlyAboutTheAxis) {
  msd::Hinge h;
  h.centre = msd::Vec3(0.1, 0.2, 0.5);
  h.axis = msd::Vec3(1, 0, 0);
  h.inertia = 0.1;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  msd::Points rest(3, 6), x = msd::Points::Zero(3, 6), v = msd::Points::Zero(3, 6);
  for (int i = 0; i < 6; ++i) rest.col(i) = h.centre + msd::Vec3(u(rng), u(rng), u(rng));
  rest.col(5) = h.centre + msd::Vec3(0.3, 0, 0);  // on the axis
  const msd::HingeState s{0.7, 2.0};
  msd::place_attached(h, s, rest, {0, 1, 2, 3, 4, 5}, x, v);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR((x.col(i) - x.col(j)).norm(), (rest.col(i) - rest.col(j)).norm(), 1e-14);  // rigid
  EXPECT_LT((x.col(5) - rest.col(5)).norm(), 1e-15);  // the axis does not move
  EXPECT_LT(v.col(5).norm(), 1e-15);
  // A node 0.4 m below the knee, turned by 0.7 rad about +x: it swings towards +y.
  msd::Points one = msd::Points::Zero(3, 1), x1 = one, v1 = one;
  one.col(0) = h.centre + msd::Vec3(0, 0, -0.4);
  msd::place_attached(h, s, one, {0}, x1, v1);
  EXPECT_LT((x1.col(0) - (h.centre + 0.4 * msd::Vec3(0, std::sin(0.7), -std::cos(0.7)))).norm(), 1e-14);
  EXPECT_LT((v1.col(0) - 2.0 * 0.4 * msd::Vec3(0, std::cos(0.7), std::sin(0.7))).norm(), 1e-14);
}

TEST(Hinge, AFreeLowerLegSwingsWithThePendulumPeriod) {
  // A 3.5 kg lower leg with its centre of mass 0.25 m below the knee and
  // I = 0.3 kg m^2 about the knee: small swings have T = 2 pi sqrt(I / (m g d)).
  msd::Hinge h;
  h.inertia = 0.3;
  h.min_angle = -1.0;
  h.max_angle = 1.0;
  const double m = 3.5, g = 9.81, d = 0.25, dt = 1e-4;
  msd::HingeState s{0.05, 0.0};
  double t = 0.0, last_crossing = -1.0, period = 0.0;
  int crossings = 0;
  while (crossings < 3 && t < 10.0) {
    const double before = s.angle;
    msd::step_hinge(h, -m * g * d * std::sin(s.angle), dt, s);
    t += dt;
    if (before > 0.0 && s.angle <= 0.0) {
      if (last_crossing >= 0.0) period = t - last_crossing;
      last_crossing = t;
      ++crossings;
    }
  }
  EXPECT_NEAR(period, 2 * M_PI * std::sqrt(h.inertia / (m * g * d)), 1e-3);
}

TEST(Hinge, TheFlexionRangeHoldsAndBadHingesAreRefused) {
  msd::Hinge h;
  h.inertia = 0.3;
  msd::HingeState s{2.3, 5.0};
  msd::step_hinge(h, 0.0, 0.1, s);
  EXPECT_DOUBLE_EQ(s.angle, h.max_angle);
  EXPECT_DOUBLE_EQ(s.velocity, 0.0);
  s = {0.01, -3.0};
  msd::step_hinge(h, 0.0, 0.1, s);
  EXPECT_DOUBLE_EQ(s.angle, 0.0);
  EXPECT_DOUBLE_EQ(s.velocity, 0.0);
  s = {0.0, 1.0};  // moving away from the stop is allowed
  msd::step_hinge(h, 0.0, 0.1, s);
  EXPECT_GT(s.angle, 0.0);
  EXPECT_NO_THROW(msd::check_hinge(h));
  h.axis = msd::Vec3::Zero();
  EXPECT_THROW(msd::check_hinge(h), msd::Error);
  h.axis = msd::Vec3::UnitX();
  h.max_angle = h.min_angle;
  EXPECT_THROW(msd::check_hinge(h), msd::Error);
  h.max_angle = 2.0;
  h.inertia = 0.0;
  EXPECT_THROW(msd::check_hinge(h), msd::Error);
}
