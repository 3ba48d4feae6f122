// The multi-region cubic approximation (thesis 4.5, figure 4.7): overlaps and
// contacts resolved by erosion with the thesis' priorities, a passive layer
// between internal regions and over the bones, and bone points where a bone
// vanished under the skin.
#include "msd/mesh/regions.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace {

msd::CubicGrid grid(int n) {
  msd::CubicGrid g;
  g.spacing = 0.01;
  g.nx = g.ny = g.nz = n;
  return g;
}

// Cubes with lo <= (i, j, k) < hi.
std::vector<char> box(const msd::CubicGrid& g, std::array<int, 3> lo, std::array<int, 3> hi) {
  std::vector<char> m(static_cast<size_t>(g.num_cubes()), 0);
  for (int k = lo[2]; k < hi[2]; ++k)
    for (int j = lo[1]; j < hi[1]; ++j)
      for (int i = lo[0]; i < hi[0]; ++i) m[static_cast<size_t>(g.cube_id(i, j, k))] = 1;
  return m;
}

std::vector<char> unite(std::vector<char> a, const std::vector<char>& b) {
  for (size_t i = 0; i < a.size(); ++i) a[i] = a[i] || b[i];
  return a;
}

}  // namespace

TEST(Regions, AThickBoneOverlappingAMuscleIsErodedFirst) {
  const auto g = grid(12);
  const auto skin = box(g, {0, 0, 0}, {12, 12, 12});
  const auto muscle = box(g, {2, 2, 2}, {7, 10, 10});
  const auto bone = box(g, {5, 2, 2}, {10, 10, 10});  // overlaps the muscle at i = 5, 6; five cubes thick
  const auto r = msd::label_regions(g, skin, {{msd::kFrontMuscle, muscle}, {msd::kUpperBone, bone}});
  EXPECT_EQ(msd::separation_fault(g, r.label), "");
  // The muscle keeps every cube; the bone loses the overlap and one more layer.
  EXPECT_EQ(r.cubes_after.at(msd::kFrontMuscle), r.cubes_before.at(msd::kFrontMuscle));
  EXPECT_EQ(r.cubes_after.at(msd::kUpperBone), 2 * 8 * 8);
  EXPECT_EQ(r.label[static_cast<size_t>(g.cube_id(7, 5, 5))], msd::kPassiveTissue);
  EXPECT_EQ(r.label[static_cast<size_t>(g.cube_id(8, 5, 5))], msd::kUpperBone);
  EXPECT_TRUE(r.bone_points.empty());
}

TEST(Regions, WhereTheBoneIsOneCubeThickTheMuscleGivesWay) {
  const auto g = grid(12);
  const auto skin = box(g, {0, 0, 0}, {12, 12, 12});
  const auto bone = box(g, {6, 2, 2}, {7, 10, 10});      // a plate one cube thick
  const auto muscle = box(g, {2, 2, 2}, {6, 10, 10});    // touching it face to face
  const auto r = msd::label_regions(g, skin, {{msd::kBackMuscle, muscle}, {msd::kLowerBone, bone}});
  EXPECT_EQ(msd::separation_fault(g, r.label), "");
  EXPECT_EQ(r.cubes_after.at(msd::kLowerBone), 8 * 8);
  EXPECT_EQ(r.cubes_after.at(msd::kBackMuscle), 3 * 8 * 8);
  EXPECT_EQ(r.eroded_muscle_cubes, 8 * 8);
  EXPECT_EQ(r.eroded_bone_cubes, 0);
}

TEST(Regions, BoneUnderTheSkinIsErodedAndLeavesBonePoints) {
  const auto g = grid(10);
  const auto skin = box(g, {1, 1, 1}, {9, 9, 9});
  // The lower bone: a rod in the middle and, separately, a 4 x 4 plate one cube
  // under the skin (the thesis' foot).
  const auto plate = box(g, {3, 3, 1}, {7, 7, 2});
  const auto bone = unite(box(g, {3, 5, 5}, {7, 6, 6}), plate);
  const auto r = msd::label_regions(g, skin, {{msd::kLowerBone, bone}});
  EXPECT_EQ(msd::separation_fault(g, r.label), "");
  EXPECT_EQ(r.cubes_after.at(msd::kLowerBone), 4);  // the rod
  EXPECT_EQ(r.eroded_bone_cubes, 16);
  // Every node of the vanished plate is a bone point of the lower bone.
  ASSERT_EQ(r.bone_points.size(), 5u * 5u * 2u);
  std::set<long> expected;
  for (int k = 1; k <= 2; ++k)
    for (int j = 3; j <= 7; ++j)
      for (int i = 3; i <= 7; ++i) expected.insert(g.node_id(i, j, k));
  for (const auto& p : r.bone_points) {
    EXPECT_EQ(p.region, msd::kLowerBone);
    EXPECT_TRUE(expected.count(p.grid_node)) << p.grid_node;
  }
}

