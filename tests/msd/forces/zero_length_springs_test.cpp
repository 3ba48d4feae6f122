// Tests for msd/src/forces/zero_length_springs.cpp and the bulk term's
// neo-Hookean law (msd/src/forces/bulk_volume.cpp): the cotangent weights in
// closed form on the five-tet cube and their second-moment identity; the
// springs' energy is the linear element's Dirichlet energy; the law's
// pressure and stiffness are its energy's derivatives, with its continuation
// below the floor; in a model, the lattice's energy is the neo-Hookean energy
// (springs per tet, volume per cube) for any deformation, its forces are
// minus that energy's gradient, a body of cubes and a cylinder with moved
// boundary nodes are force-free at rest, Newton's matrix is the forces'
// derivative; the small-strain moduli are the continuum's; the refusals.
#include "msd/forces/zero_length_springs.hpp"

#include "msd/forces/bulk_volume.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/forces/force_engine.hpp"
#include "msd/forces/stable_neo_hookean.hpp"
#include "msd/geometry/triangle_mesh.hpp"
#include "msd/integrate/implicit.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using msd::Mat3;
using msd::Vec3;

namespace {

const double kE = 3000.0, kNu = 0.45;
double lambda_of(double E, double nu) { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
double mu_of(double E, double nu) { return E / (2 * (1 + nu)); }

msd::TissueMaterial material(double nu = kNu) {
  msd::TissueMaterial mat;
  mat.mode = msd::ConstantsMode::Physical;
  mat.density = 1000;
  mat.youngs_modulus = kE;
  mat.damping_time = 0.01;
  mat.poisson_ratio = nu;
  mat.zero_length_springs = true;
  return mat;
}

struct Meshed {
  msd::TetMesh mesh;
  std::vector<long> cube;
};

Meshed block(const Vec3& size) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), size), o, "block");
  return {s.mesh, s.info.tet_cube_id};
}

// A cylinder (r = 2 cm, height 4 cm, h = 1 cm): its boundary nodes are moved
// onto the surface, so its tets are not all the cube's.
Meshed cylinder() {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  auto s = msd::mesh_closed_surface(msd::make_cylinder(0.02, 0.04, 32), o, "cylinder");
  return {s.mesh, s.info.tet_cube_id};
}

msd::Model build(const Meshed& m, unsigned terms = msd::kSprings | msd::kBulk, msd::TissueMaterial mat = material(),
                 int threads = 1) {
  msd::ModelOptions mo;
  mo.terms = terms;
  mo.region_materials = {mat};
  mo.threads = threads;
  mo.volume_group = m.cube;
  return msd::build_model(m.mesh, mo);
}

// The lattice's energy computed independently: mu/2 V_t tr(F_t^T F_t) per tet
// and V0_g W(J_g) per cube, W(J) = -mu ln J + lambda/4 (J^2 - 1 - 2 ln J).
double neo_hookean_energy(const msd::Model& m, const msd::Points& x, double mu, double lambda) {
  double u = 0.0;
  std::vector<double> volume(static_cast<size_t>(m.volume_groups.size()), 0.0);
  for (size_t t = 0; t < m.elements.size(); ++t) {
    Vec3 X[4], y[4];
    for (int i = 0; i < 4; ++i) {
      X[i] = m.rest_positions.col(m.elements[t].nodes[static_cast<size_t>(i)]);
      y[i] = x.col(m.elements[t].nodes[static_cast<size_t>(i)]);
    }
    const Mat3 F = msd::deformation_gradient(y, msd::rest_shape_inverse(X));
    u += 0.5 * mu * m.elements[t].rest_volume * (F.transpose() * F).trace();
    volume[static_cast<size_t>(m.volume_groups.of_tet[t])] += msd::tet_signed_volume(y[0], y[1], y[2], y[3]);
  }
  for (int g = 0; g < m.volume_groups.size(); ++g) {
    const double v0 = m.volume_groups.rest_volume[static_cast<size_t>(g)], J = volume[static_cast<size_t>(g)] / v0;
    u += v0 * (-mu * std::log(J) + 0.25 * lambda * (J * J - 1 - 2 * std::log(J)));
  }
  return u;
}

}  // namespace

