#include "msd/forces/stable_neo_hookean.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using msd::Mat3;
using msd::Mat9;
using msd::Mat12;
using msd::SnhConstants;
using msd::Vec3;

namespace {

// Non-muscular tissue (benchmarks/materials.yaml): E = 2990 Pa, nu = 0.495.
const SnhConstants kFlesh = msd::snh_constants(2990.0, 0.495);

// A rest tet of edge ~1 cm, not regular.
void rest_tet(Vec3 x[4]) {
  x[0] = Vec3(0.0, 0.0, 0.0);
  x[1] = Vec3(0.010, 0.001, 0.0);
  x[2] = Vec3(0.002, 0.011, 0.001);
  x[3] = Vec3(0.001, 0.002, 0.009);
}

// A deformed copy: rest positions moved by `amount` times random vectors of up to the tet's size.
void deformed(const Vec3 rest[4], double amount, unsigned seed, Vec3 x[4]) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (int i = 0; i < 4; ++i) x[i] = rest[i] + amount * Vec3(u(rng), u(rng), u(rng));
}

Eigen::Matrix<double, 12, 1> forces(const Vec3 x[4], const Mat3& dm_inv, double v0, const SnhConstants& c) {
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  msd::add_snh_forces(x, dm_inv, v0, c, f);
  Eigen::Matrix<double, 12, 1> out;
  for (int i = 0; i < 4; ++i) out.segment<3>(3 * i) = f[i];
  return out;
}

Mat3 random_matrix(unsigned seed, double spread) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-spread, spread);
  Mat3 m;
  for (int i = 0; i < 9; ++i) m.data()[i] = u(rng);
  return m;
}

// Deformation gradients to test at: stretched, sheared, compressed to J = 0.1, inverted, collapsed to a plane.
std::vector<Mat3> test_gradients() {
  std::vector<Mat3> out;
  out.push_back(Mat3::Identity() + random_matrix(1, 0.3));
  out.push_back(Mat3::Identity() + random_matrix(2, 0.8));
  out.push_back(Eigen::Vector3d(0.1, 1.0, 1.0).asDiagonal() * (Mat3::Identity() + random_matrix(3, 0.05)));
  out.push_back(Eigen::Vector3d(1.0, 1.0, -0.7).asDiagonal() * (Mat3::Identity() + random_matrix(4, 0.1)));
  Mat3 flat = Mat3::Identity() + random_matrix(5, 0.2);
  flat.col(2) = 0.3 * flat.col(0) - 0.6 * flat.col(1);
  out.push_back(flat);
  return out;
}

}  // namespace

TEST(StableNeoHookean, TheConstantsAreTheLameConstantsMappedAsSmithDeGoesAndKimSection34) {
  const double E = 2990.0, nu = 0.495;
  const double mu_l = E / (2 * (1 + nu)), lambda_l = E * nu / ((1 + nu) * (1 - 2 * nu));
  EXPECT_NEAR(kFlesh.mu, 4.0 / 3.0 * mu_l, 1e-12 * mu_l);
  EXPECT_NEAR(kFlesh.lambda, lambda_l + 5.0 / 6.0 * mu_l, 1e-12 * lambda_l);
  EXPECT_NEAR(kFlesh.alpha, 1.0 + 0.75 * kFlesh.mu / kFlesh.lambda, 1e-15);
  const SnhConstants scaled = msd::snh_constants(E, nu, 2.0);
  EXPECT_NEAR(scaled.mu, 2.0 * kFlesh.mu, 1e-12 * kFlesh.mu);
  EXPECT_NEAR(scaled.lambda, 2.0 * kFlesh.lambda, 1e-12 * kFlesh.lambda);
}

