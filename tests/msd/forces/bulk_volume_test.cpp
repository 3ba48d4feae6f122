// Tests for msd/src/forces/bulk_volume.cpp: the tet's volume, its gradient and
// Hessian against differences; the bulk term's forces against its energy, zero
// net force and torque, force-free rest; in a model (per cube of the lattice)
// the engine against the per-tet loop, bit-identical threads, forces = -grad
// of conservative_energy; its small-strain elasticity in closed form (with
// isotropic springs, the continuum's lambda and mu); and the refusals.
#include "msd/forces/bulk_volume.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/forces/force_engine.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <random>

using msd::Vec3;

namespace {

const double kE = 3000.0, kNu = 0.45;

msd::TissueMaterial material(double nu = kNu) {
  msd::TissueMaterial mat;
  mat.mode = msd::ConstantsMode::Physical;
  mat.density = 1000;
  mat.youngs_modulus = kE;
  mat.damping_time = 0.01;
  mat.poisson_ratio = nu;
  return mat;
}

// A block of the lattice (h = 1 cm) with the given terms, one volume group per cube.
msd::Model lattice(unsigned terms, const Vec3& size, int threads = 1, msd::TissueMaterial mat = material()) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  const auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), size), o, "block");
  msd::ModelOptions mo;
  mo.terms = terms;
  mo.region_materials = {mat};
  mo.threads = threads;
  mo.volume_group = s.info.tet_cube_id;
  return msd::build_model(s.mesh, mo);
}

double lambda_of(double E, double nu) { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
double mu_of(double E, double nu) { return E / (2 * (1 + nu)); }

}  // namespace

TEST(BulkVolume, TheTetsVolumeGradientAndHessianAreItsDerivatives) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    Vec3 x[4];
    testing_support::random_tet(rng, x, 0.02);
    Vec3 g[4], fd[4];
    msd::tet_volume_gradient(x, g);
    testing_support::fd_gradient([](const Vec3* y) { return msd::tet_signed_volume(y[0], y[1], y[2], y[3]); }, x, 1e-7, fd);
    const double scale = g[0].norm() + g[1].norm();
    for (int i = 0; i < 4; ++i) EXPECT_LT((g[i] - fd[i]).norm(), 1e-7 * scale) << trial << " " << i;
    // The Hessian: differences of the gradient.
    const msd::Mat12 H = msd::tet_volume_hessian(x);
    EXPECT_LT((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-15);
    for (int j = 0; j < 4; ++j)
      for (int b = 0; b < 3; ++b) {
        Vec3 up[4] = {x[0], x[1], x[2], x[3]}, down[4] = {x[0], x[1], x[2], x[3]}, gu[4], gd[4];
        up[j][b] += 1e-6;
        down[j][b] -= 1e-6;
        msd::tet_volume_gradient(up, gu);
        msd::tet_volume_gradient(down, gd);
        for (int i = 0; i < 4; ++i)
          for (int a = 0; a < 3; ++a)
            EXPECT_NEAR(H(3 * i + a, 3 * j + b), (gu[i][a] - gd[i][a]) / 2e-6, 1e-8 * H.cwiseAbs().maxCoeff());
      }
  }
}

