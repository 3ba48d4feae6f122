// Tendon strands through the grid: each strand runs from its own muscle node,
// spread over the muscle end, through tissue nodes near the path, to a node of
// the bone; bad tendons are named.
#include "msd/mesh/tendon_paths.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace {

const msd::LimbMesh& mesh() {
  static const msd::LimbMesh m = [] {
    msd::LimbMeshOptions o;
    o.spacing = 0.01;
    return msd::mesh_limb(testing_support::cylinder_limb(), o);
  }();
  return m;
}

// The back muscle's lower end to the lower bone's top, behind the knee gap.
msd::TendonPathSpec hamstring_tendon(int strands) {
  msd::TendonPathSpec t;
  t.name = "hamstrings to lower bone";
  t.muscle = msd::kBackMuscle;
  t.bone = msd::kLowerBone;
  t.path = {{0, -0.03, 0.17}, {0, -0.03, 0.14}, {0, -0.012, 0.13}};
  t.strands = strands;
  return t;
}

std::set<int> region_nodes(const msd::LimbMesh& m, int region) {
  std::set<int> s;
  for (size_t e = 0; e < m.mesh.tets.size(); ++e)
    if (m.mesh.region[e] == region) s.insert(m.mesh.tets[e].begin(), m.mesh.tets[e].end());
  return s;
}

}  // namespace

TEST(TendonPaths, StrandsSpreadOverTheMuscleEndAndEndOnTheBone) {
  const msd::LimbMesh& m = mesh();
  const msd::TendonStrands t = msd::route_tendon(m, hamstring_tendon(6));
  ASSERT_EQ(t.strands.size(), 6u);
  const auto muscle = region_nodes(m, msd::kBackMuscle), bone = region_nodes(m, msd::kLowerBone);
  std::set<int> starts;
  for (const auto& s : t.strands) {
    ASSERT_GE(s.size(), 2u);
    EXPECT_TRUE(muscle.count(s.front()));
    EXPECT_TRUE(bone.count(s.back()));
    starts.insert(s.front());
    for (size_t k = 1; k < s.size(); ++k) {
      EXPECT_NE(s[k], s[k - 1]);
      if (k + 1 < s.size()) {  // inner nodes slide through tissue: neither muscle nor bone
        EXPECT_FALSE(muscle.count(s[k]));
        EXPECT_FALSE(bone.count(s[k]));
      }
    }
    // Every strand follows the path: its nodes stay within two cubes of it.
    for (int v : s) EXPECT_LT(std::abs(m.mesh.nodes(0, v)), 0.03);
  }
  EXPECT_EQ(starts.size(), 6u) << "each strand has its own muscle node";
  // Spread: no two starts closer than one grid spacing.
  for (int a : starts)
    for (int b : starts)
      if (a != b) {
        EXPECT_GE((m.mesh.nodes.col(a) - m.mesh.nodes.col(b)).norm(), m.grid.spacing - 1e-12);
      }
  // The strand from the nearest muscle node goes through the tissue below the
  // muscle (the path runs 3 cm down before it turns to the bone).
  EXPECT_GE(t.strands.front().size(), 3u);
}

TEST(TendonPaths, OneStrandStartsAtTheMuscleNodeNearestThePath) {
  const msd::LimbMesh& m = mesh();
  const msd::TendonStrands t = msd::route_tendon(m, hamstring_tendon(1));
  ASSERT_EQ(t.strands.size(), 1u);
  double best = 1e9;
  for (int v : region_nodes(m, msd::kBackMuscle)) best = std::min(best, (m.mesh.nodes.col(v) - msd::Vec3(0, -0.03, 0.17)).norm());
  EXPECT_NEAR((m.mesh.nodes.col(t.strands[0].front()) - msd::Vec3(0, -0.03, 0.17)).norm(), best, 1e-12);
}

TEST(TendonPaths, BadTendonsAreNamed) {
  const msd::LimbMesh& m = mesh();
  auto message = [&](const msd::TendonPathSpec& t) -> std::string {
    try {
      msd::route_tendon(m, t);
    } catch (const msd::Error& e) {
      return e.what();
    }
    return "";
  };
  auto t = hamstring_tendon(6);
  t.path.resize(1);
  EXPECT_NE(message(t).find("tendon 'hamstrings to lower bone': the path needs at least two points"), std::string::npos);
  t = hamstring_tendon(0);
  EXPECT_NE(message(t).find("strands must be at least 1"), std::string::npos);
  t = hamstring_tendon(500);
  EXPECT_NE(message(t).find("for 500 strands"), std::string::npos) << message(t);
  t = hamstring_tendon(6);
  t.bone = msd::kFrontMuscle;
  EXPECT_NE(message(t).find("is not a bone"), std::string::npos);
  // A mesh without the muscle.
  msd::LimbSurfaces s = testing_support::cylinder_limb();
  s.inner.erase(msd::kBackMuscle);
  msd::LimbMeshOptions o;
  o.spacing = 0.01;
  EXPECT_THROW(msd::route_tendon(msd::mesh_limb(s, o), hamstring_tendon(6)), msd::Error);
}

TEST(TendonPaths, EndsMustLieOnTheirMuscleAndBone) {
  msd::LimbSurfaces s = testing_support::cylinder_limb();
  s.source[msd::kBackMuscle] = "hamstrings.obj";
  s.source[msd::kLowerBone] = "tibia.stl";
  auto message = [&](const msd::TendonPathSpec& t) -> std::string {
    try {
      msd::validate_tendon_ends(s, t, 0.005);
    } catch (const msd::Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message(hamstring_tendon(6)), "");
  // Drawn the wrong way round: the first point is at the bone.
  auto t = hamstring_tendon(6);
  std::reverse(t.path.begin(), t.path.end());
  EXPECT_NE(message(t).find("tendon 'hamstrings to lower bone': its first (muscle) point (0, -0.012, 0.13) is not in "
                            "back_muscle (hamstrings.obj)"),
            std::string::npos)
      << message(t);
  // Ending in the passive tissue, 2 cm from the bone.
  t = hamstring_tendon(6);
  t.path.back() = msd::Vec3(0, -0.035, 0.13);
  EXPECT_NE(message(t).find("its last (bone) point"), std::string::npos) << message(t);
  EXPECT_NE(message(t).find("lower_bone (tibia.stl)"), std::string::npos);
  // Within the tolerance is accepted.
  t.path.back() = msd::Vec3(0, -0.015, 0.13);
  EXPECT_EQ(message(t), "");
  // A limb without that muscle.
  s.inner.erase(msd::kBackMuscle);
  EXPECT_NE(message(hamstring_tendon(6)).find("the limb has no back_muscle"), std::string::npos);
}
