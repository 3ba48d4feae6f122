// Marching tetrahedra with relaxation: closed, manifold, outward surfaces that
// lie on the zero set, whose enclosed volume converges to the solid's; the
// field helpers are the distances they claim to be.
#include "msd/geometry/implicit_surface.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

constexpr double kPi = 3.14159265358979323846;

double max_field_on_vertices(const msd::ScalarField& f, const msd::TriangleMesh& m) {
  double worst = 0.0;
  for (int v = 0; v < m.num_vertices(); ++v) worst = std::max(worst, std::abs(f(m.vertices.col(v))));
  return worst;
}

// Smallest cosine between a triangle's normal and the field's gradient at its
// centroid: negative means a triangle folded inwards.
double min_normal_alignment(const msd::ScalarField& f, const msd::TriangleMesh& m, double h) {
  double worst = 1.0;
  for (const msd::Tri& t : m.triangles) {
    const msd::Vec3 a = m.vertices.col(t[0]), b = m.vertices.col(t[1]), c = m.vertices.col(t[2]);
    const msd::Vec3 n = (b - a).cross(c - a).normalized();
    const msd::Vec3 g = msd::field_gradient(f, (a + b + c) / 3.0, h).normalized();
    worst = std::min(worst, n.dot(g));
  }
  return worst;
}

}  // namespace

TEST(ImplicitSurface, SphereIsClosedOutwardOnItsSurfaceAndConvergesInVolume) {
  const double R = 0.05;
  const msd::ScalarField f = [&](const msd::Vec3& x) { return x.norm() - R; };
  double previous_error = 1.0;
  for (double cell : {0.01, 0.005, 0.0025}) {
    msd::ImplicitMeshOptions o;
    o.lo = msd::Vec3::Constant(-0.07);
    o.hi = msd::Vec3::Constant(0.07);
    o.cell = cell;
    const msd::TriangleMesh m = msd::mesh_implicit_surface(f, o);
    EXPECT_NO_THROW(msd::validate_closed_surface(m, "sphere"));
    EXPECT_LT(max_field_on_vertices(f, m), 1e-9);  // projected onto the surface
    EXPECT_GT(min_normal_alignment(f, m, 1e-4), 0.5);
    const double error = std::abs(msd::enclosed_volume(m) / (4.0 / 3.0 * kPi * R * R * R) - 1.0);
    EXPECT_LT(error, previous_error) << "cell " << cell;
    previous_error = error;
  }
  EXPECT_LT(previous_error, 0.01);
}