TEST(BulkVolume, OneGroupsForcesAreMinusItsEnergysGradientWithNoNetForceOrTorqueAndNoneAtRest) {
  std::mt19937 rng(5);
  const double K = 2e5;
  for (int trial = 0; trial < 10; ++trial) {
    Vec3 x[4], rest[4];
    testing_support::random_tet(rng, rest, 0.02);
    std::uniform_real_distribution<double> u(-0.004, 0.004);
    for (int i = 0; i < 4; ++i) x[i] = rest[i] + Vec3(u(rng), u(rng), u(rng));
    const double v0 = msd::tet_signed_volume(rest[0], rest[1], rest[2], rest[3]);
    const auto energy = [&](const Vec3* y) { return msd::bulk_energy(msd::tet_signed_volume(y[0], y[1], y[2], y[3]), v0, K); };
    Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, grad[4];
    msd::add_bulk_forces(x, msd::bulk_pressure(msd::tet_signed_volume(x[0], x[1], x[2], x[3]), v0, K), f);
    testing_support::fd_gradient(energy, x, 1e-8, grad);
    const double scale = f[0].norm() + f[1].norm() + f[2].norm() + f[3].norm();
    ASSERT_GT(scale, 0.0);
    Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      EXPECT_LT((f[i] + grad[i]).norm(), 1e-5 * scale) << trial << " " << i;
      net += f[i];
      torque += x[i].cross(f[i]);
    }
    EXPECT_LT(net.norm(), 1e-12 * scale);
    EXPECT_LT(torque.norm(), 1e-12 * scale * 0.02);
    // At rest: no pressure, no force; and U = V0 p^2 / (2K).
    EXPECT_EQ(msd::bulk_pressure(v0, v0, K), 0.0);
    const double p = msd::bulk_pressure(msd::tet_signed_volume(x[0], x[1], x[2], x[3]), v0, K);
    EXPECT_NEAR(energy(x), v0 * p * p / (2 * K), 1e-12 * energy(x));
  }
}

TEST(BulkVolume, InAModelTheEngineEqualsTheReferenceLoopIsMinusTheEnergysGradientAndBitIdenticalOnTwoThreads) {
  const Vec3 size(0.03, 0.02, 0.04);
  const msd::Model m = lattice(msd::kSprings | msd::kDampers | msd::kBulk, size);
  ASSERT_EQ(m.volume_groups.size(), 24);  // one group per cube
  ASSERT_EQ(m.volume_groups.bulk_law.size(), 24u);
  EXPECT_NEAR(m.volume_groups.bulk_law[0].modulus, lambda_of(kE, kNu) - mu_of(kE, kNu), 1e-9 * kE);
  msd::Points x, v, fast, ref, fast2;
  testing_support::deform(m, 0.6, 0.001, x, v);
  msd::compute_internal_forces(m, x, v, fast);
  msd::Model reference = m;
  reference.reference_forces = true;
  msd::compute_internal_forces(reference, x, v, ref);
  const double scale = ref.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  EXPECT_LT((fast - ref).cwiseAbs().maxCoeff(), 1e-12 * scale);
  msd::Model two = m;
  two.threads = 2;
  msd::compute_internal_forces(two, x, v, fast2);
  EXPECT_EQ((fast - fast2).cwiseAbs().maxCoeff(), 0.0);
  // The bulk term alone: forces = -grad of conservative_energy, none at rest,
  // no net force or torque.
  const msd::Model bulk = lattice(msd::kBulk, size);
  msd::Points f, zero = msd::Points::Zero(3, x.cols());
  msd::compute_internal_forces(bulk, x, zero, f);
  const double fs = f.cwiseAbs().maxCoeff();
  ASSERT_GT(fs, 0.0);
  for (int node : {0, 7, 31, bulk.num_nodes() - 1})
    for (int c = 0; c < 3; ++c) {
      msd::Points y = x;
      y(c, node) += 1e-8;
      const double up = msd::conservative_energy(bulk, y);
      y(c, node) -= 2e-8;
      const double down = msd::conservative_energy(bulk, y);
      EXPECT_NEAR(f(c, node), -(up - down) / 2e-8, 1e-5 * fs) << node << " " << c;
    }
  msd::Points at_rest;
  msd::compute_internal_forces(bulk, bulk.rest_positions, zero, at_rest);
  EXPECT_LT(at_rest.cwiseAbs().maxCoeff(), 1e-12 * fs);
  Vec3 torque = Vec3::Zero();
  for (int i = 0; i < x.cols(); ++i) torque += Vec3(x.col(i)).cross(Vec3(f.col(i)));
  EXPECT_LT(Vec3(f.rowwise().sum()).norm(), 1e-10 * fs);
  EXPECT_LT(torque.norm(), 1e-10 * fs * 0.04);
}

