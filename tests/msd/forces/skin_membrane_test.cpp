// The skin membrane (msd/forces/skin_membrane.hpp): rest and rigid motions are
// force-free, equibiaxial stretch matches the incompressible sheet's closed
// form (and its small-strain limit E / (1 - nu) with E = 3 mu, nu = 1/2), the
// forces are minus the energy's gradient and the stiffness their derivative.
#include "msd/forces/skin_membrane.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "msd/mesh/tet_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

using msd::Points;
using msd::Vec3;

namespace {

// Published in-vivo skin (benchmarks/materials.yaml's `skin`): E = 129 kPa
// (Diridollou et al. 2000, suction fitted with a membrane model), h = 1.55 mm
// (Laurent et al. 2007, the thigh).
constexpr double kE = 129e3, kH = 1.55e-3;

// Two triangles sharing an edge, not in a coordinate plane, of edge ~2 cm.
Points rest_patch() {
  Points x(3, 4);
  x.col(0) = Vec3(0.0, 0.0, 0.0);
  x.col(1) = Vec3(0.020, 0.002, 0.003);
  x.col(2) = Vec3(0.004, 0.018, -0.002);
  x.col(3) = Vec3(0.022, 0.021, 0.004);
  return x;
}
const std::vector<msd::Tri> kFaces{{0, 1, 2}, {1, 3, 2}};

Points forces(const msd::SkinMembrane& s, const Points& x) {
  Points f = Points::Zero(3, x.cols());
  msd::add_membrane_forces(s, x, f);
  return f;
}

// x scaled by l about its centroid (equibiaxial stretch of a flat patch's
// triangles, and a squeeze of any).
Points scaled_about_centroid(const Points& x, double l) {
  const Vec3 c = x.rowwise().mean();
  return ((l * (x.colwise() - c)).colwise() + c).eval();
}

double total_rest_area(const msd::SkinMembrane& s) {
  double area = 0.0;
  for (const auto& t : s.triangles) area += t.rest_area;
  return area;
}

Points randomly_moved(const Points& x, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Points y = x;
  for (int i = 0; i < x.cols(); ++i) y.col(i) += amount * Vec3(u(rng), u(rng), u(rng));
  return y;
}

}  // namespace

TEST(SkinMembrane, RestAndRigidMotionsCarryNoForceAndNoEnergy) {
  const Points x0 = rest_patch();
  const msd::SkinMembrane s = msd::make_skin_membrane(x0, kFaces, kE, kH);
  EXPECT_DOUBLE_EQ(s.shear_modulus, kE / 3.0);
  EXPECT_NEAR(msd::membrane_energy(s, x0), 0.0, 1e-15);
  EXPECT_LT(forces(s, x0).norm(), 1e-9);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, -1).normalized()).toRotationMatrix();
  const Points moved = (R * x0).colwise() + Vec3(0.3, -0.1, 0.05);
  EXPECT_NEAR(msd::membrane_energy(s, moved), 0.0, 1e-12);
  EXPECT_LT(forces(s, moved).norm(), 1e-9);
}

TEST(SkinMembrane, EquibiaxialStretchFollowsTheIncompressibleSheetsClosedForm) {
  // x = l X about the centroid: W = A0 h mu/2 (2 l^2 + l^-4 - 3) and the
  // generalised force sum_i f_i . (X_i - c) = -dW/dl = -2 A0 h mu (l - l^-5),
  // which is the Cauchy stress mu (l^2 - l^-4) on the current section
  // (area A0 l^2, thickness h l^-2): -2 sigma A0 h / l.
  const Points x0 = rest_patch();
  const msd::SkinMembrane s = msd::make_skin_membrane(x0, kFaces, kE, kH);
  const double area = total_rest_area(s);
  const Points r = x0.colwise() - x0.rowwise().mean();
  const double mu = kE / 3.0;
  for (double l : {0.75, 0.9, 1.0 + 1e-6, 1.3, 2.0}) {  // area ratios above the floor (0.5)
    const Points x = scaled_about_centroid(x0, l);
    const double w = 0.5 * area * kH * mu * (2 * l * l + std::pow(l, -4) - 3);
    EXPECT_NEAR(msd::membrane_energy(s, x), w, 1e-10 * std::abs(w) + 1e-12 * area * kH * mu) << "l " << l;
    const Points f = forces(s, x);
    double generalised = 0.0;
    for (int i = 0; i < 4; ++i) generalised += f.col(i).dot(r.col(i));
    const double sigma = mu * (l * l - std::pow(l, -4));
    EXPECT_NEAR(generalised, -2.0 * sigma * area * kH / l, 1e-9 * std::abs(sigma * area * kH)) << "l " << l;
    if (l < 1.0 + 1e-5 && l > 1.0) {
      // Small strain, from the code's forces: sigma = E / (1 - nu) eps, the
      // plane-stress sheet of E = 3 mu and nu = 1/2.
      const double sigma_code = -generalised * l / (2.0 * area * kH);
      EXPECT_NEAR(sigma_code / (l - 1.0), kE / (1.0 - 0.5), 1e-4 * kE);
    }
  }
}

