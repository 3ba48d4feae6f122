#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

using msd::CubeRule;
using msd::Vec3;

namespace {

msd::SampleMesh mesh(const msd::TriangleMesh& s, double h, CubeRule rule) {
  msd::SampleMeshOptions o;
  o.spacing = h;
  o.rule = rule;
  return msd::mesh_closed_surface(s, o, "test surface");
}

// The invariants every cubic-grid mesh must satisfy.
void expect_valid(const msd::SampleMesh& s) {
  const double h = s.grid.spacing;
  // Total volume = cubes * h^3, every tet positive and of the expected quality.
  EXPECT_NEAR(msd::total_volume(s.mesh.nodes, s.mesh.tets), s.cubes * h * h * h, 1e-9 * s.cubes * h * h * h);
  for (const auto& t : s.mesh.tets) EXPECT_GT(msd::tet_signed_volume(s.mesh.nodes, t), 0.0);
  EXPECT_GT(msd::min_quality(s.mesh), 0.8);
  EXPECT_EQ(s.mesh.num_tets(), 5 * s.cubes);
  // Conformity: every triangle is shared by one tet (boundary) or two
  // (interior); no triangle is shared by three or more.
  const auto hist = msd::face_sharing_histogram(s.mesh.tets);
  ASSERT_LE(hist.size(), 3u);
  // Boundary triangles are exactly two per exposed cube face: a face between
  // two selected cubes never shows up as boundary (the splits match there).
  std::set<long> cubes(s.info.tet_cube_id.begin(), s.info.tet_cube_id.end());
  long exposed = 0;
  const auto& g = s.grid;
  for (long id : cubes) {
    const int i = static_cast<int>(id % g.nx), j = static_cast<int>((id / g.nx) % g.ny),
              k = static_cast<int>(id / (static_cast<long>(g.nx) * g.ny));
    const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k}, {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
    for (const auto& n : nb) {
      const bool in_grid = n[0] >= 0 && n[0] < g.nx && n[1] >= 0 && n[1] < g.ny && n[2] >= 0 && n[2] < g.nz;
      if (!in_grid || !cubes.count(g.cube_id(n[0], n[1], n[2]))) ++exposed;
    }
  }
  EXPECT_EQ(hist[1], 2 * exposed);
  EXPECT_EQ(static_cast<long>(msd::boundary_faces(s.mesh.tets).size()), 2 * exposed);
  // Interior triangles: each cube has 5 tets * 4 faces = 20 face slots.
  EXPECT_EQ(hist[1] + 2 * hist[2], 20 * s.cubes);
}

}  // namespace

TEST(CubicGrid, ThesisCylinderCountsForEachRule) {
  // The thesis' sample: 15 cm tall, 10 cm across, h = 2.5 cm (5.2.1). The thesis
  // reports 120 tets: the cubes lying wholly inside the cylinder (2 x 2 per
  // layer, 6 layers). Keeping cubes whose centre is inside gives 12 per layer;
  // keeping every cube the cylinder touches gives 16 per layer.
  const auto c = msd::make_cylinder(0.05, 0.15, 64);
  const auto inside = mesh(c, 0.025, CubeRule::WhollyInside);
  EXPECT_EQ(inside.cubes, 24);
  EXPECT_EQ(inside.mesh.num_tets(), 120);
  EXPECT_EQ(inside.mesh.num_nodes(), 63);
  const auto centre = mesh(c, 0.025, CubeRule::Centre);
  EXPECT_EQ(centre.cubes, 72);
  EXPECT_EQ(centre.mesh.num_tets(), 360);
  const auto overlap = mesh(c, 0.025, CubeRule::Overlap);
  EXPECT_EQ(overlap.cubes, 96);
  EXPECT_EQ(overlap.mesh.num_tets(), 480);
  expect_valid(inside);
  expect_valid(centre);
  expect_valid(overlap);
}

