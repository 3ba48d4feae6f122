#include "msd/forces/edge_dampers.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

namespace {
const Vec3 kX[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
const double kKd[6] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5};

void forces(const Vec3 v[4], Vec3 f[4]) {
  for (int i = 0; i < 4; ++i) f[i].setZero();
  msd::add_edge_dampers(msd::edge_frame(kX), v, kKd, f);
}
}  // namespace

TEST(EdgeDampers, HandComputedSeparation) {
  // Vertex 1 moves away from vertex 0 along their edge at 2 m/s: the damper on
  // edge (0,1) pulls vertex 0 along +x with k_d * 2 = 1 N; edges (1,2), (1,3)
  // lengthen at 2 / sqrt(2) m/s.
  const Vec3 v[4] = {Vec3::Zero(), Vec3(2, 0, 0), Vec3::Zero(), Vec3::Zero()};
  Vec3 f[4];
  forces(v, f);
  EXPECT_NEAR((f[0] - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
  const Vec3 f2 = 0.5 * (2 / std::sqrt(2.0)) * Vec3(1, -1, 0) / std::sqrt(2.0);
  EXPECT_NEAR((f[2] - f2).norm(), 0.0, 1e-12);
}

TEST(EdgeDampers, NoForceOnRigidMotionAndDissipative) {
  const Vec3 trans[4] = {Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)};
  Vec3 f[4];
  forces(trans, f);
  for (const auto& fi : f) EXPECT_LT(fi.norm(), 1e-15);
  const Vec3 w(0.3, -0.2, 0.9);  // rigid rotation v = w x x
  Vec3 rot[4];
  for (int i = 0; i < 4; ++i) rot[i] = w.cross(kX[i]);
  forces(rot, f);
  for (const auto& fi : f) EXPECT_LT(fi.norm(), 1e-15);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 50; ++k) {
    Vec3 v[4];
    for (auto& vi : v) vi = Vec3(u(rng), u(rng), u(rng));
    forces(v, f);
    double power = 0.0;
    for (int i = 0; i < 4; ++i) power += f[i].dot(v[i]);
    EXPECT_LE(power, 1e-15);
  }
}