// Deformed states: random moves of up to 6 mm, and the same squeezed to 0.55
// of the size (area ratio 0.3, below the floor).
Points deformed_state(const Points& x0, unsigned seed) {
  const Points x = randomly_moved(x0, 0.006, seed);
  return seed % 2 ? x : scaled_about_centroid(x, 0.55);
}

// The squeezed states (even seeds) have every triangle below the area floor
// (J2 < a_f^2 = 0.25), the others every triangle above it.
void expect_below_the_floor_when_squeezed(const msd::SkinMembrane& s, const Points& x, unsigned seed) {
  for (const msd::MembraneTriangle& t : s.triangles) {
    Eigen::Matrix<double, 3, 2> d;
    d.col(0) = x.col(t.nodes[1]) - x.col(t.nodes[0]);
    d.col(1) = x.col(t.nodes[2]) - x.col(t.nodes[0]);
    const Eigen::Matrix<double, 3, 2> F = d * t.rest_inverse;
    const double j2 = (F.transpose() * F).determinant();
    if (seed % 2) EXPECT_GT(j2, 0.25) << seed;
    else EXPECT_LT(j2, 0.25) << seed;
  }
}

TEST(SkinMembrane, ForcesAreMinusTheGradientOfTheEnergy) {
  const Points x0 = rest_patch();
  const msd::SkinMembrane s = msd::make_skin_membrane(x0, kFaces, kE, kH);
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const Points x = deformed_state(x0, seed);
    expect_below_the_floor_when_squeezed(s, x, seed);
    const Points f = forces(s, x);
    const double scale = f.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.1);  // a real deformation: tenths of a newton on 2 cm of skin
    const double h = 1e-8;
    for (int i = 0; i < 4; ++i)
      for (int a = 0; a < 3; ++a) {
        Points xp = x, xm = x;
        xp(a, i) += h;
        xm(a, i) -= h;
        const double grad = (msd::membrane_energy(s, xp) - msd::membrane_energy(s, xm)) / (2 * h);
        EXPECT_NEAR(f(a, i), -grad, 1e-6 * scale) << "seed " << seed << " node " << i << " axis " << a;
      }
    EXPECT_LT(f.rowwise().sum().norm(), 1e-12 * scale);  // internal: no net force
  }
}

TEST(SkinMembrane, EachTrianglesStiffnessIsTheDerivativeOfItsForces) {
  const Points x0 = rest_patch();
  const msd::SkinMembrane s = msd::make_skin_membrane(x0, kFaces, kE, kH);
  for (unsigned seed : {5u, 6u}) {
    const Points x = deformed_state(x0, seed);
    expect_below_the_floor_when_squeezed(s, x, seed);
    for (size_t k = 0; k < s.triangles.size(); ++k) {
      msd::SkinMembrane one = s;
      one.triangles = {s.triangles[k]};
      const msd::Mat9 K = msd::membrane_triangle_stiffness(s, k, x);
      const double scale = K.cwiseAbs().maxCoeff();
      EXPECT_LT((K - K.transpose()).cwiseAbs().maxCoeff(), 1e-9 * scale);  // the energy's Hessian
      const double h = 1e-8;
      for (int j = 0; j < 3; ++j)
        for (int a = 0; a < 3; ++a) {
          const int node = s.triangles[k].nodes[static_cast<size_t>(j)];
          Points xp = x, xm = x;
          xp(a, node) += h;
          xm(a, node) -= h;
          const Points df = (forces(one, xp) - forces(one, xm)) / (2 * h);
          for (int i = 0; i < 3; ++i) {
            const int row = s.triangles[k].nodes[static_cast<size_t>(i)];
            for (int b = 0; b < 3; ++b)
              EXPECT_NEAR(K(3 * i + b, 3 * j + a), df(b, row), 1e-5 * scale)
                  << "seed " << seed << " triangle " << k << " (" << i << b << ", " << j << a << ")";
          }
        }
    }
  }
}