TEST(BulkVolume, WithIsotropicSpringsTheLatticeHasTheContinuumsSmallStrainElasticity) {
  // One cube under a small homogeneous strain. The springs at class factors
  // a = d / 2 give C11 = 2 (a + d) s E / 3, C12 = C44 = d s E / 3
  // (spring_law.hpp); d = 3 mu / (s E) makes C44 = mu, and the bulk term adds
  // K = lambda - mu to C11 and C12: C11 = lambda + 2 mu, C12 = lambda.
  const double h = 0.01, V = h * h * h, s = msd::kLatticeStiffnessFactor;
  const double lambda = lambda_of(kE, kNu), mu = mu_of(kE, kNu), d = 3 * mu / (s * kE);
  msd::TissueMaterial mat = material();
  mat.edge_laws[0].stiffness = d / 2;
  mat.edge_laws[1].stiffness = d;
  const msd::Model m = lattice(msd::kSprings | msd::kBulk, Vec3(h, h, h), 1, mat);
  ASSERT_EQ(m.num_elements(), 5);
  const double e = 1e-6;
  const auto energy = [&](const msd::Mat3& strain) {
    return msd::conservative_energy(m, (msd::Mat3::Identity() + strain) * m.rest_positions) / V;
  };
  msd::Mat3 uni = msd::Mat3::Zero(), bi = msd::Mat3::Zero(), shear = msd::Mat3::Zero(), turned = msd::Mat3::Zero();
  uni(0, 0) = e;
  bi(0, 0) = bi(1, 1) = e;
  shear(0, 1) = shear(1, 0) = e / 2;
  turned(0, 0) = e / 2;
  turned(1, 1) = -e / 2;
  const double C11 = lambda + 2 * mu, C12 = lambda, tol = 1e-4 * C11 * e * e;
  EXPECT_NEAR(energy(uni), 0.5 * C11 * e * e, tol);
  EXPECT_NEAR(energy(bi), (C11 + C12) * e * e, tol);
  EXPECT_NEAR(energy(shear), 0.5 * mu * e * e, tol);
  EXPECT_NEAR(energy(turned), 0.5 * mu * e * e, tol);  // isotropic: the turned shear costs the same
  // A uniform dilatation J = (1 + e)^3: the bulk term's energy is K V0 (J - 1)^2 / 2 exactly.
  const msd::Model bulk = lattice(msd::kBulk, Vec3(h, h, h), 1, mat);
  const double J = std::pow(1 + 1e-3, 3);
  EXPECT_NEAR(msd::conservative_energy(bulk, (1 + 1e-3) * bulk.rest_positions),
              0.5 * (lambda - mu) * V * (J - 1) * (J - 1), 1e-9 * (lambda - mu) * V * (J - 1) * (J - 1));
}

TEST(BulkVolume, TheTermIsRefusedWithoutCubesWithTheContinuumElementOrAtNuOfAQuarterOrLess) {
  msd::SampleMeshOptions o;
  o.spacing = 0.01;
  const auto s = msd::mesh_closed_surface(msd::make_box(Vec3::Zero(), Vec3(0.02, 0.01, 0.01)), o, "block");
  const auto refused = [&](unsigned terms, bool groups, msd::TissueMaterial mat, const std::string& says) {
    msd::ModelOptions mo;
    mo.terms = terms;
    mo.region_materials = {mat};
    if (groups) mo.volume_group = s.info.tet_cube_id;
    try {
      msd::build_model(s.mesh, mo);
      ADD_FAILURE() << "accepted: " << says;
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused(msd::kSprings | msd::kBulk, false, material(), "the bulk term needs volume groups");
  refused(msd::kBulk | msd::kNeoHookean, true, material(), "choose one");
  refused(msd::kSprings | msd::kBulk, true, material(0.25), "region 0: poisson_ratio must be above 0.25");
  msd::TissueMaterial no_nu = material();
  no_nu.poisson_ratio.reset();
  refused(msd::kSprings | msd::kBulk, true, no_nu, "needs physical constants with a Poisson's ratio");
  msd::TissueMaterial zero = material();
  zero.bulk_factor = 0.0;
  refused(msd::kSprings | msd::kBulk, true, zero, "bulk_factor must be positive");
  EXPECT_EQ(msd::parse_force_term("bulk"), msd::kBulk);
  EXPECT_EQ(msd::force_terms_to_string(msd::kSprings | msd::kBulk), "springs,bulk");
}
