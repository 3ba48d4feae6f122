// Embedded surfaces (thesis 5.5, eq. 5.6): the search structure agrees with a
// scan over all tets, rest positions and any affine motion of the tet mesh are
// reproduced exactly, and vertices outside the mesh take the nearest tet.
#include "msd/mesh/embedding.hpp"

#include "msd/geometry/inside_test.hpp"
#include "msd/mesh/cubic_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

// A UV sphere of radius 5 cm (1,106 vertices), outward normals.
msd::TriangleMesh sphere() {
  msd::TriangleMesh s;
  const int rings = 24, segments = 48;
  const double r = 0.05;
  s.vertices.resize(3, 2 + (rings - 1) * segments);
  s.vertices.col(0) = msd::Vec3(0, 0, r);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / segments;
      s.vertices.col(1 + (i - 1) * segments + j) =
          r * msd::Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  const int south = 1 + (rings - 1) * segments;
  s.vertices.col(south) = msd::Vec3(0, 0, -r);
  auto id = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) s.triangles.push_back({0, id(1, j), id(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (int j = 0; j < segments; ++j) s.triangles.push_back({south, id(rings - 1, j + 1), id(rings - 1, j)});
  return s;
}

// The sphere meshed at h = 1 cm (cube centres inside): a curved outline, so the
// cubic mesh leaves parts of the smooth sphere uncovered.
msd::SampleMesh sphere_mesh(const msd::TriangleMesh& s, double h = 0.01) {
  msd::SampleMeshOptions o;
  o.spacing = h;
  return msd::mesh_closed_surface(s, o, "sphere");
}

// The scan the thesis used: every tet, inside-outside by barycentric coordinates.
int scan_containing(const msd::TetMesh& m, const msd::Vec3& p, double tol) {
  int best = -1;
  double best_min = -tol;
  for (int e = 0; e < m.num_tets(); ++e) {
    const auto& t = m.tets[static_cast<size_t>(e)];
    const msd::Vec3 a = m.nodes.col(t[0]);
    msd::Mat3 mm;
    mm << m.nodes.col(t[1]) - a, m.nodes.col(t[2]) - a, m.nodes.col(t[3]) - a;
    const msd::Vec3 l = mm.inverse() * (p - a);
    const double smallest = std::min({1.0 - l.sum(), l[0], l[1], l[2]});
    if (smallest >= best_min) {
      best_min = smallest;
      best = e;
    }
  }
  return best;
}

double scan_distance(const msd::TetMesh& m, const msd::Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (const auto& t : m.tets)
    for (const auto& f : kFaces)
      best = std::min(best, (msd::closest_point_on_triangle(p, m.nodes.col(t[f[0]]), m.nodes.col(t[f[1]]),
                                                             m.nodes.col(t[f[2]])) -
                             p)
                                .norm());
  return best;
}

}  // namespace

TEST(Embedding, LocatorAgreesWithAScanOverAllTets) {
  const msd::SampleMesh sm = sphere_mesh(sphere());
  const msd::TetLocator locator(sm.mesh.nodes, sm.mesh.tets);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.07, 0.07);
  int inside = 0, outside = 0;
  for (int n = 0; n < 400; ++n) {
    const msd::Vec3 p(u(rng), u(rng), u(rng));
    const int e = locator.containing(p);
    EXPECT_EQ(e, scan_containing(sm.mesh, p, 1e-10)) << "point " << p.transpose();
    if (e >= 0) {
      ++inside;
      EXPECT_EQ(locator.nearest(p), std::make_pair(e, 0.0));
    } else {
      ++outside;
      // The nearest tet by rings of cells is as near as the nearest by a scan.
      const auto [near, d] = locator.nearest(p);
      ASSERT_GE(near, 0);
      EXPECT_NEAR(d, scan_distance(sm.mesh, p), 1e-12) << "point " << p.transpose();
    }
  }
  EXPECT_GT(inside, 50);
  EXPECT_GT(outside, 50);
  EXPECT_LT(locator.cells(), 4 * sm.mesh.num_tets() + 65);
}