TEST(ZeroLengthSprings, TheCubesTetsHaveTheClosedFormWeights) {
  // Corner tet: h/6 on the three cube edges, 0 on the face diagonals (their
  // opposite dihedral angle is 90 degrees); the central tet: h/12 on all six.
  const double h = 0.01;
  const Vec3 corner[4] = {Vec3::Zero(), Vec3(h, 0, 0), Vec3(0, h, 0), Vec3(0, 0, h)};
  double w[6];
  msd::cotangent_weights(corner, w);
  for (int e = 0; e < 6; ++e) EXPECT_NEAR(w[e], e < 3 ? h / 6 : 0.0, 1e-15) << e;  // kTetEdges: 0-1, 0-2, 0-3 first
  const Vec3 central[4] = {Vec3::Zero(), Vec3(h, h, 0), Vec3(0, h, h), Vec3(h, 0, h)};
  msd::cotangent_weights(central, w);
  for (int e = 0; e < 6; ++e) EXPECT_NEAR(w[e], h / 12, 1e-15) << e;
  const Vec3 flat[4] = {Vec3::Zero(), Vec3(h, 0, 0), Vec3(0, h, 0), Vec3(h, h, 0)};
  EXPECT_THROW(msd::cotangent_weights(flat, w), msd::Error);
}

TEST(ZeroLengthSprings, TheWeightsSumTheEdgesSecondMomentToTheVolumeAndTheEnergyIsTheDirichletEnergy) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (int trial = 0; trial < 20; ++trial) {
    Vec3 X[4];
    testing_support::random_tet(rng, X, 0.02);
    double w[6];
    msd::cotangent_weights(X, w);
    const double V = msd::tet_signed_volume(X[0], X[1], X[2], X[3]);
    Mat3 moment = Mat3::Zero();
    for (int e = 0; e < 6; ++e) {
      const Vec3 l = X[msd::kTetEdges[e][1]] - X[msd::kTetEdges[e][0]];
      moment += w[e] * l * l.transpose();
    }
    EXPECT_LT((moment - V * Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-10 * V) << trial;
    // Any placement of a tet is affine: the springs' energy is mu V tr(F^T F) / 2.
    Vec3 x[4];
    for (int i = 0; i < 4; ++i) x[i] = X[i] + Vec3(u(rng), u(rng), u(rng));
    const double mu = 1234.0;
    double k[6];
    for (int e = 0; e < 6; ++e) k[e] = mu * w[e];
    const Mat3 F = msd::deformation_gradient(x, msd::rest_shape_inverse(X));
    const double expected = 0.5 * mu * V * (F.transpose() * F).trace();
    EXPECT_NEAR(msd::zero_length_spring_energy(x, k), expected, 1e-10 * expected) << trial;
  }
}

TEST(ZeroLengthSprings, TheNeoHookeanBulkLawsPressureAndStiffnessAreItsEnergysDerivativesAndItHoldsTheRestPull) {
  const double mu = mu_of(kE, kNu), lambda = lambda_of(kE, kNu);
  const msd::BulkLaw law{lambda, mu, true};
  // At rest: W = 0, p = -mu (the springs' pull), W'' = mu + lambda.
  EXPECT_NEAR(msd::bulk_law_energy(law, 1.0), 0.0, 1e-12 * mu);
  EXPECT_NEAR(msd::bulk_law_pressure(law, 1.0), -mu, 1e-12 * mu);
  EXPECT_NEAR(msd::bulk_law_stiffness(law, 1.0), mu + lambda, 1e-12 * lambda);
  // Central differences above and below the floor (0.1), and at it below.
  for (double J : {1.7, 1.0, 0.6, 0.2, 0.1 + 1e-4, 0.1 - 1e-4, 0.05, 0.0, -0.3}) {
    const double d = 1e-6;
    const double p = (msd::bulk_law_energy(law, J + d) - msd::bulk_law_energy(law, J - d)) / (2 * d);
    const double k = (msd::bulk_law_pressure(law, J + d) - msd::bulk_law_pressure(law, J - d)) / (2 * d);
    const double ps = std::abs(msd::bulk_law_pressure(law, J)) + mu, ks = msd::bulk_law_stiffness(law, J);
    EXPECT_NEAR(msd::bulk_law_pressure(law, J), p, 1e-6 * ps) << J;
    EXPECT_NEAR(msd::bulk_law_stiffness(law, J), k, 1e-5 * ks) << J;
    EXPECT_TRUE(std::isfinite(msd::bulk_law_energy(law, J))) << J;
  }
  // C2 at the floor itself: value, pressure and stiffness meet from both sides.
  const double f = msd::kBulkFloor, e = 1e-9;
  EXPECT_NEAR(msd::bulk_law_energy(law, f - e), msd::bulk_law_energy(law, f + e), 1e-6 * mu);
  EXPECT_NEAR(msd::bulk_law_pressure(law, f - e), msd::bulk_law_pressure(law, f + e), 1e-6 * (mu + lambda));
  EXPECT_NEAR(msd::bulk_law_stiffness(law, f - e), msd::bulk_law_stiffness(law, f + e), 1e-6 * msd::bulk_law_stiffness(law, f));
  // Crushed or inverted, it pushes outwards ever harder.
  EXPECT_LT(msd::bulk_law_pressure(law, -0.3), msd::bulk_law_pressure(law, 0.05));
  EXPECT_LT(msd::bulk_law_pressure(law, 0.05), -mu);
  // The quadratic law is K (J - 1) whatever the floor.
  const msd::BulkLaw quad{2e5, 0.0, false};
  EXPECT_DOUBLE_EQ(msd::bulk_law_pressure(quad, 0.05), 2e5 * (0.05 - 1));
  EXPECT_DOUBLE_EQ(msd::bulk_law_stiffness(quad, 0.05), 2e5);
}