TEST(ImplicitSurface, RelaxationEvensOutTheSlivers) {
  const msd::ScalarField f = [](const msd::Vec3& x) { return msd::ellipsoid_field(x, msd::Vec3::Zero(), {0.06, 0.04, 0.03}); };
  msd::ImplicitMeshOptions o;
  o.lo = msd::Vec3::Constant(-0.08);
  o.hi = msd::Vec3::Constant(0.08);
  o.cell = 0.006;
  auto worst_quality = [](const msd::TriangleMesh& m) {
    double q = 1.0;  // 4 sqrt(3) area / sum of squared edges: 1 for equilateral
    for (const msd::Tri& t : m.triangles) {
      const msd::Vec3 a = m.vertices.col(t[0]), b = m.vertices.col(t[1]), c = m.vertices.col(t[2]);
      const double area = 0.5 * (b - a).cross(c - a).norm();
      q = std::min(q, 4.0 * std::sqrt(3.0) * area / ((b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm()));
    }
    return q;
  };
  o.relax_iterations = 0;
  const msd::TriangleMesh raw = msd::mesh_implicit_surface(f, o);
  o.relax_iterations = 4;
  const msd::TriangleMesh relaxed = msd::mesh_implicit_surface(f, o);
  EXPECT_NO_THROW(msd::validate_closed_surface(raw, "raw"));
  EXPECT_NO_THROW(msd::validate_closed_surface(relaxed, "relaxed"));
  EXPECT_EQ(raw.triangles, relaxed.triangles);  // relaxation moves vertices only
  EXPECT_LT(worst_quality(raw), 0.05);
  EXPECT_GT(worst_quality(relaxed), 5.0 * worst_quality(raw));
}

TEST(ImplicitSurface, TwoSeparateSolidsGiveTwoClosedPieces) {
  const msd::ScalarField f = [](const msd::Vec3& x) {
    return std::min(msd::capsule_field(x, {-0.05, 0, 0}, {-0.02, 0, 0}, 0.01),
                    (x - msd::Vec3(0.04, 0, 0)).norm() - 0.015);
  };
  msd::ImplicitMeshOptions o;
  o.lo = msd::Vec3(-0.08, -0.03, -0.03);
  o.hi = msd::Vec3(0.07, 0.03, 0.03);
  o.cell = 0.003;
  const msd::TriangleMesh m = msd::mesh_implicit_surface(f, o);
  EXPECT_NO_THROW(msd::validate_closed_surface(m, "two"));
  const double capsule = kPi * 0.01 * 0.01 * 0.03 + 4.0 / 3.0 * kPi * 1e-6, ball = 4.0 / 3.0 * kPi * std::pow(0.015, 3);
  EXPECT_NEAR(msd::enclosed_volume(m), capsule + ball, 0.03 * (capsule + ball));
}

TEST(ImplicitSurface, FieldHelpersAreDistances) {
  // Capsule: exact distance off the axis and beyond the caps.
  EXPECT_NEAR(msd::capsule_field({0.5, 0.3, 0}, {0, 0, 0}, {1, 0, 0}, 0.1), 0.2, 1e-15);
  EXPECT_NEAR(msd::capsule_field({1.5, 0, 0}, {0, 0, 0}, {1, 0, 0}, 0.1), 0.4, 1e-15);
  // Ellipsoid: exact on a sphere, zero on the surface, negative inside.
  EXPECT_NEAR(msd::ellipsoid_field({0.3, 0, 0}, msd::Vec3::Zero(), msd::Vec3::Constant(0.1)), 0.2, 1e-15);
  EXPECT_NEAR(msd::ellipsoid_field({0, 0.04, 0}, msd::Vec3::Zero(), {0.06, 0.04, 0.03}), 0.0, 1e-15);
  EXPECT_LT(msd::ellipsoid_field({0.01, 0.01, 0.01}, msd::Vec3::Zero(), {0.06, 0.04, 0.03}), 0.0);
  // Smooth minimum: the minimum far apart, below it where the two are close.
  EXPECT_EQ(msd::smooth_min(0.0, 1.0, 0.1), 0.0);
  EXPECT_NEAR(msd::smooth_min(0.2, 0.2, 0.1), 0.2 - 0.025, 1e-15);
  EXPECT_EQ(msd::smooth_min(0.2, 0.3, 0.0), 0.2);
  EXPECT_NEAR(msd::smooth_max(0.2, 0.2, 0.1), 0.225, 1e-15);
}

TEST(ImplicitSurface, BadRequestsAreRefused) {
  const msd::ScalarField ball = [](const msd::Vec3& x) { return x.norm() - 0.05; };
  msd::ImplicitMeshOptions o;
  o.lo = msd::Vec3::Constant(-0.1);
  o.hi = msd::Vec3::Constant(0.1);
  o.cell = 0.0;
  EXPECT_THROW(msd::mesh_implicit_surface(ball, o), msd::Error);
  o.cell = 0.01;
  o.hi = msd::Vec3(0.1, -0.2, 0.1);  // inverted
  EXPECT_THROW(msd::mesh_implicit_surface(ball, o), msd::Error);
  o.hi = msd::Vec3::Constant(0.03);  // the ball pokes through the box: open
  o.lo = msd::Vec3::Constant(-0.03);
  EXPECT_THROW(msd::mesh_implicit_surface(ball, o), msd::Error);
  o.lo = msd::Vec3::Constant(-0.1);
  o.hi = msd::Vec3::Constant(0.1);
  const msd::ScalarField nothing = [](const msd::Vec3&) { return 1.0; };
  EXPECT_THROW(msd::mesh_implicit_surface(nothing, o), msd::Error);
  o.cell = 1e-5;  // far too many nodes
  EXPECT_THROW(msd::mesh_implicit_surface(ball, o), msd::Error);
}