TEST(CubicGrid, InvariantsOnFinerCylinderAndBox) {
  expect_valid(mesh(msd::make_cylinder(0.05, 0.15, 48), 0.01, CubeRule::Centre));
  expect_valid(mesh(msd::make_cylinder(0.05, 0.15, 48), 0.007, CubeRule::Overlap));
  const auto box = mesh(msd::make_box(Vec3(0, 0, 0), Vec3(0.04, 0.04, 0.08)), 0.01, CubeRule::Centre);
  EXPECT_EQ(box.cubes, 4 * 4 * 8);
  expect_valid(box);
  // Aligned box: the three rules agree.
  EXPECT_EQ(mesh(msd::make_box(Vec3(0, 0, 0), Vec3(0.04, 0.04, 0.08)), 0.01, CubeRule::WhollyInside).cubes, 128);
  EXPECT_EQ(mesh(msd::make_box(Vec3(0, 0, 0), Vec3(0.04, 0.04, 0.08)), 0.01, CubeRule::Overlap).cubes, 128);
}

TEST(CubicGrid, NonConvexSurfaceFromObjStyleMesh) {
  // An L-shaped solid: box minus a quadrant, built as a closed surface by
  // meshing two boxes' union boundary is tedious, so use the tet mesher's own
  // boundary of an L of cubes as the input surface.
  msd::CubicGrid g;
  g.spacing = 1.0;
  g.nx = 2;
  g.ny = 2;
  g.nz = 1;
  std::vector<int> region(4, 0);
  region[g.cube_id(1, 1, 0)] = -1;
  const msd::TetMesh l = msd::split_cubes(g, region);
  msd::TriangleMesh surface;
  surface.vertices = l.nodes;
  for (const auto& f : msd::boundary_faces(l.tets)) surface.triangles.push_back(f);
  msd::validate_closed_surface(surface, "L");
  const auto s = mesh(surface, 0.5, CubeRule::Centre);
  EXPECT_EQ(s.cubes, 3 * 8);  // three unit cubes, each 2 x 2 x 2 half-cubes
  expect_valid(s);
}

TEST(CubicGrid, SplitAlternatesBetweenNeighbours) {
  // Two cubes side by side: the face diagonals on the shared face coincide.
  msd::CubicGrid g;
  g.spacing = 1.0;
  g.nx = 2;
  g.ny = 1;
  g.nz = 1;
  const msd::TetMesh m = msd::split_cubes(g, {0, 0});
  EXPECT_EQ(m.num_tets(), 10);
  const auto hist = msd::face_sharing_histogram(m.tets);
  EXPECT_EQ(hist[1], 20);  // 10 exposed cube faces * 2
  EXPECT_EQ(hist[2], (40 - 20) / 2);
  // Central tets are regular, corner tets are right-angled.
  for (const auto& t : m.tets) {
    const double q = msd::tet_quality(m.nodes.col(t[0]), m.nodes.col(t[1]), m.nodes.col(t[2]), m.nodes.col(t[3]));
    EXPECT_TRUE(std::abs(q - 1.0) < 1e-12 || q > 0.83) << q;
  }
}

TEST(CubicGrid, BadInputIsReportedClearly) {
  const auto c = msd::make_cylinder(0.05, 0.15, 16);
  msd::SampleMeshOptions o;
  o.spacing = 0.0;
  EXPECT_THROW(msd::mesh_closed_surface(c, o, "c"), msd::Error);
  o.spacing = -0.01;
  EXPECT_THROW(msd::mesh_closed_surface(c, o, "c"), msd::Error);
  o.spacing = 1e-5;
  try {
    msd::mesh_closed_surface(c, o, "c");
    FAIL();
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the limit"), std::string::npos) << e.what();
  }
  o.spacing = 0.2;  // larger than the sample: with "inside" nothing fits
  o.rule = CubeRule::WhollyInside;
  try {
    msd::mesh_closed_surface(c, o, "c");
    FAIL();
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no cube"), std::string::npos) << e.what();
  }
  auto open = c;
  open.triangles.pop_back();
  o.spacing = 0.01;
  EXPECT_THROW(msd::mesh_closed_surface(open, o, "c"), msd::Error);
}

TEST(CubicGrid, RuleNamesRoundTrip) {
  for (auto r : {CubeRule::Centre, CubeRule::WhollyInside, CubeRule::Overlap})
    EXPECT_EQ(msd::parse_cube_rule(msd::to_string(r)), r);
  EXPECT_EQ(msd::parse_cube_rule("center"), CubeRule::Centre);
  EXPECT_THROW(msd::parse_cube_rule("any"), msd::Error);
}
