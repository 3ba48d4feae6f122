#include "msd/mesh/tet_mesh.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

using msd::Vec3;

namespace {

msd::TetMesh unit_tet() { return testing_support::corner_tet_mesh(1.0); }

}  // namespace

TEST(TetMesh, SignedVolumeAndOrientation) {
  const msd::TetMesh m = unit_tet();
  EXPECT_DOUBLE_EQ(msd::tet_signed_volume(m.nodes, m.tets[0]), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(msd::tet_signed_volume(m.nodes, msd::Tet{0, 2, 1, 3}), -1.0 / 6.0);
  EXPECT_EQ(msd::count_inverted(m.nodes, {{0, 1, 2, 3}, {0, 2, 1, 3}}), 1);
}

TEST(TetMesh, QualityIsOneForRegularAndZeroForFlat) {
  const Vec3 a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
  EXPECT_NEAR(msd::tet_quality(a, b, c, d), 1.0, 1e-12);
  EXPECT_NEAR(msd::tet_quality(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)), 0.0, 1e-12);
}

TEST(TetMesh, BoundaryFacesOfOneTetFaceOutwards) {
  const msd::TetMesh m = unit_tet();
  const auto faces = msd::boundary_faces(m.tets);
  ASSERT_EQ(faces.size(), 4u);
  const Vec3 centre = m.nodes.rowwise().mean();
  for (const auto& f : faces) {
    const Vec3 a = m.nodes.col(f[0]), b = m.nodes.col(f[1]), c = m.nodes.col(f[2]);
    EXPECT_GT((b - a).cross(c - a).dot(a - centre), 0.0);
  }
}

TEST(TetMesh, CheckRejectsInvertedTetBadIndexAndRegionCount) {
  msd::TetMesh m = unit_tet();
  EXPECT_NO_THROW(msd::check_tet_mesh(m, "m"));
  msd::TetMesh inverted = m;
  inverted.tets[0] = {0, 2, 1, 3};
  EXPECT_THROW(msd::check_tet_mesh(inverted, "m"), msd::Error);
  msd::TetMesh bad = m;
  bad.tets[0][3] = 4;
  EXPECT_THROW(msd::check_tet_mesh(bad, "m"), msd::Error);
  msd::TetMesh regions = m;
  regions.region.clear();
  EXPECT_THROW(msd::check_tet_mesh(regions, "m"), msd::Error);
}

TEST(TetMesh, FaceSharingHistogram) {
  msd::TetMesh m = unit_tet();
  m.nodes.conservativeResize(3, 5);
  m.nodes.col(4) = Vec3(1, 1, 1);
  m.tets.push_back({1, 2, 3, 4});  // shares face (1, 2, 3)
  if (msd::tet_signed_volume(m.nodes, m.tets[1]) < 0) std::swap(m.tets[1][2], m.tets[1][3]);
  const auto h = msd::face_sharing_histogram(m.tets);
  EXPECT_EQ(h[1], 6);
  EXPECT_EQ(h[2], 1);
}