TEST(StableNeoHookean, UnphysicalConstantsAreRefusedByName) {
  for (double nu : {0.5, 0.6, -1.0, -1.5, std::nan("")}) {
    try {
      msd::snh_constants(1000.0, nu);
      FAIL() << "nu = " << nu << " accepted";
    } catch (const msd::Error& e) {
      EXPECT_NE(std::string(e.what()).find("nu"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(msd::snh_constants(0.0, 0.3), msd::Error);
  EXPECT_THROW(msd::snh_constants(-5.0, 0.3), msd::Error);
  EXPECT_THROW(msd::snh_constants(std::numeric_limits<double>::infinity(), 0.3), msd::Error);
}

TEST(StableNeoHookean, TheRestStateIsStressFreeAndForceFree) {
  for (double nu : {0.0, 0.3, 0.45, 0.495, 0.4999}) {
    const SnhConstants c = msd::snh_constants(1e4, nu);
    EXPECT_LT(msd::snh_stress(Mat3::Identity(), c).norm(), 1e-12 * c.mu) << "nu = " << nu;
  }
  Vec3 x[4];
  rest_tet(x);
  const Mat3 dm_inv = msd::rest_shape_inverse(x);
  const double v0 = (x[1] - x[0]).dot((x[2] - x[0]).cross(x[3] - x[0])) / 6.0;
  // Scale: a unit-strain force, mu times a face area.
  EXPECT_LT(forces(x, dm_inv, v0, kFlesh).norm(), 1e-12 * kFlesh.mu * 1e-4);
  EXPECT_NEAR(msd::snh_element_energy(x, dm_inv, v0, kFlesh),
              v0 * (0.5 * kFlesh.lambda * (1 - kFlesh.alpha) * (1 - kFlesh.alpha) - 0.5 * kFlesh.mu * std::log(4.0)),
              1e-12 * kFlesh.mu * v0);
}

TEST(StableNeoHookean, TheStressIsTheEnergysGradientEvenInvertedOrFlat) {
  const double h = 1e-6;
  for (const Mat3& F : test_gradients()) {
    const Mat3 P = msd::snh_stress(F, kFlesh);
    Mat3 fd;
    for (int k = 0; k < 9; ++k) {
      Mat3 up = F, down = F;
      up.data()[k] += h;
      down.data()[k] -= h;
      fd.data()[k] = (msd::snh_energy_density(up, kFlesh) - msd::snh_energy_density(down, kFlesh)) / (2 * h);
    }
    EXPECT_LT((P - fd).norm(), 1e-6 * (P.norm() + kFlesh.mu)) << "F =\n" << F << "\nJ = " << F.determinant();
    EXPECT_TRUE(P.allFinite());
  }
}

TEST(StableNeoHookean, TheStressDerivativeIsTheStresssDerivativeAndSymmetric) {
  const double h = 1e-6;
  for (const Mat3& F : test_gradients()) {
    const Mat9 H = msd::snh_stress_derivative(F, kFlesh);
    Mat9 fd;
    for (int k = 0; k < 9; ++k) {
      Mat3 up = F, down = F;
      up.data()[k] += h;
      down.data()[k] -= h;
      const Mat3 d = (msd::snh_stress(up, kFlesh) - msd::snh_stress(down, kFlesh)) / (2 * h);
      fd.col(k) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(d.data());
    }
    EXPECT_LT((H - fd).norm(), 1e-6 * H.norm()) << "J = " << F.determinant();
    EXPECT_LT((H - H.transpose()).norm(), 1e-12 * H.norm());
  }
}

TEST(StableNeoHookean, LinearisedAtRestItIsLinearElasticityWithTheMaterialsLameConstants) {
  // sigma = 2 mu_L eps + lambda_L tr(eps) I for a small displacement gradient (closed form).
  const double E = 2990.0, nu = 0.495;
  const double mu_l = E / (2 * (1 + nu)), lambda_l = E * nu / ((1 + nu) * (1 - 2 * nu));
  for (unsigned seed : {11u, 12u, 13u}) {
    const Mat3 H = random_matrix(seed, 1.0);
    const double eps = 1e-7;
    const Mat3 strain = 0.5 * eps * (H + H.transpose());
    const Mat3 linear = 2 * mu_l * strain + lambda_l * strain.trace() * Mat3::Identity();
    const Mat3 P = msd::snh_stress(Mat3::Identity() + eps * H, kFlesh);
    EXPECT_LT((P - linear).norm(), 1e-5 * linear.norm()) << "P =\n" << P << "\nlinear =\n" << linear;
  }
}

TEST(StableNeoHookean, TheEnergyIsFrameIndifferentAndTheStressTurnsWithTheBody) {
  const Mat3 R = Eigen::AngleAxisd(0.9, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  for (const Mat3& F : test_gradients()) {
    EXPECT_NEAR(msd::snh_energy_density(R * F, kFlesh), msd::snh_energy_density(F, kFlesh), 1e-9 * kFlesh.lambda);
    EXPECT_LT((msd::snh_stress(R * F, kFlesh) - R * msd::snh_stress(F, kFlesh)).norm(),
              1e-10 * msd::snh_stress(F, kFlesh).norm() + 1e-12 * kFlesh.mu);
  }
}

TEST(StableNeoHookean, TheForcesAreMinusTheElementEnergysGradientWithZeroNetForceAndTorque) {
  Vec3 rest[4];
  rest_tet(rest);
  const Mat3 dm_inv = msd::rest_shape_inverse(rest);
  const double v0 = (rest[1] - rest[0]).dot((rest[2] - rest[0]).cross(rest[3] - rest[0])) / 6.0;
  for (double amount : {0.2, 0.6, 1.5}) {
    Vec3 x[4];
    deformed(rest, amount, 7u, x);
    const auto f = forces(x, dm_inv, v0, kFlesh);
    const double h = 1e-9;
    Eigen::Matrix<double, 12, 1> fd;
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d) {
        Vec3 y[4] = {x[0], x[1], x[2], x[3]};
        y[k][d] += h;
        const double up = msd::snh_element_energy(y, dm_inv, v0, kFlesh);
        y[k][d] -= 2 * h;
        const double down = msd::snh_element_energy(y, dm_inv, v0, kFlesh);
        fd[3 * k + d] = -(up - down) / (2 * h);
      }
    EXPECT_LT((f - fd).norm(), 1e-5 * f.norm()) << "amount " << amount;
    Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      net += f.segment<3>(3 * i);
      torque += x[i].cross(Vec3(f.segment<3>(3 * i)));
    }
    EXPECT_LT(net.norm(), 1e-12 * f.norm());
    EXPECT_LT(torque.norm(), 1e-12 * f.norm() * 0.02);
  }
}

TEST(StableNeoHookean, TheForceJacobianIsTheForcesDerivativeAndSymmetric) {
  Vec3 rest[4];
  rest_tet(rest);
  const Mat3 dm_inv = msd::rest_shape_inverse(rest);
  const double v0 = (rest[1] - rest[0]).dot((rest[2] - rest[0]).cross(rest[3] - rest[0])) / 6.0;
  for (double amount : {0.0, 0.3, 1.5}) {
    Vec3 x[4];
    deformed(rest, amount, 9u, x);
    Mat12 K;
    msd::snh_force_jacobian(x, dm_inv, v0, kFlesh, K);
    Mat12 fd;
    const double h = 1e-8;
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d) {
        Vec3 y[4] = {x[0], x[1], x[2], x[3]};
        y[k][d] += h;
        const auto up = forces(y, dm_inv, v0, kFlesh);
        y[k][d] -= 2 * h;
        const auto down = forces(y, dm_inv, v0, kFlesh);
        fd.col(3 * k + d) = (up - down) / (2 * h);
      }
    EXPECT_LT((K - fd).norm(), 1e-6 * K.norm()) << "amount " << amount;
    EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm());
    // Rigid translations are in its null space.
    for (int d = 0; d < 3; ++d) {
      Eigen::Matrix<double, 12, 1> t = Eigen::Matrix<double, 12, 1>::Zero();
      for (int i = 0; i < 4; ++i) t[3 * i + d] = 1.0;
      EXPECT_LT((K * t).norm(), 1e-10 * K.norm());
    }
  }
}

TEST(StableNeoHookean, AnInvertedElementIsPushedBackTowardsItsRestOrientation) {
  Vec3 x[4];
  rest_tet(x);
  const Mat3 dm_inv = msd::rest_shape_inverse(x);
  const double v0 = (x[1] - x[0]).dot((x[2] - x[0]).cross(x[3] - x[0])) / 6.0;
  // Vertex 3 pushed through the opposite face: J < 0.
  Vec3 y[4] = {x[0], x[1], x[2], x[3] - Vec3(0, 0, 0.014)};
  EXPECT_LT(msd::deformation_gradient(y, dm_inv).determinant(), 0.0);
  const auto f = forces(y, dm_inv, v0, kFlesh);
  EXPECT_TRUE(f.allFinite());
  EXPECT_GT(f[11], 0.0) << "vertex 3 is pulled back up through its face";
  // Collapsed to a point: finite.
  Vec3 z[4] = {x[0], x[0], x[0], x[0]};
  EXPECT_TRUE(forces(z, dm_inv, v0, kFlesh).allFinite());
  EXPECT_TRUE(std::isfinite(msd::snh_element_energy(z, dm_inv, v0, kFlesh)));
}

TEST(StableNeoHookean, ADegenerateRestTetIsRefused) {
  Vec3 x[4] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  EXPECT_THROW(msd::rest_shape_inverse(x), msd::Error);
}

TEST(StableNeoHookean, TheVolumeGradientIsTheTetVolumesDerivative) {
  Vec3 rest[4];
  rest_tet(rest);
  const Mat3 dm_inv = msd::rest_shape_inverse(rest);
  const double v0 = (rest[1] - rest[0]).dot((rest[2] - rest[0]).cross(rest[3] - rest[0])) / 6.0;
  Vec3 x[4];
  deformed(rest, 0.8, 21u, x);
  const auto g = msd::volume_gradient(x, dm_inv, v0);
  const auto volume = [&](const Vec3 y[4]) { return (y[1] - y[0]).dot((y[2] - y[0]).cross(y[3] - y[0])) / 6.0; };
  const double h = 1e-8;
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) {
      Vec3 y[4] = {x[0], x[1], x[2], x[3]};
      y[k][d] += h;
      const double up = volume(y);
      y[k][d] -= 2 * h;
      EXPECT_NEAR(g(d, k), (up - volume(y)) / (2 * h), 1e-7 * g.norm()) << "vertex " << k << " axis " << d;
    }
}

