#include "msd/forces/stable_neo_hookean.hpp"

#include <Eigen/LU>

#include <cmath>
#include <string>

namespace msd {

namespace {

// dJ/dF = [f1 x f2, f2 x f0, f0 x f1].
Mat3 det_gradient(const Mat3& F) {
  Mat3 g;
  g.col(0) = F.col(1).cross(F.col(2));
  g.col(1) = F.col(2).cross(F.col(0));
  g.col(2) = F.col(0).cross(F.col(1));
  return g;
}

// The shape-function gradients as a 4 x 3 matrix: row i is G_i.
Eigen::Matrix<double, 4, 3> shape_gradients(const Mat3& dm_inv) {
  Eigen::Matrix<double, 4, 3> G;
  G.bottomRows<3>() = dm_inv;
  G.row(0) = -dm_inv.colwise().sum();
  return G;
}

// H += s d^2 J / dF^2: blocks (c, d) = [[0, -f2^, f1^], [f2^, 0, -f0^], [-f1^, f0^, 0]].
void add_det_hessian(const Mat3& F, double s, Mat9& H) {
  const Mat3 h0 = s * cross_matrix(F.col(0)), h1 = s * cross_matrix(F.col(1)), h2 = s * cross_matrix(F.col(2));
  H.block<3, 3>(0, 3) -= h2;
  H.block<3, 3>(0, 6) += h1;
  H.block<3, 3>(3, 0) += h2;
  H.block<3, 3>(3, 6) -= h0;
  H.block<3, 3>(6, 0) -= h1;
  H.block<3, 3>(6, 3) += h0;
}

}  // namespace

SnhConstants snh_constants(double youngs_modulus, double poisson_ratio, double scale) {
  const double E = scale * youngs_modulus, nu = poisson_ratio;
  if (!(E > 0.0) || !std::isfinite(E) || !(nu > -1.0 && nu < 0.5))
    throw Error("stable neo-Hookean: needs E > 0 and nu in (-1, 0.5), got E = " + std::to_string(E) +
                " Pa, nu = " + std::to_string(nu));
  const double mu_l = E / (2.0 * (1.0 + nu));
  const double lambda_l = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  SnhConstants c;
  c.mu = 4.0 / 3.0 * mu_l;
  c.lambda = lambda_l + 5.0 / 6.0 * mu_l;
  // lambda / mu_L = 2 nu / (1 - 2 nu) + 5/6 > 0 for every nu in (-1, 0.5): alpha is finite.
  c.alpha = 1.0 + 0.75 * c.mu / c.lambda;
  return c;
}

double snh_energy_density(const Mat3& F, const SnhConstants& c) {
  const double ic = F.squaredNorm(), j = F.determinant();
  return 0.5 * c.mu * (ic - 3.0) + 0.5 * c.lambda * (j - c.alpha) * (j - c.alpha) - 0.5 * c.mu * std::log(ic + 1.0);
}

Mat3 snh_stress(const Mat3& F, const SnhConstants& c) {
  const double ic = F.squaredNorm(), j = F.determinant();
  return c.mu * (1.0 - 1.0 / (ic + 1.0)) * F + c.lambda * (j - c.alpha) * det_gradient(F);
}

Mat9 snh_stress_derivative(const Mat3& F, const SnhConstants& c) {
  const double ic = F.squaredNorm(), j = F.determinant();
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> f(F.data());
  const Mat3 gm = det_gradient(F);
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> g(gm.data());
  Mat9 H = (c.mu * (1.0 - 1.0 / (ic + 1.0))) * Mat9::Identity();
  H.noalias() += (2.0 * c.mu / ((ic + 1.0) * (ic + 1.0))) * f * f.transpose();
  H.noalias() += c.lambda * g * g.transpose();
  add_det_hessian(F, c.lambda * (j - c.alpha), H);
  return H;
}

Mat3 rest_shape_inverse(const Vec3 x[4]) {
  Mat3 dm;
  for (int k = 0; k < 3; ++k) dm.col(k) = x[k + 1] - x[0];
  const double det = dm.determinant();
  const double scale = dm.colwise().norm().prod();
  if (!(std::abs(det) > 1e-12 * scale)) throw Error("stable neo-Hookean: a degenerate tet at rest (6 V = " + std::to_string(det) + ")");
  return dm.inverse();
}

Mat3 deformation_gradient(const Vec3 x[4], const Mat3& dm_inv) {
  Mat3 ds;
  for (int k = 0; k < 3; ++k) ds.col(k) = x[k + 1] - x[0];
  return ds * dm_inv;
}

double snh_element_energy(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c) {
  return rest_volume * snh_energy_density(deformation_gradient(x, dm_inv), c);
}

void add_snh_forces(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c, Vec3 f[4]) {
  add_snh_forces_at_pressure(x, dm_inv, rest_volume, c, snh_pressure(deformation_gradient(x, dm_inv).determinant(), c), f);
}

double snh_shear_energy_density(const Mat3& F, const SnhConstants& c) {
  const double ic = F.squaredNorm();
  return 0.5 * c.mu * (ic - 3.0) - 0.5 * c.mu * std::log(ic + 1.0);
}

void add_snh_forces_at_pressure(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c,
                                double pressure, Vec3 f[4]) {
  const Mat3 F = deformation_gradient(x, dm_inv);
  const Mat3 P = c.mu * (1.0 - 1.0 / (F.squaredNorm() + 1.0)) * F + pressure * det_gradient(F);
  const Mat3 h = -rest_volume * P * dm_inv.transpose();
  for (int k = 0; k < 3; ++k) {
    f[k + 1] += h.col(k);
    f[0] -= h.col(k);
  }
}

Eigen::Matrix<double, 3, 4> volume_gradient(const Vec3 x[4], const Mat3& dm_inv, double rest_volume) {
  const Mat3 h = rest_volume * det_gradient(deformation_gradient(x, dm_inv)) * dm_inv.transpose();
  Eigen::Matrix<double, 3, 4> g;
  g.rightCols<3>() = h;
  g.col(0) = -h.rowwise().sum();
  return g;
}

namespace {

// -V0 B^T H B for a 9 x 9 dP/dF H.
void stiffness_from(const Mat9& H, const Mat3& dm_inv, double rest_volume, Mat12& K) {
  const Eigen::Matrix<double, 4, 3> G = shape_gradients(dm_inv);
  // B = d vec F / dx: F_ac depends on x_i's component a through G_i(c).
  Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
  for (int i = 0; i < 4; ++i)
    for (int col = 0; col < 3; ++col)
      for (int a = 0; a < 3; ++a) B(a + 3 * col, 3 * i + a) = G(i, col);
  const Eigen::Matrix<double, 9, 12> HB = H * B;
  K.noalias() = -rest_volume * B.transpose() * HB;
}

}  // namespace

void snh_force_jacobian_at_pressure(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c,
                                    double pressure, Mat12& K) {
  const Mat3 F = deformation_gradient(x, dm_inv);
  const double ic = F.squaredNorm();
  const Eigen::Map<const Eigen::Matrix<double, 9, 1>> f(F.data());
  Mat9 H = (c.mu * (1.0 - 1.0 / (ic + 1.0))) * Mat9::Identity();
  H.noalias() += (2.0 * c.mu / ((ic + 1.0) * (ic + 1.0))) * f * f.transpose();
  add_det_hessian(F, pressure, H);
  stiffness_from(H, dm_inv, rest_volume, K);
}

void snh_force_jacobian(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c, Mat12& K) {
  stiffness_from(snh_stress_derivative(deformation_gradient(x, dm_inv), c), dm_inv, rest_volume, K);
}

}  // namespace msd