TEST(ZeroLengthSprings, InAModelTheEnergyIsTheNeoHookeanEnergyAndTheForcesAreMinusItsGradient) {
  const double mu = mu_of(kE, kNu), lambda = lambda_of(kE, kNu);
  for (const Meshed& mesh : {block(Vec3(0.03, 0.02, 0.04)), cylinder()}) {
    const msd::Model m = build(mesh);
    ASSERT_EQ(m.volume_groups.bulk_law.size(), static_cast<size_t>(m.volume_groups.size()));
    EXPECT_TRUE(m.volume_groups.bulk_law[0].neo_hookean);
    EXPECT_NEAR(m.volume_groups.bulk_law[0].modulus, lambda, 1e-9 * lambda);
    EXPECT_NEAR(m.volume_groups.bulk_law[0].rest_modulus, mu, 1e-9 * mu);
    msd::Points x, v, f, ref;
    testing_support::deform(m, 0.7, 0.001, x, v);
    const double u = msd::conservative_energy(m, x);
    EXPECT_NEAR(u, neo_hookean_energy(m, x, mu, lambda), 1e-10 * u);
    // Forces: the engine equals the per-tet loop, and both are -grad U.
    msd::Points zero = msd::Points::Zero(3, x.cols());
    msd::compute_internal_forces(m, x, zero, f);
    msd::Model reference = m;
    reference.reference_forces = true;
    msd::compute_internal_forces(reference, x, zero, ref);
    const double fs = f.cwiseAbs().maxCoeff();
    ASSERT_GT(fs, 0.0);
    EXPECT_LT((f - ref).cwiseAbs().maxCoeff(), 1e-12 * fs);
    for (int node : {0, 7, 31, m.num_nodes() - 1})
      for (int c = 0; c < 3; ++c) {
        msd::Points y = x;
        y(c, node) += 1e-8;
        const double up = msd::conservative_energy(m, y);
        y(c, node) -= 2e-8;
        const double down = msd::conservative_energy(m, y);
        EXPECT_NEAR(f(c, node), -(up - down) / 2e-8, 1e-5 * fs) << node << " " << c;
      }
    // No net force or torque; the threads do not change a bit.
    Vec3 torque = Vec3::Zero();
    for (int i = 0; i < x.cols(); ++i) torque += Vec3(x.col(i)).cross(Vec3(f.col(i)));
    EXPECT_LT(Vec3(f.rowwise().sum()).norm(), 1e-10 * fs);
    EXPECT_LT(torque.norm(), 1e-10 * fs * 0.04);
    msd::Model two = m;
    two.threads = 2;
    msd::Points f2;
    msd::compute_internal_forces(two, x, zero, f2);
    EXPECT_EQ((f - f2).cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(ZeroLengthSprings, ABodyOfCubesAndACylinderWithMovedBoundaryNodesAreForceFreeAtRest) {
  // Each spring pulls at rest; per tet the springs' force on a corner is
  // -mu dV/dx (the weights' identity), which the law's rest pressure -mu
  // cancels (+mu dV/dx) cube by cube.
  for (const Meshed& mesh : {block(Vec3(0.03, 0.02, 0.04)), cylinder()}) {
    const msd::Model m = build(mesh);
    msd::Points f, zero = msd::Points::Zero(3, m.num_nodes());
    msd::compute_internal_forces(m, m.rest_positions, zero, f);
    // The springs' pull alone, for scale: the bulk term's pressure at J = 1 is -mu.
    double pull = 0.0;
    for (int e = 0; e < m.plan.num_edges(); ++e)
      pull = std::max(pull, m.plan.edge_k_s[static_cast<size_t>(e)] *
                                (m.rest_positions.col(m.plan.edge_b[static_cast<size_t>(e)]) -
                                 m.rest_positions.col(m.plan.edge_a[static_cast<size_t>(e)])).norm());
    ASSERT_GT(pull, 0.0);
    EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12 * pull);
    EXPECT_EQ(m.plan.edge_rest[0], 0.0);
  }
}

TEST(ZeroLengthSprings, TheSmallStrainModuliAreTheContinuumsOnOneCubeInAnyDirection) {
  // W = mu/2 (tr C - 3) - mu ln J + lambda/4 (J^2 - 1 - 2 ln J) linearises to
  // mu eps:eps + lambda/2 tr(eps)^2: C11 = lambda + 2 mu, C12 = lambda,
  // C44 = mu, with no class factor.
  const double h = 0.01, V = h * h * h, lambda = lambda_of(kE, kNu), mu = mu_of(kE, kNu);
  const msd::Model m = build(block(Vec3(h, h, h)));
  ASSERT_EQ(m.num_elements(), 5);
  const double u0 = msd::conservative_energy(m, m.rest_positions);
  EXPECT_NEAR(u0, 1.5 * mu * V, 1e-12 * mu * V);  // the springs' mu/2 tr(I) V
  const double e = 1e-5;
  const auto energy = [&](const Mat3& strain) {
    return (msd::conservative_energy(m, (Mat3::Identity() + strain) * m.rest_positions) - u0) / V;
  };
  Mat3 uni = Mat3::Zero(), shear = Mat3::Zero(), turned = Mat3::Zero();
  uni(2, 2) = e;
  shear(0, 2) = shear(2, 0) = e / 2;
  turned(0, 0) = e / 2;
  turned(2, 2) = -e / 2;
  const double C11 = lambda + 2 * mu, tol = 1e-3 * C11 * e * e;
  EXPECT_NEAR(energy(uni), 0.5 * C11 * e * e, tol);
  EXPECT_NEAR(energy(shear), 0.5 * mu * e * e, tol);
  EXPECT_NEAR(energy(turned), 0.5 * mu * e * e, tol);
}

TEST(ZeroLengthSprings, NewtonsMatrixIsTheForcesDerivative) {
  const msd::Model m = build(cylinder());
  msd::Points x, v;
  testing_support::deform(m, 0.8, 0.0005, x, v);
  const msd::Points zero = msd::Points::Zero(3, x.cols());
  msd::SystemLayout L = msd::make_system_layout(m);
  Eigen::SparseMatrix<double> A = L.pattern;
  msd::assemble_system(m, L, x, zero, 0.0, 0.0, 1.0, A);  // c_k = 1: A = K = df/dx
  const double ks = Eigen::MatrixXd(A).cwiseAbs().maxCoeff();
  ASSERT_GT(ks, 0.0);
  msd::Points fp, fm;
  for (int node : {3, 40, m.num_nodes() - 2})
    for (int c = 0; c < 3; ++c) {
      msd::Points y = x;
      y(c, node) += 1e-7;
      msd::compute_internal_forces(m, y, zero, fp);
      y(c, node) -= 2e-7;
      msd::compute_internal_forces(m, y, zero, fm);
      const Eigen::VectorXd col = Eigen::Map<const Eigen::VectorXd>(fp.data(), fp.size()) -
                                  Eigen::Map<const Eigen::VectorXd>(fm.data(), fm.size());
      const Eigen::VectorXd assembled = A.col(3 * node + c);
      EXPECT_LT((assembled - col / 2e-7).cwiseAbs().maxCoeff(), 1e-6 * ks) << node << " " << c;
    }
}

TEST(ZeroLengthSprings, AreRefusedWithEdgeClassesWithoutTheBulkTermBesideTheContinuumOrMixedWithOtherSprings) {
  const Meshed mesh = block(Vec3(0.02, 0.01, 0.01));
  const auto refused = [&](unsigned terms, std::vector<msd::TissueMaterial> mats, const std::string& says) {
    msd::ModelOptions mo;
    mo.terms = terms;
    mo.region_materials = mats;
    mo.volume_group = mesh.cube;
    try {
      msd::build_model(mesh.mesh, mo);
      ADD_FAILURE() << "accepted: " << says;
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused(msd::kSprings, {material()}, "need the springs and the bulk term");
  refused(msd::kBulk, {material()}, "need the springs and the bulk term");
  refused(msd::kSprings | msd::kBulk | msd::kNeoHookean, {material()}, "choose one");
  msd::TissueMaterial classes = material();
  classes.edge_laws[0].stiffness = 0.5;
  refused(msd::kSprings | msd::kBulk, {classes}, "edge classes");
  refused(msd::kSprings | msd::kBulk, {material(0.0)}, "poisson_ratio must be above 0");
  msd::TissueMaterial other = material();
  other.zero_length_springs = false;
  refused(msd::kSprings | msd::kBulk, {material(), other}, "region 1: zero_length_springs differs from region 0's");
  msd::TissueMaterial raw = material();
  raw.mode = msd::ConstantsMode::Raw;
  raw.k_s = 1.0;
  refused(msd::kSprings | msd::kBulk, {raw}, "physical constants with a Poisson's ratio");
}