TEST(SkinMembrane, BadConstantsAndFacesAreRefusedByName) {
  const Points x0 = rest_patch();
  auto message = [&](const std::vector<msd::Tri>& faces, double e, double h) {
    try {
      msd::make_skin_membrane(x0, faces, e, h);
    } catch (const msd::Error& err) {
      return std::string(err.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(kFaces, 0.0, kH).find("Young's modulus"), std::string::npos);
  EXPECT_NE(message(kFaces, std::nan(""), kH).find("Young's modulus"), std::string::npos);
  EXPECT_NE(message(kFaces, kE, -1e-3).find("thickness"), std::string::npos);
  EXPECT_NE(message({{0, 1, 1}}, kE, kH).find("face 0 has zero area"), std::string::npos);
  EXPECT_NE(message({{0, 1, 2}, {0, 1, 7}}, kE, kH).find("face 1 names node 7"), std::string::npos);
}

TEST(SkinMembrane, BelowItsAreaFloorTheEnergyContinuesSmoothlyAndAFlattenedTriangleStaysFinite) {
  // Equibiaxial l below a_f = 0.5 in area (l^2 < 0.5): g(J2) is 1/J2's
  // second-order Taylor polynomial at s = 0.25, so W is continuous with its
  // slope at the floor, and finite at zero area.
  const Points x0 = rest_patch();
  const msd::SkinMembrane s = msd::make_skin_membrane(x0, kFaces, kE, kH);
  const double area = total_rest_area(s);
  auto scaled = [&](double l) { return scaled_about_centroid(x0, l); };
  const double mu = kE / 3.0, sf = 0.25;
  for (double l : {0.6, 0.3, 0.0}) {
    const double j2 = std::pow(l, 4), d = j2 - sf;
    const double g = 1.0 / sf - d / (sf * sf) + d * d / (sf * sf * sf);
    const double w = 0.5 * area * kH * mu * (2 * l * l + g - 3);
    EXPECT_NEAR(msd::membrane_energy(s, scaled(l)), w, 1e-10 * w) << "l " << l;
  }
  const double lf = std::sqrt(0.5);  // the floor: both sides meet in value and slope
  const double h = 1e-6;
  EXPECT_NEAR(msd::membrane_energy(s, scaled(lf - h)), msd::membrane_energy(s, scaled(lf + h)),
              1e-4 * msd::membrane_energy(s, scaled(lf)));
  EXPECT_NEAR(msd::membrane_energy(s, scaled(lf + 2 * h)) - msd::membrane_energy(s, scaled(lf)),
              msd::membrane_energy(s, scaled(lf)) - msd::membrane_energy(s, scaled(lf - 2 * h)),
              1e-3 * std::abs(msd::membrane_energy(s, scaled(lf + 2 * h)) - msd::membrane_energy(s, scaled(lf))));
  // A triangle pressed flat onto a line (its third node on the first two's
  // line, as a stick contact can leave it): finite forces and stiffness.
  Points flat = x0;
  flat.col(2) = x0.col(0) + 0.4 * (x0.col(1) - x0.col(0));
  msd::SkinMembrane one = s;
  one.triangles = {s.triangles[0]};
  EXPECT_TRUE(forces(one, flat).allFinite());
  EXPECT_TRUE(msd::membrane_triangle_stiffness(one, 0, flat).allFinite());
  EXPECT_TRUE(std::isfinite(msd::membrane_energy(one, flat)));
}

TEST(SkinMembrane, TheForcesAreBitIdenticalOnOneAndTwoThreads) {
  // A closed membrane: the boundary faces of a meshed 3 x 2 x 4 cm box (about
  // 200 triangles), randomly deformed.
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  const auto sample = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.03, 0.02, 0.04)), o, "box");
  const msd::SkinMembrane s =
      msd::make_skin_membrane(sample.mesh.nodes, msd::boundary_faces(sample.mesh.tets), kE, kH);
  ASSERT_GT(s.triangles.size(), 100u);
  const Points x = randomly_moved(sample.mesh.nodes, 0.003, 9);
  Points one = Points::Zero(3, x.cols()), two = one, corner;
  msd::add_membrane_forces(s, x, one, 1, corner);
  msd::add_membrane_forces(s, x, two, 2, corner);
  EXPECT_GT(one.cwiseAbs().maxCoeff(), 0.01);
  EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one - forces(s, x)).cwiseAbs().maxCoeff(), 0.0);  // the one-thread overload: the same bits
}
