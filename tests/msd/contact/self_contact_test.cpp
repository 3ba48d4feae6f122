// Skin against skin: the bounding-volume hierarchy finds exactly the boxes a
// point is in; a node pushed into the other side's tets is put back on that
// side's surface along the face normal with its velocity removed, nodes that
// do not penetrate are untouched, and only the region's nodes are tested.
#include "msd/contact/self_contact.hpp"

#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

#include <random>

namespace {

// Two 4 x 4 x 2 cm blocks, one above the other with a 1 cm gap (the thigh's
// back and the calf's back behind a bent knee), in one tet mesh.
msd::TetMesh two_blocks() {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  const msd::TetMesh lower =
      msd::mesh_closed_surface(msd::make_box({0, 0, 0}, {0.04, 0.04, 0.02}), o, "lower").mesh;
  const msd::TetMesh upper =
      msd::mesh_closed_surface(msd::make_box({0, 0, 0.03}, {0.04, 0.04, 0.05}), o, "upper").mesh;
  msd::TetMesh m = lower;
  const int offset = lower.num_nodes();
  m.nodes.conservativeResize(3, offset + upper.num_nodes());
  m.nodes.rightCols(upper.num_nodes()) = upper.nodes;
  for (msd::Tet t : upper.tets) {
    for (int& v : t) v += offset;
    m.tets.push_back(t);
    m.region.push_back(0);
  }
  return m;
}

int node_at(const msd::TetMesh& m, const msd::Vec3& p) {
  for (int i = 0; i < m.num_nodes(); ++i)
    if ((m.nodes.col(i) - p).norm() < 1e-9) return i;
  return -1;
}

}  // namespace

TEST(AabbTree, FindsExactlyTheBoxesThatContainThePoint) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 500;
  msd::Points lo(3, n), hi(3, n);
  for (int b = 0; b < n; ++b) {
    const msd::Vec3 c(u(rng), u(rng), u(rng)), half = 0.05 * msd::Vec3(u(rng), u(rng), u(rng));
    lo.col(b) = c - half;
    hi.col(b) = c + half;
  }
  const msd::AabbTree tree(lo, hi);
  std::vector<int> found;
  for (int q = 0; q < 200; ++q) {
    const msd::Vec3 p(u(rng), u(rng), u(rng));
    tree.query(p, found);
    std::sort(found.begin(), found.end());
    std::vector<int> expected;
    for (int b = 0; b < n; ++b)
      if ((p.array() >= lo.col(b).array()).all() && (p.array() <= hi.col(b).array()).all()) expected.push_back(b);
    EXPECT_EQ(found, expected);
  }
}

TEST(SelfContact, PenetratingNodeReturnsToTheOtherSidesSurfaceAndStops) {
  const msd::TetMesh m = two_blocks();
  const msd::SelfContactRegion r = msd::make_self_contact_region(m, "behind_knee", msd::Vec3(-1, -1, -1),
                                                                 msd::Vec3(1, 1, 1), msd::Vec3(0, 0, 0.025),
                                                                 msd::Vec3::UnitZ());
  EXPECT_FALSE(r.nodes[0].empty());
  EXPECT_FALSE(r.nodes[1].empty());
  msd::Points x = m.nodes, v = msd::Points::Zero(3, m.num_nodes());
  // At rest: no contact, nothing moves.
  msd::SelfContactReport rep = msd::resolve_self_contact(r, m.tets, x, v);
  EXPECT_EQ(rep.contacts, 0);
  EXPECT_EQ(x, m.nodes);
  // The upper block's bottom-face node at (0.02, 0.02, 0.03) driven 4 mm into
  // the lower block (top face z = 0.02), moving down.
  const int node = node_at(m, {0.02, 0.02, 0.03});
  ASSERT_GE(node, 0);
  x(2, node) = 0.016;
  v.col(node) = msd::Vec3(0.1, 0, -1.0);
  rep = msd::resolve_self_contact(r, m.tets, x, v);
  EXPECT_EQ(rep.contacts, 1);
  EXPECT_NEAR(rep.max_depth, 0.004, 1e-12);
  EXPECT_NEAR(x(2, node), 0.02, 1e-12);  // on the lower block's top face
  EXPECT_NEAR(x(0, node), 0.02, 1e-12);  // along the face's normal only
  EXPECT_EQ(v.col(node), msd::Vec3::Zero());
  // A third of the area of its 4-8 surface triangles (1 cm grid, half a square
  // centimetre each, stretched by the move).
  EXPECT_GT(rep.area, 4 * 0.5e-4 / 3.0);
  EXPECT_LT(rep.area, 8 * 0.5e-4 * 1.5 / 3.0);
  // A node that may not move (a bone's, say) stays where it is; the lower
  // block's node that its tets now engulf is the one pushed out instead.
  x = m.nodes;
  x(2, node) = 0.016;
  std::vector<char> held(static_cast<size_t>(m.num_nodes()), 0);
  held[static_cast<size_t>(node)] = 1;
  rep = msd::resolve_self_contact(r, m.tets, x, v, held);
  EXPECT_NEAR(x(2, node), 0.016, 1e-15);
  const int below = node_at(m, {0.02, 0.02, 0.02});
  ASSERT_GE(below, 0);
  EXPECT_EQ(rep.contacts, 1);
  EXPECT_NE(x.col(below), m.nodes.col(below));
  EXPECT_EQ(v.col(below), msd::Vec3::Zero());
}