TEST(StableNeoHookean, ATetAloneInItsVolumeGroupIsTheElementItself) {
  // Shear energy + lambda/2 (J - alpha)^2 is Psi; the shear forces at the tet's own
  // pressure are its forces; the stiffness at that pressure minus (lambda / V0) g g^T is its stiffness.
  Vec3 rest[4];
  rest_tet(rest);
  const Mat3 dm_inv = msd::rest_shape_inverse(rest);
  const double v0 = (rest[1] - rest[0]).dot((rest[2] - rest[0]).cross(rest[3] - rest[0])) / 6.0;
  Vec3 x[4];
  deformed(rest, 0.7, 23u, x);
  const Mat3 F = msd::deformation_gradient(x, dm_inv);
  const double J = F.determinant(), p = msd::snh_pressure(J, kFlesh);
  EXPECT_NEAR(msd::snh_shear_energy_density(F, kFlesh) + 0.5 * kFlesh.lambda * (J - kFlesh.alpha) * (J - kFlesh.alpha),
              msd::snh_energy_density(F, kFlesh), 1e-12 * kFlesh.lambda);
  // At a fixed pressure p the forces are -d/dx [V0 Psi_shear(F) + p V], by central differences
  // (independent of add_snh_forces, which calls add_snh_forces_at_pressure).
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  msd::add_snh_forces_at_pressure(x, dm_inv, v0, kFlesh, p, f);
  const auto energy_at_p = [&](const Vec3 y[4]) {
    const double volume = (y[1] - y[0]).dot((y[2] - y[0]).cross(y[3] - y[0])) / 6.0;
    return v0 * msd::snh_shear_energy_density(msd::deformation_gradient(y, dm_inv), kFlesh) + p * volume;
  };
  double scale = 0.0;
  for (int i = 0; i < 4; ++i) scale = std::max(scale, f[i].norm());
  const double h = 1e-9;
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) {
      Vec3 y[4] = {x[0], x[1], x[2], x[3]};
      y[k][d] += h;
      const double up = energy_at_p(y);
      y[k][d] -= 2 * h;
      EXPECT_NEAR(f[k][d], -(up - energy_at_p(y)) / (2 * h), 1e-5 * scale) << "vertex " << k << " axis " << d;
    }
  Mat12 Kp, K;
  msd::snh_force_jacobian_at_pressure(x, dm_inv, v0, kFlesh, p, Kp);
  msd::snh_force_jacobian(x, dm_inv, v0, kFlesh, K);
  const auto g = msd::volume_gradient(x, dm_inv, v0);
  const Eigen::Map<const Eigen::Matrix<double, 12, 1>> gv(g.data());
  EXPECT_LT((Kp - (kFlesh.lambda / v0) * gv * gv.transpose() - K).norm(), 1e-10 * K.norm());
}