TEST(Embedding, RestPositionsAreReproducedAndOutsideVerticesCounted) {
  const msd::TriangleMesh s = sphere();
  const msd::SampleMesh sm = sphere_mesh(s);
  const msd::Embedding e = msd::embed_vertices(sm.mesh, s.vertices);
  ASSERT_EQ(e.vertices.size(), static_cast<size_t>(s.num_vertices()));
  // The cube-centre rule leaves parts of the sphere's skin outside the cubes.
  EXPECT_GT(e.outside, 0);
  EXPECT_LT(e.outside, s.num_vertices());
  EXPECT_GT(e.max_outside_distance, 0.0);
  EXPECT_LT(e.max_outside_distance, 0.01 * std::sqrt(3.0));  // within one cube diagonal
  int counted = 0;
  for (const auto& v : e.vertices) {
    ASSERT_GE(v.tet, 0);
    if (v.distance > 0) ++counted;
    else
      EXPECT_GE(std::min({1.0 - v.u - v.v - v.w, v.u, v.v, v.w}), -1e-10);
  }
  EXPECT_EQ(counted, e.outside);
  msd::Points x;
  msd::embedded_positions(sm.mesh.nodes, sm.mesh.tets, e, x);
  EXPECT_LT((x - s.vertices).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(Embedding, AnyAffineMotionOfTheTetMeshIsReproducedExactly) {
  const msd::TriangleMesh s = sphere();
  const msd::SampleMesh sm = sphere_mesh(s);
  const msd::Embedding e = msd::embed_vertices(sm.mesh, s.vertices);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    msd::Mat3 a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = (i == j ? 1.0 : 0.0) + 0.6 * u(rng);  // shear, stretch, rotation
    const msd::Vec3 b(u(rng), u(rng), u(rng));
    const msd::Points moved = (a * sm.mesh.nodes).colwise() + b;
    msd::Points x;
    msd::embedded_positions(moved, sm.mesh.tets, e, x);
    const msd::Points expected = (a * s.vertices).colwise() + b;
    // Inside and extrapolated vertices alike: the map is affine in the nodes.
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-14) << "trial " << trial;
  }
}

TEST(Embedding, ANonAffineMotionMovesEachVertexWithItsOwnTet) {
  // Moving one node moves only the vertices embedded in tets that use it, by
  // its barycentric weight times the node's displacement.
  const msd::TriangleMesh s = sphere();
  const msd::SampleMesh sm = sphere_mesh(s);
  const msd::Embedding e = msd::embed_vertices(sm.mesh, s.vertices);
  const int node = sm.mesh.tets[static_cast<size_t>(e.vertices[0].tet)][2];
  msd::Points moved = sm.mesh.nodes;
  const msd::Vec3 d(0.001, -0.002, 0.003);
  moved.col(node) += d;
  msd::Points x;
  msd::embedded_positions(moved, sm.mesh.tets, e, x);
  int affected = 0;
  for (size_t i = 0; i < e.vertices.size(); ++i) {
    const auto& v = e.vertices[i];
    const auto& t = sm.mesh.tets[static_cast<size_t>(v.tet)];
    const double weights[4] = {1.0 - v.u - v.v - v.w, v.u, v.v, v.w};
    msd::Vec3 expected = s.vertices.col(static_cast<Eigen::Index>(i));
    for (int k = 0; k < 4; ++k)
      if (t[static_cast<size_t>(k)] == node) expected += weights[k] * d;
    if ((expected - s.vertices.col(static_cast<Eigen::Index>(i))).norm() > 0) ++affected;
    EXPECT_LT((x.col(static_cast<Eigen::Index>(i)) - expected).norm(), 1e-15);
  }
  EXPECT_GE(affected, 1);
  EXPECT_LT(affected, 100);
}

TEST(Embedding, BadInputIsNamed) {
  const msd::SampleMesh sm = sphere_mesh(sphere(), 0.02);
  msd::Points bad(3, 2);
  bad << 0, 0, 0, std::numeric_limits<double>::quiet_NaN(), 0, 0;
  try {
    msd::embed_vertices(sm.mesh, bad);
    FAIL() << "a NaN vertex was embedded";
  } catch (const msd::Error& err) {
    EXPECT_NE(std::string(err.what()).find("vertex 1"), std::string::npos) << err.what();
  }
  EXPECT_THROW(msd::TetLocator(msd::Points(3, 0), {}), msd::Error);
  msd::Points flat(3, 4);
  flat << 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0;  // four coplanar nodes
  EXPECT_THROW(msd::TetLocator(flat, {msd::Tet{0, 1, 2, 3}}), msd::Error);
}
