// A limb from surfaces: validation names the region and the fault; the mesh
// carries all five regions kept apart, bone points on the mesh, the grid's
// orientation as an option, and every surface embedded.
#include "msd/mesh/limb_mesher.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

msd::TriangleMesh moved(msd::TriangleMesh m, const msd::Vec3& by) {
  m.vertices.colwise() += by;
  return m;
}

msd::LimbSurfaces limb() {
  msd::LimbSurfaces s = testing_support::cylinder_limb();
  s.source[msd::kPassiveTissue] = "skin.obj";
  s.source[msd::kUpperBone] = "femur.stl";
  return s;
}

std::string error_of(const msd::LimbSurfaces& s) {
  try {
    msd::validate_limb(s);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(LimbMesher, AllRegionsMeshApartAndEverySurfaceIsEmbedded) {
  const msd::LimbSurfaces s = limb();
  msd::LimbMeshOptions o;
  o.spacing = 0.01;
  const msd::LimbMesh m = msd::mesh_limb(s, o);
  EXPECT_EQ(m.mesh.num_tets(), 5 * m.cubes);
  for (int r : {msd::kPassiveTissue, msd::kFrontMuscle, msd::kBackMuscle, msd::kUpperBone, msd::kLowerBone})
    EXPECT_GT(m.tets_by_region.count(r) ? m.tets_by_region.at(r) : 0, 0) << msd::region_name(r);
  EXPECT_EQ(msd::separation_fault(m.grid, m.labels.label), "");
  EXPECT_GT(msd::min_quality(m.mesh), 0.8);
  // The lower bone reaches within one cube of the skin's end: it is eroded there.
  EXPECT_GT(m.labels.eroded_bone_cubes, 0);
  for (const auto& [node, region] : m.bone_points) {
    ASSERT_GE(node, 0);
    ASSERT_LT(node, m.mesh.num_nodes());
    EXPECT_TRUE(msd::is_bone(region));
  }
  // Every surface is embedded and reproduced at rest.
  ASSERT_EQ(m.embedded.size(), 5u);
  for (const auto& [r, e] : m.embedded) {
    const msd::TriangleMesh& surface = r == msd::kPassiveTissue ? s.skin : s.inner.at(r);
    msd::Points x;
    msd::embedded_positions(m.mesh.nodes, m.mesh.tets, e, x);
    EXPECT_LT((x - surface.vertices).cwiseAbs().maxCoeff(), 1e-12) << msd::region_name(r);
    EXPECT_LE(e.outside, surface.num_vertices());
  }
  // The internal surfaces lie inside the tissue: none of their vertices is
  // more than a cube's diagonal from a tet.
  for (int r : {msd::kFrontMuscle, msd::kUpperBone})
    EXPECT_LT(m.embedded.at(r).max_outside_distance, 0.01 * std::sqrt(3.0));
}

TEST(LimbMesher, GridOrientationIsAnOption) {
  msd::LimbMeshOptions o;
  o.spacing = 0.01;
  o.rotation_deg = msd::Vec3(0, 0, 30);
  const msd::LimbMesh m = msd::mesh_limb(limb(), o);
  // Nodes sit on the rotated lattice: in the grid frame, (x - origin) / h is integral.
  for (int i = 0; i < m.mesh.num_nodes(); i += 7) {
    const msd::Vec3 g = (m.rotation * m.mesh.nodes.col(i) - m.grid.origin) / m.grid.spacing;
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(g[d], std::round(g[d]), 1e-9);
  }
  // ... and the lattice is not aligned with the limb's frame: its x edges run
  // at -30 degrees in the limb's xy plane.
  const msd::Vec3 grid_x = m.rotation.transpose() * msd::Vec3::UnitX();
  EXPECT_NEAR(std::atan2(grid_x.y(), grid_x.x()), -M_PI / 6, 1e-12);
  bool rotated = false;
  for (const auto& t : m.mesh.tets)
    for (int a = 0; a < 4 && !rotated; ++a)
      for (int b = a + 1; b < 4 && !rotated; ++b) {
        const msd::Vec3 e = (m.mesh.nodes.col(t[b]) - m.mesh.nodes.col(t[a])) / m.grid.spacing;
        rotated = (e - grid_x).norm() < 1e-9 || (e + grid_x).norm() < 1e-9;
      }
  EXPECT_TRUE(rotated);
  EXPECT_EQ(msd::separation_fault(m.grid, m.labels.label), "");
}

TEST(LimbMesher, ValidationNamesTheRegionItsFileAndTheFault) {
  msd::LimbSurfaces s = limb();
  EXPECT_EQ(error_of(s), "");
  // A femur poking out of the skin.
  s.inner[msd::kUpperBone] = moved(msd::make_cylinder(0.012, 0.20, 16), {0, 0, 0.165});
  EXPECT_NE(error_of(s).find("upper_bone (femur.stl): vertex"), std::string::npos) << error_of(s);
  EXPECT_NE(error_of(s).find("lies outside the skin"), std::string::npos);
  // Two bones overlapping.
  s = limb();
  s.inner[msd::kLowerBone] = moved(msd::make_cylinder(0.012, 0.20, 16), {0, 0, 0.005});
  EXPECT_NE(error_of(s).find("overlap"), std::string::npos) << error_of(s);
  // A bone overlapping a muscle is the thesis' case: allowed, erosion resolves it.
  s = limb();
  s.inner[msd::kFrontMuscle] = msd::make_box({-0.025, 0.005, 0.17}, {0.025, 0.042, 0.28});
  EXPECT_EQ(error_of(s), "");
  msd::LimbMeshOptions o;
  o.spacing = 0.01;
  EXPECT_EQ(msd::separation_fault(msd::mesh_limb(s, o).grid, msd::mesh_limb(s, o).labels.label), "");
  // An open skin.
  s = limb();
  s.skin.triangles.pop_back();
  EXPECT_NE(error_of(s).find("skin (skin.obj): triangle "), std::string::npos) << error_of(s);
  EXPECT_NE(error_of(s).find(": the surface is open"), std::string::npos) << error_of(s);
  // Flipped muscle.
  s = limb();
  for (auto& t : s.inner[msd::kBackMuscle].triangles) std::swap(t[1], t[2]);
  EXPECT_NE(error_of(s).find("back_muscle"), std::string::npos) << error_of(s);
  // Bad options.
  o.spacing = 0.0;
  EXPECT_THROW(msd::mesh_limb(limb(), o), msd::Error);
}

TEST(LimbMesher, PullingSurfaceNodesTowardsTheSkinShrinksTheGapOnlyInTheArea) {
  const msd::LimbSurfaces s = limb();
  msd::LimbMeshOptions o;
  o.spacing = 0.01;
  const msd::LimbMesh plain = msd::mesh_limb(s, o);
  o.pull_areas = {{"behind the knee", {-0.06, -0.06, 0.12}, {0.06, -0.01, 0.18}}};
  const msd::LimbMesh pulled = msd::mesh_limb(s, o);
  EXPECT_GT(pulled.pull.candidates, 5);
  EXPECT_GT(pulled.pull.moved, 0);
  EXPECT_LT(pulled.pull.gap_after, 0.5 * pulled.pull.gap_before);
  EXPECT_GE(msd::min_quality(pulled.mesh), o.pull_min_quality);
  // Nodes outside the area did not move; inside it some did.
  int moved = 0;
  for (int v = 0; v < plain.mesh.num_nodes(); ++v) {
    const msd::Vec3 x = plain.mesh.nodes.col(v);
    const bool in_area = x.y() <= -0.01 && x.z() >= 0.12 && x.z() <= 0.18;
    if (!in_area) {
      EXPECT_EQ((pulled.mesh.nodes.col(v) - x).norm(), 0.0) << v;
    }
    moved += (pulled.mesh.nodes.col(v) - x).norm() > 0 ? 1 : 0;
  }
  EXPECT_EQ(moved, pulled.pull.moved);
  // The embedding is computed on the pulled mesh: rest positions still exact.
  msd::Points x;
  msd::embedded_positions(pulled.mesh.nodes, pulled.mesh.tets, pulled.embedded.at(msd::kPassiveTissue), x);
  EXPECT_LT((x - s.skin.vertices).cwiseAbs().maxCoeff(), 1e-12);
  o.pull_areas[0].hi.z() = 0.0;  // hi below lo
  EXPECT_THROW(msd::mesh_limb(s, o), msd::Error);
}
