#include "msd/forces/bulk_volume.hpp"

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

void add_bulk_forces(const Vec3 x[4], double pressure, Vec3 f[4]) {
  Vec3 g[4];
  tet_volume_gradient(x, g);
  for (int i = 0; i < 4; ++i) f[i] -= pressure * g[i];
}

void add_bulk_pressure_jacobian(const Vec3 x[4], double pressure, Mat12& K) {
  K.noalias() -= pressure * tet_volume_hessian(x);
}

}  // namespace msd
