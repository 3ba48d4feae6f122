#include "msd/forces/tet_frame.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

TEST(TetFrame, HeightsAreSignedDistancesToOppositeFaces) {
  std::mt19937 rng(3);
  for (int k = 0; k < 200; ++k) {
    Vec3 x[4];
    testing_support::random_tet(rng, x);
    const msd::TetFrame g = msd::tet_frame(x);
    EXPECT_NEAR(g.volume, msd::tet_signed_volume(x[0], x[1], x[2], x[3]), 1e-14);
    for (int i = 0; i < 4; ++i) {
      const Vec3& a = x[(i + 1) % 4];
      const Vec3& b = x[(i + 2) % 4];
      const Vec3& c = x[(i + 3) % 4];
      Vec3 n = (b - a).cross(c - a).normalized();
      if (n.dot(x[i] - a) < 0) n = -n;  // towards vertex i
      EXPECT_NEAR(g.height[i], n.dot(x[i] - a), 1e-12);
      EXPECT_NEAR((g.m[i] * g.inv_norm[i] - n).norm(), 0.0, 1e-12);
    }
  }
}

TEST(TetFrame, ProjectionWeightsReproduceTheProjectedPoint) {
  std::mt19937 rng(4);
  for (int k = 0; k < 200; ++k) {
    Vec3 x[4];
    testing_support::random_tet(rng, x);
    const msd::TetFrame g = msd::tet_frame(x);
    for (int i = 0; i < 4; ++i) {
      Vec3 p = Vec3::Zero();
      double sum = 0.0;
      for (int j = 0; j < 4; ++j)
        if (j != i) {
          p += msd::projection_weight(g, i, j) * x[j];
          sum += msd::projection_weight(g, i, j);
        }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      const Vec3 expected = x[i] - g.height[i] * g.inv_norm[i] * g.m[i];
      EXPECT_NEAR((p - expected).norm(), 0.0, 1e-12);
    }
  }
}

TEST(TetFrame, InvertedTetHasNegativeHeights) {
  Vec3 x[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -0.5)};
  const msd::TetFrame g = msd::tet_frame(x);
  EXPECT_LT(g.volume, 0.0);
  for (double h : g.height) EXPECT_LT(h, 0.0);
  EXPECT_NEAR(g.height[3], -0.5, 1e-15);
}

TEST(TetFrame, BalancedForcesHaveZeroNetForceAndTorque) {
  std::mt19937 rng(5);
  for (int k = 0; k < 500; ++k) {
    Vec3 x[4];
    testing_support::random_tet(rng, x, 0.03);
    const msd::TetFrame g = msd::tet_frame(x);
    const double mag[4] = {1.3, -0.7, 2.1, 0.4};
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    msd::add_balanced_normal_forces(g, mag, f);
    Vec3 single[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    for (int i = 0; i < 4; ++i) msd::add_balanced_normal_force(g, i, mag[i], single);
    Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
    double scale = 0.0;
    for (int i = 0; i < 4; ++i) {
      net += f[i];
      torque += x[i].cross(f[i]);
      scale += f[i].norm();
      EXPECT_NEAR((f[i] - single[i]).norm(), 0.0, 1e-12 * scale + 1e-15);
    }
    EXPECT_LT(net.norm(), 1e-12 * scale);
    EXPECT_LT(torque.norm(), 1e-12 * scale * 0.03);
  }
}
