#include "msd/geometry/triangle_mesh.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

using msd::TriangleMesh;
using msd::Vec3;

namespace {

std::string error_of(const TriangleMesh& m) {
  try {
    msd::validate_closed_surface(m, "surf");
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TriangleMesh, BuiltInShapesAreValidClosedSurfaces) {
  EXPECT_EQ(error_of(msd::make_cylinder(0.05, 0.15, 64)), "");
  EXPECT_EQ(error_of(msd::make_box(Vec3(0, 0, 0), Vec3(1, 2, 3))), "");
}

TEST(TriangleMesh, EnclosedVolumeOfBuiltInShapes) {
  EXPECT_NEAR(msd::enclosed_volume(msd::make_box(Vec3(0, 0, 0), Vec3(1, 2, 3))), 6.0, 1e-12);
  // Prism over a regular n-gon inscribed in the circle.
  const int n = 64;
  const double area = 0.5 * n * 0.05 * 0.05 * std::sin(2 * M_PI / n);
  EXPECT_NEAR(msd::enclosed_volume(msd::make_cylinder(0.05, 0.15, n)), area * 0.15, 1e-15);
}

TEST(TriangleMesh, CylinderHasExactAxisVertices) {
  const TriangleMesh c = msd::make_cylinder(0.05, 0.15, 64);
  const msd::Aabb box = msd::bounding_box(c);
  EXPECT_EQ(box.lo.x(), -0.05);
  EXPECT_EQ(box.hi.x(), 0.05);
  EXPECT_EQ(box.lo.y(), -0.05);
  EXPECT_EQ(box.hi.y(), 0.05);
}

TEST(TriangleMesh, RejectsOpenSurface) {
  TriangleMesh m = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.triangles.pop_back();
  EXPECT_NE(error_of(m).find("open"), std::string::npos) << error_of(m);
}

TEST(TriangleMesh, RejectsInconsistentOrientation) {
  TriangleMesh m = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  EXPECT_NE(error_of(m).find("inconsistent orientation"), std::string::npos) << error_of(m);
}

TEST(TriangleMesh, RejectsInwardFacingSurface) {
  TriangleMesh m = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  EXPECT_NE(error_of(m).find("inwards"), std::string::npos) << error_of(m);
}

TEST(TriangleMesh, RejectsEdgeSharedByMoreThanTwoTriangles) {
  // Two boxes sharing one edge along z at x = y = 1: a non-manifold edge.
  TriangleMesh a = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const TriangleMesh b = msd::make_box(Vec3(1, 1, 0), Vec3(2, 2, 1));
  // Merge b's vertices onto a's where coordinates coincide.
  std::vector<int> map(8);
  for (int i = 0; i < 8; ++i) {
    map[i] = -1;
    for (int j = 0; j < a.num_vertices(); ++j)
      if ((a.vertices.col(j) - b.vertices.col(i)).norm() == 0.0) map[i] = j;
    if (map[i] < 0) {
      a.vertices.conservativeResize(3, a.num_vertices() + 1);
      a.vertices.col(a.num_vertices() - 1) = b.vertices.col(i);
      map[i] = a.num_vertices() - 1;
    }
  }
  for (const auto& t : b.triangles) a.triangles.push_back({map[t[0]], map[t[1]], map[t[2]]});
  EXPECT_NE(error_of(a).find("non-manifold"), std::string::npos) << error_of(a);
}

TEST(TriangleMesh, RejectsNonManifoldVertex) {
  // Two boxes touching at a single corner (1, 1, 1).
  TriangleMesh a = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const TriangleMesh b = msd::make_box(Vec3(1, 1, 1), Vec3(2, 2, 2));
  const int offset = a.num_vertices();
  a.vertices.conservativeResize(3, offset + 8);
  a.vertices.rightCols(8) = b.vertices;
  for (auto t : b.triangles) {
    for (int& k : t) k = (k == 0) ? 7 : k + offset;  // b's corner 0 is a's corner 7
    a.triangles.push_back(t);
  }
  // Counted from 1, as the OBJ file counts: a's corner 7 (0-based) is vertex 8.
  EXPECT_NE(error_of(a).find("vertex 8 at (1, 1, 1) is non-manifold"), std::string::npos) << error_of(a);
}

TEST(TriangleMesh, RejectsDegenerateTriangleAndBadIndex) {
  TriangleMesh m = msd::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  TriangleMesh bad_index = m;
  bad_index.triangles[0][0] = 99;
  EXPECT_NE(error_of(bad_index).find("triangle 1 refers to vertex 100"), std::string::npos) << error_of(bad_index);
  TriangleMesh degenerate = m;
  degenerate.vertices.col(1) = degenerate.vertices.col(0);
  EXPECT_NE(error_of(degenerate).find("degenerate"), std::string::npos) << error_of(degenerate);
}

TEST(TriangleMesh, ObjRoundTrip) {
  testing_support::TempDir dir("obj");
  const TriangleMesh c = msd::make_cylinder(0.05, 0.15, 16);
  msd::write_obj(dir.file("c.obj"), c);
  const TriangleMesh r = msd::read_obj(dir.file("c.obj"));
  ASSERT_EQ(r.num_vertices(), c.num_vertices());
  ASSERT_EQ(r.num_triangles(), c.num_triangles());
  EXPECT_EQ((r.vertices - c.vertices).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(r.triangles, c.triangles);
}

TEST(TriangleMesh, ObjOfADeformedFrameHasTheGivenDecimalsAndTheMeshsFaces) {
  testing_support::TempDir dir("obj");
  const TriangleMesh c = msd::make_cylinder(0.05, 0.15, 16);
  const msd::Points moved = c.vertices.colwise() + msd::Vec3(1.0 / 3.0, 0.0, -2.0);
  msd::write_obj(dir.file("f.obj"), moved, c.triangles, 6);
  std::ifstream in(dir.file("f.obj"));
  std::string first;
  std::getline(in, first);
  char expected[96];
  std::snprintf(expected, sizeof expected, "v %.6f %.6f %.6f", moved(0, 0), moved(1, 0), moved(2, 0));
  EXPECT_EQ(first, expected);
  const TriangleMesh r = msd::read_obj(dir.file("f.obj"));
  EXPECT_EQ(r.triangles, c.triangles);
  EXPECT_LT((r.vertices - moved).cwiseAbs().maxCoeff(), 5e-7);
}

TEST(TriangleMesh, VertexNormalsAreUnitAndOutward) {
  const TriangleMesh b = msd::make_box(msd::Vec3(-1, -1, -1), msd::Vec3(1, 1, 1));
  const msd::Points n = msd::vertex_normals(b);
  ASSERT_EQ(n.cols(), b.num_vertices());
  for (int i = 0; i < n.cols(); ++i) {
    EXPECT_NEAR(n.col(i).norm(), 1.0, 1e-12);
    EXPECT_GT(n.col(i).dot(b.vertices.col(i)), 0.0);  // the box is centred at the origin: outward = away from it
  }
  // On the cylinder's side the normals point away from the axis.
  const TriangleMesh c = msd::make_cylinder(0.05, 0.15, 16);
  const msd::Points m = msd::vertex_normals(c);
  for (int i = 0; i < c.num_vertices(); ++i) {
    const msd::Vec3 radial(c.vertices(0, i), c.vertices(1, i), 0.0);
    if (radial.norm() > 1e-9) {
      EXPECT_GT(m.col(i).dot(radial), 0.0);
    }
  }
}

TEST(TriangleMesh, ObjQuadsSlashesAndNegativeIndices) {
  testing_support::TempDir dir("obj");
  std::ofstream(dir.file("q.obj")) << "# unit square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                   << "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -4 -2 -1\n";
  const TriangleMesh m = msd::read_obj(dir.file("q.obj"));
  ASSERT_EQ(m.num_triangles(), 3);
  EXPECT_EQ(m.triangles[1], (msd::Tri{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (msd::Tri{0, 2, 3}));
}

TEST(TriangleMesh, ObjErrorsNameFileAndLine) {
  testing_support::TempDir dir("obj");
  std::ofstream(dir.file("bad.obj")) << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
  try {
    msd::read_obj(dir.file("bad.obj"));
    FAIL() << "expected an error";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj:3:"), std::string::npos) << e.what();
  }
  std::ofstream(dir.file("bad2.obj")) << "v 0 zero 0\n";
  EXPECT_THROW(msd::read_obj(dir.file("bad2.obj")), msd::Error);
  EXPECT_THROW(msd::read_obj(dir.file("missing.obj")), msd::Error);
}
