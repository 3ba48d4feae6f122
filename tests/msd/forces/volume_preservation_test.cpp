#include "msd/forces/volume_preservation.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

TEST(VolumePreservation, MagnitudeFollowsEquation55) {
  // Right-corner tet with vertex 3 at height 0.5 over face (0,1,2) of area 1/2:
  // V0 = 1/6, required height 3 V0 / A = 1, so V_3 = k_v (1 - 0.5) along +z.
  const Vec3 x[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.1, 0.1, 0.5)};
  const msd::TetFrame g = msd::tet_frame(x);
  EXPECT_NEAR(msd::volume_force_magnitude(g, 3, 1.0 / 6.0, 4.0), 4.0 * 0.5, 1e-12);
}

TEST(VolumePreservation, ZeroWheneverVolumeIsAtRest) {
  // Sliding a vertex parallel to its opposite face keeps the volume: no force.
  const Vec3 rest[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  const double v0 = 1.0 / 6.0, kv[4] = {1, 1, 1, 1};
  for (double s : {0.0, 0.3, -0.7}) {
    const Vec3 x[4] = {rest[0], rest[1], rest[2], Vec3(s, 0.5 * s, 1)};
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    msd::add_volume_preservation(msd::tet_frame(x), v0, kv, f);
    for (const auto& fi : f) EXPECT_LT(fi.norm(), 1e-14);
  }
}

TEST(VolumePreservation, ZeroNetForceAndTorqueOnRandomTets) {
  std::mt19937 rng(31);
  for (int k = 0; k < 300; ++k) {
    Vec3 x[4];
    testing_support::random_tet(rng, x, 0.02);
    const double kv[4] = {2.0, 1.0, 3.0, 0.5};
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    const msd::TetFrame g = msd::tet_frame(x);
    msd::add_volume_preservation(g, 1.7 * g.volume, kv, f);
    Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
    double scale = 0.0;
    for (int i = 0; i < 4; ++i) {
      net += f[i];
      torque += x[i].cross(f[i]);
      scale += f[i].norm();
    }
    EXPECT_GT(scale, 0.0);
    EXPECT_LT(net.norm(), 1e-12 * scale);
    EXPECT_LT(torque.norm(), 1e-12 * scale * 0.02);
  }
}

TEST(VolumePreservation, CompressedTetIsPushedApartAndInvertedTetBack) {
  const double kv[4] = {1, 1, 1, 1};
  for (double z : {0.4, -0.3}) {
    const Vec3 x[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, z)};
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    msd::add_volume_preservation(msd::tet_frame(x), 1.0 / 6.0, kv, f);
    EXPECT_GT(f[3].z(), 0.0) << z;
    // Work done along the volume gradient increases the volume.
    const msd::TetFrame g = msd::tet_frame(x);
    double dv = 0.0;
    for (int i = 0; i < 4; ++i) dv += f[i].dot(g.m[i]);
    EXPECT_GT(dv, 0.0);
  }
}
