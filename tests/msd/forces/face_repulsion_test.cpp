#include "msd/forces/face_repulsion.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

TEST(FaceRepulsion, MagnitudeFollowsEquation51) {
  const double k = 2.0, x0 = 0.1, floor = 1e-9;
  EXPECT_NEAR(msd::face_repulsion_magnitude(x0, x0, k, floor), 0.0, 1e-15);
  EXPECT_NEAR(msd::face_repulsion_magnitude(0.05, x0, k, floor), k * (0.01 / 0.05 - 0.05), 1e-15);
  // Beyond the rest height it pulls back like a spring: f(x) < 0.
  EXPECT_LT(msd::face_repulsion_magnitude(0.15, x0, k, floor), 0.0);
}

TEST(FaceRepulsion, GrowsWithoutBoundTowardsThePlane) {
  const double k = 1.0, x0 = 1.0, floor = 1e-12;
  double previous = 0.0;
  for (double x = 1e-3; x > 1e-10; x /= 10) {
    const double f = msd::face_repulsion_magnitude(x, x0, k, floor);
    EXPECT_GT(f, previous);
    EXPECT_NEAR(f * x, 1.0, 1e-6);  // f ~ k x0^2 / x
    previous = f;
  }
  EXPECT_GT(previous, 1e8);
}

TEST(FaceRepulsion, TangentContinuationBelowFloorRestoresInvertedVertex) {
  const double k = 1.0, x0 = 1.0, floor = 0.01, xc = 0.01;
  const double fc = msd::face_repulsion_magnitude(xc, x0, k, floor);
  EXPECT_NEAR(fc, 100.0 - 0.01, 1e-12);
  // Continuous and still increasing through the plane and beyond.
  EXPECT_NEAR(msd::face_repulsion_magnitude(xc * (1 - 1e-12), x0, k, floor), fc, 1e-6);
  EXPECT_GT(msd::face_repulsion_magnitude(0.0, x0, k, floor), fc);
  EXPECT_GT(msd::face_repulsion_magnitude(-0.2, x0, k, floor), msd::face_repulsion_magnitude(0.0, x0, k, floor));
}

TEST(FaceRepulsion, HandComputedTetWithEqualisingForces) {
  // Right-corner tet; vertex 3 pushed from (0,0,1) to (0.25,0.25,0.5). Its face
  // (0,1,2) is the plane z = 0, x = 0.5, x0 = 1: f = k (1/0.5 - 0.5) = 1.5 k.
  // The projection P = (0.25, 0.25, 0) has barycentric weights 0.5, 0.25, 0.25
  // on vertices 0, 1, 2, which take -weight * R (eq. 5.3).
  const double k = 2.0;
  const Vec3 x[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.25, 0.25, 0.5)};
  const msd::TetFrame g = msd::tet_frame(x);
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  msd::add_balanced_normal_force(g, 3, msd::face_repulsion_magnitude(g.height[3], 1.0, k, 0.01), f);
  const Vec3 r(0, 0, 1.5 * k);
  EXPECT_NEAR((f[3] - r).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f[0] + 0.5 * r).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f[1] + 0.25 * r).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f[2] + 0.25 * r).norm(), 0.0, 1e-12);
}

TEST(FaceRepulsion, ZeroAtRestAndZeroNetForceAndTorque) {
  std::mt19937 rng(21);
  for (int k = 0; k < 300; ++k) {
    Vec3 rest[4], x[4];
    testing_support::random_tet(rng, rest, 0.02);
    const msd::TetFrame g0 = msd::tet_frame(rest);
    const double kr[4] = {1.0, 2.0, 3.0, 4.0};
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    msd::add_face_repulsion(g0, g0.height, kr, 0.01, f);
    for (const auto& fi : f) EXPECT_LT(fi.norm(), 1e-12);
    testing_support::random_tet(rng, x, 0.02);
    for (auto& fi : f) fi.setZero();
    msd::add_face_repulsion(msd::tet_frame(x), g0.height, kr, 0.01, f);
    Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
    double scale = 0.0;
    for (int i = 0; i < 4; ++i) {
      net += f[i];
      torque += x[i].cross(f[i]);
      scale += f[i].norm();
    }
    EXPECT_LT(net.norm(), 1e-12 * scale);
    EXPECT_LT(torque.norm(), 1e-12 * scale * 0.02);
  }
}

TEST(FaceRepulsion, ForcesAreMinusEnergyGradient) {
  std::mt19937 rng(22);
  for (int k = 0; k < 100; ++k) {
    Vec3 rest[4], x[4];
    testing_support::random_tet(rng, rest, 0.02);
    testing_support::random_tet(rng, x, 0.02);
    const double x0[4] = {msd::tet_frame(rest).height[0], msd::tet_frame(rest).height[1],
                          msd::tet_frame(rest).height[2], msd::tet_frame(rest).height[3]};
    const double kr[4] = {1.0, 0.5, 2.0, 1.5};
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    msd::add_face_repulsion(msd::tet_frame(x), x0, kr, 0.05, f);
    Vec3 grad[4];
    testing_support::fd_gradient(
        [&](const Vec3* y) { return msd::face_repulsion_energy(msd::tet_frame(y), x0, kr, 0.05); }, x, 1e-8,
        grad);
    double scale = 0.0;
    for (int i = 0; i < 4; ++i) scale = std::max(scale, f[i].norm());
    for (int i = 0; i < 4; ++i) EXPECT_NEAR((f[i] + grad[i]).norm(), 0.0, 1e-5 * scale) << i;
  }
}
