#include "msd/forces/edge_springs.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

using msd::Vec3;

namespace {
const Vec3 kRest[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};

void rest_lengths(const Vec3 x[4], double r[6]) {
  for (int e = 0; e < 6; ++e) r[e] = (x[msd::kTetEdges[e][1]] - x[msd::kTetEdges[e][0]]).norm();
}
}  // namespace

TEST(EdgeSprings, ZeroAtRest) {
  double r[6], ks[6] = {1, 2, 3, 4, 5, 6};
  rest_lengths(kRest, r);
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  msd::add_edge_springs(msd::edge_frame(kRest), r, ks, f);
  for (const auto& fi : f) EXPECT_EQ(fi.norm(), 0.0);
}

TEST(EdgeSprings, HandComputedStretch) {
  // Vertex 1 moved from (1,0,0) to (1.2,0,0): edge (0,1) stretched by 0.2,
  // edges (1,2) and (1,3) from sqrt(2) to sqrt(1.44 + 1).
  double r[6], ks[6] = {10, 10, 10, 10, 10, 10};
  rest_lengths(kRest, r);
  Vec3 x[4] = {kRest[0], Vec3(1.2, 0, 0), kRest[2], kRest[3]};
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  msd::add_edge_springs(msd::edge_frame(x), r, ks, f);
  // Vertex 0 is pulled towards vertex 1 by k * 0.2 = 2 N.
  EXPECT_NEAR((f[0] - Vec3(2, 0, 0)).norm(), 0.0, 1e-12);
  // Vertex 2: spring (1,2) stretched by d = sqrt(2.44) - sqrt(2), along (1.2,-1,0)/len.
  const double len = std::sqrt(2.44), d = len - std::sqrt(2.0);
  const Vec3 f2 = 10 * d * Vec3(1.2, -1, 0) / len;
  EXPECT_NEAR((f[2] - f2).norm(), 0.0, 1e-12);
  Vec3 net = f[0] + f[1] + f[2] + f[3];
  EXPECT_LT(net.norm(), 1e-12);
}

TEST(EdgeSprings, ForcesAreMinusEnergyGradient) {
  std::mt19937 rng(11);
  for (int k = 0; k < 100; ++k) {
    Vec3 rest[4], x[4];
    testing_support::random_tet(rng, rest, 0.02);
    testing_support::random_tet(rng, x, 0.02);
    double r[6], ks[6];
    rest_lengths(rest, r);
    for (int e = 0; e < 6; ++e) ks[e] = 1.0 + e;
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    msd::add_edge_springs(msd::edge_frame(x), r, ks, f);
    Vec3 grad[4];
    testing_support::fd_gradient([&](const Vec3* y) { return msd::edge_spring_energy(y, r, ks); }, x, 1e-7, grad);
    double scale = 0.0;
    for (int i = 0; i < 4; ++i) scale = std::max(scale, f[i].norm());
    for (int i = 0; i < 4; ++i) EXPECT_NEAR((f[i] + grad[i]).norm(), 0.0, 1e-6 * scale) << i;
  }
}
