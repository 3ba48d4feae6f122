#include "msd/forces/bulk_volume.hpp"

#include <algorithm>
#include <cmath>

namespace msd {

void tet_volume_gradient(const Vec3 x[4], Vec3 g[4]) {
  const Vec3 a = x[1] - x[0], b = x[2] - x[0], c = x[3] - x[0];
  g[1] = b.cross(c) / 6.0;
  g[2] = c.cross(a) / 6.0;
  g[3] = a.cross(b) / 6.0;
  g[0] = -(g[1] + g[2] + g[3]);
}

Mat12 tet_volume_hessian(const Vec3 x[4]) {
  const Vec3 a = x[1] - x[0], b = x[2] - x[0], c = x[3] - x[0];
  // H[p][q] = d2V / (d e_p d e_q) for the edge vectors e = (a, b, c).
  Mat3 H[3][3];
  H[0][0] = H[1][1] = H[2][2] = Mat3::Zero();
  H[0][1] = -cross_matrix(c) / 6.0;
  H[0][2] = cross_matrix(b) / 6.0;
  H[1][2] = -cross_matrix(a) / 6.0;
  H[1][0] = H[0][1].transpose();
  H[2][0] = H[0][2].transpose();
  H[2][1] = H[1][2].transpose();
  // e_p = x_(p+1) - x_0: block (i, j) = sum_pq T(p, i) T(q, j) H[p][q] with
  // T(p, p + 1) = 1 and T(p, 0) = -1.
  const auto t = [](int p, int i) { return i == 0 ? -1.0 : (i == p + 1 ? 1.0 : 0.0); };
  Mat12 out;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      Mat3 block = Mat3::Zero();
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) {
          const double w = t(p, i) * t(q, j);
          if (w != 0.0) block += w * H[p][q];
        }
      out.block<3, 3>(3 * i, 3 * j) = block;
    }
  return out;
}

namespace {

// The neo-Hookean law's W, W', W'' for J above the floor.
double neo_w(const BulkLaw& b, double J) {
  const double ln = std::log(J);
  return -b.rest_modulus * ln + 0.25 * b.modulus * (J * J - 1.0 - 2.0 * ln);
}
double neo_p(const BulkLaw& b, double J) { return -b.rest_modulus / J + 0.5 * b.modulus * (J - 1.0 / J); }
double neo_k(const BulkLaw& b, double J) { return b.rest_modulus / (J * J) + 0.5 * b.modulus * (1.0 + 1.0 / (J * J)); }

}  // namespace

double bulk_law_energy(const BulkLaw& b, double J) {
  if (!b.neo_hookean) return 0.5 * b.modulus * (J - 1.0) * (J - 1.0);
  if (J >= kBulkFloor) return neo_w(b, J);
  const double d = J - kBulkFloor;
  return neo_w(b, kBulkFloor) + neo_p(b, kBulkFloor) * d + 0.5 * neo_k(b, kBulkFloor) * d * d;
}

double bulk_law_pressure(const BulkLaw& b, double J) {
  if (!b.neo_hookean) return b.modulus * (J - 1.0);
  if (J >= kBulkFloor) return neo_p(b, J);
  return neo_p(b, kBulkFloor) + neo_k(b, kBulkFloor) * (J - kBulkFloor);
}

double bulk_law_stiffness(const BulkLaw& b, double J) {
  if (!b.neo_hookean) return b.modulus;
  return neo_k(b, std::max(J, kBulkFloor));
}

void add_bulk_forces(const Vec3 x[4], double pressure, Vec3 f[4]) {
  Vec3 g[4];
  tet_volume_gradient(x, g);
  for (int i = 0; i < 4; ++i) f[i] -= pressure * g[i];
}

void add_bulk_pressure_jacobian(const Vec3 x[4], double pressure, Mat12& K) {
  K.noalias() -= pressure * tet_volume_hessian(x);
}

}  // namespace msd