TEST(Regions, TouchingMusclesArePartedAndTheSmallerKeepsItsCubes) {
  const auto g = grid(12);
  const auto skin = box(g, {0, 0, 0}, {12, 12, 12});
  const auto front = box(g, {2, 2, 2}, {5, 5, 5});   // 27 cubes
  const auto back = box(g, {5, 2, 2}, {10, 10, 10}); // 320 cubes, touching
  const auto r = msd::label_regions(g, skin, {{msd::kFrontMuscle, front}, {msd::kBackMuscle, back}});
  EXPECT_EQ(msd::separation_fault(g, r.label), "");
  EXPECT_EQ(r.cubes_after.at(msd::kFrontMuscle), 27);
  EXPECT_LT(r.cubes_after.at(msd::kBackMuscle), 320);
}

TEST(Regions, RandomLayoutsAlwaysEndSeparated) {
  std::mt19937 rng(5);
  const auto g = grid(14);
  std::uniform_int_distribution<int> lo(0, 9), len(1, 6);
  for (int trial = 0; trial < 40; ++trial) {
    auto random_box = [&] {
      std::array<int, 3> a{}, b{};
      for (int d = 0; d < 3; ++d) {
        a[static_cast<size_t>(d)] = lo(rng);
        b[static_cast<size_t>(d)] = std::min(14, a[static_cast<size_t>(d)] + len(rng));
      }
      return box(g, a, b);
    };
    const auto skin = unite(box(g, {1, 1, 1}, {13, 13, 13}), random_box());
    const auto r = msd::label_regions(g, skin, {{msd::kFrontMuscle, random_box()}, {msd::kBackMuscle, random_box()},
                                                {msd::kUpperBone, random_box()}, {msd::kLowerBone, random_box()}});
    ASSERT_EQ(msd::separation_fault(g, r.label), "") << "trial " << trial;
    // Bone points are tissue nodes that no muscle or other bone uses.
    for (const auto& p : r.bone_points) {
      const int i = static_cast<int>(p.grid_node % (g.nx + 1)), j = static_cast<int>((p.grid_node / (g.nx + 1)) % (g.ny + 1)),
                k = static_cast<int>(p.grid_node / (static_cast<long>(g.nx + 1) * (g.ny + 1)));
      bool tissue = false;
      for (int c = 0; c < 8; ++c) {
        const int ci = i - (c & 1), cj = j - ((c >> 1) & 1), ck = k - ((c >> 2) & 1);
        if (ci < 0 || cj < 0 || ck < 0 || ci >= g.nx || cj >= g.ny || ck >= g.nz) continue;
        const int l = r.label[static_cast<size_t>(g.cube_id(ci, cj, ck))];
        tissue |= l >= 0;
        EXPECT_FALSE(l >= msd::kFrontMuscle && l != p.region) << "trial " << trial;
      }
      EXPECT_TRUE(tissue);
    }
  }
}

TEST(Regions, BadInputIsNamed) {
  const auto g = grid(4);
  const auto skin = box(g, {0, 0, 0}, {4, 4, 4});
  EXPECT_THROW(msd::label_regions(g, std::vector<char>(3, 1), {}), msd::Error);
  EXPECT_THROW(msd::label_regions(g, box(g, {0, 0, 0}, {0, 0, 0}), {}), msd::Error);
  EXPECT_THROW(msd::label_regions(g, skin, {{msd::kUpperBone, skin}, {msd::kUpperBone, skin}}), msd::Error);
  EXPECT_THROW(msd::label_regions(g, skin, {{msd::kPassiveTissue, skin}}), msd::Error);
  EXPECT_THROW(msd::label_regions(g, skin, {{msd::kFrontMuscle, std::vector<char>(5, 1)}}), msd::Error);
}
