// Tests for msd/control/keyframes.hpp: piecewise-linear way-points.
#include "msd/control/keyframes.hpp"

#include "msd/core/types.hpp"

#include <gtest/gtest.h>

TEST(Keyframes, LinearBetweenHeldOutsideAndTheSlopeOfTheSegment) {
  msd::Keyframes<double> k;
  k.add(1.0, 0.0);
  k.add(2.0, 10.0);
  k.add(4.0, 0.0);
  EXPECT_EQ(k.at(0.0), 0.0);
  EXPECT_DOUBLE_EQ(k.at(1.5), 5.0);
  EXPECT_DOUBLE_EQ(k.at(3.0), 5.0);
  EXPECT_EQ(k.at(9.0), 0.0);
  EXPECT_DOUBLE_EQ(k.rate(1.5), 10.0);
  EXPECT_DOUBLE_EQ(k.rate(3.0), -5.0);
  EXPECT_EQ(k.rate(0.5), 0.0);
  EXPECT_EQ(k.rate(4.5), 0.0);
  msd::Keyframes<msd::Vec3> m;
  m.add(0.0, msd::Vec3::Zero());
  m.add(2.0, msd::Vec3(2, 0, -4));
  EXPECT_LT((m.at(1.0) - msd::Vec3(1, 0, -2)).norm(), 1e-15);
  EXPECT_LT((m.rate(1.0) - msd::Vec3(1, 0, -2)).norm(), 1e-15);
}

TEST(Keyframes, EmptyIsZeroAndOneWayPointIsHeld) {
  const msd::Keyframes<double> none;
  EXPECT_EQ(none.at(1.0), 0.0);
  EXPECT_EQ(none.rate(1.0), 0.0);
  msd::Keyframes<msd::Vec3> one;
  one.add(2.0, msd::Vec3(1, 2, 3));
  EXPECT_EQ(one.at(0.0), msd::Vec3(1, 2, 3));
  EXPECT_EQ(one.at(5.0), msd::Vec3(1, 2, 3));
  EXPECT_EQ(one.rate(2.0), msd::Vec3::Zero());
}

TEST(Keyframes, AtAWayPointIsItsValueAndTheRateIsTheNextSegments) {
  msd::Keyframes<double> k;
  k.add(0.0, 1.0);
  k.add(1.0, 3.0);
  k.add(3.0, -1.0);
  EXPECT_EQ(k.at(1.0), 3.0);
  EXPECT_EQ(k.rate(1.0), -2.0);  // [1, 3): slope -2
  EXPECT_EQ(k.rate(0.0), 2.0);
  EXPECT_EQ(k.rate(3.0), 0.0);   // from the last way-point on
}