TEST(SelfContact, OnlyTheRegionIsTestedAndEmptySidesAreNamed) {
  const msd::TetMesh m = two_blocks();
  // A region covering only the left half (x < 0.02): a node at x = 0.04 is not tested.
  const msd::SelfContactRegion r = msd::make_self_contact_region(m, "left", msd::Vec3(-1, -1, -1),
                                                                 msd::Vec3(0.0199, 1, 1), msd::Vec3(0, 0, 0.025),
                                                                 msd::Vec3::UnitZ());
  msd::Points x = m.nodes, v = msd::Points::Zero(3, m.num_nodes());
  const int far = node_at(m, {0.04, 0.04, 0.03});
  ASSERT_GE(far, 0);
  x(2, far) = 0.015;
  EXPECT_EQ(msd::resolve_self_contact(r, m.tets, x, v).contacts, 0);
  EXPECT_EQ(x(2, far), 0.015);
  // A split plane above everything leaves side 0 without faces.
  try {
    msd::make_self_contact_region(m, "behind_knee", msd::Vec3(-1, -1, -1), msd::Vec3(1, 1, 1), msd::Vec3(0, 0, 2),
                                  msd::Vec3::UnitZ());
    FAIL() << "no error";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("self contact 'behind_knee': side 0"), std::string::npos) << e.what();
  }
}

TEST(SelfContact, ADeeperThanAllowedContactIsCountedAndLeftAlone) {
  const msd::TetMesh m = two_blocks();
  msd::SelfContactRegion r = msd::make_self_contact_region(m, "behind_knee", msd::Vec3(-1, -1, -1),
                                                           msd::Vec3(1, 1, 1), msd::Vec3(0, 0, 0.025),
                                                           msd::Vec3::UnitZ());
  r.max_correction = 0.003;
  msd::Points x = m.nodes, v = msd::Points::Zero(3, m.num_nodes());
  const int node = node_at(m, {0.02, 0.02, 0.03});
  ASSERT_GE(node, 0);
  x(2, node) = 0.016;  // 4 mm in: deeper than 3 mm
  const msd::SelfContactReport rep = msd::resolve_self_contact(r, m.tets, x, v);
  EXPECT_EQ(rep.too_deep, 1);
  EXPECT_EQ(x(2, node), 0.016);  // left where it is
  // (The lower block's node now inside the upper block's stretched tets is
  // shallow, and is put back as before.)
  EXPECT_LE(rep.contacts, 1);
  EXPECT_LE(rep.max_depth, 0.003);
}

TEST(SelfContact, ANodeInsideItsNeighboursTetsAtAFoldIsNotAContact) {
  // One 4 cm block split in two at z = 2 cm: a node of the upper side's
  // surface pushed 1.1 cm down lies inside a lower-side tet that touches its
  // own neighbours - a fold, not skin through skin.
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  const msd::TetMesh m = msd::mesh_closed_surface(msd::make_box({0, 0, 0}, {0.04, 0.04, 0.04}), o, "block").mesh;
  msd::SelfContactRegion r = msd::make_self_contact_region(m, "fold", msd::Vec3(-1, -1, -1), msd::Vec3(1, 1, 1),
                                                           msd::Vec3(0, 0, 0.02), msd::Vec3::UnitZ());
  const int node = node_at(m, {0.0, 0.02, 0.03});
  ASSERT_GE(node, 0);
  msd::Points x = m.nodes, v = msd::Points::Zero(3, m.num_nodes());
  x(0, node) = 0.001;
  x(2, node) = 0.019;
  EXPECT_EQ(msd::resolve_self_contact(r, m.tets, x, v).contacts, 0);
  EXPECT_EQ(x(2, node), 0.019);
  // The same fold without the neighbourhood rule counts as contact.
  for (auto& ring : r.ring) ring.clear();
  EXPECT_GE(msd::resolve_self_contact(r, m.tets, x, v).contacts, 1);
}
