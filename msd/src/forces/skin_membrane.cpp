#include "msd/forces/skin_membrane.hpp"

#include <cmath>
#include <string>

namespace msd {

namespace {

using Mat32 = Eigen::Matrix<double, 3, 2>;

// D_s = [x_1 - x_0, x_2 - x_0] of triangle t at x.
Mat32 edges(const MembraneTriangle& t, const Points& x) {
  Mat32 d;
  d.col(0) = x.col(t.nodes[1]) - x.col(t.nodes[0]);
  d.col(1) = x.col(t.nodes[2]) - x.col(t.nodes[0]);
  return d;
}

// adj C = J2 C^-1 of a symmetric 2 x 2 matrix (linear in C).
Eigen::Matrix2d adjugate(const Eigen::Matrix2d& c) {
  Eigen::Matrix2d a;
  a << c(1, 1), -c(0, 1), -c(1, 0), c(0, 0);
  return a;
}

// g(J2) (1/J2 above s = floor^2, its Taylor polynomial below) and its first
// two derivatives.
struct G {
  double g, d1, d2;
};
G g_of(double j2, double floor) {
  const double s = floor * floor;
  if (j2 >= s) return {1.0 / j2, -1.0 / (j2 * j2), 2.0 / (j2 * j2 * j2)};
  const double d = j2 - s;
  return {1.0 / s - d / (s * s) + d * d / (s * s * s), -1.0 / (s * s) + 2.0 * d / (s * s * s), 2.0 / (s * s * s)};
}

}  // namespace

SkinMembrane make_skin_membrane(const Points& rest, const std::vector<Tri>& faces, double youngs_modulus,
                                double thickness) {
  if (!(youngs_modulus > 0.0) || !std::isfinite(youngs_modulus))
    throw Error("skin: Young's modulus must be positive and finite (got " + std::to_string(youngs_modulus) + " Pa)");
  if (!(thickness > 0.0) || !std::isfinite(thickness))
    throw Error("skin: thickness must be positive and finite (got " + std::to_string(thickness) + " m)");
  SkinMembrane skin;
  skin.shear_modulus = youngs_modulus / 3.0;
  skin.thickness = thickness;
  skin.triangles.reserve(faces.size());
  for (size_t k = 0; k < faces.size(); ++k) {
    MembraneTriangle t;
    for (int i = 0; i < 3; ++i) {
      const int v = faces[k][static_cast<size_t>(i)];
      if (v < 0 || v >= rest.cols())
        throw Error("skin: face " + std::to_string(k) + " names node " + std::to_string(v) + " of " +
                    std::to_string(rest.cols()));
      t.nodes[static_cast<size_t>(i)] = v;
    }
    const Mat32 d = edges(t, rest);
    const Vec3 normal = Vec3(d.col(0)).cross(Vec3(d.col(1)));
    t.rest_area = 0.5 * normal.norm();
    if (!(t.rest_area > 0.0)) throw Error("skin: face " + std::to_string(k) + " has zero area at rest");
    // The rest edges in the triangle's own frame: t1 along edge 1, t2 in the
    // plane, normal to it.
    const Vec3 t1 = d.col(0).normalized();
    const Vec3 t2 = normal.normalized().cross(t1);
    Eigen::Matrix2d dm;
    dm << t1.dot(d.col(0)), t1.dot(d.col(1)), t2.dot(d.col(0)), t2.dot(d.col(1));
    t.rest_inverse = dm.inverse();
    skin.triangles.push_back(t);
  }
  return skin;
}

double membrane_energy(const SkinMembrane& skin, const Points& x) {
  double w = 0.0;
  for (const MembraneTriangle& t : skin.triangles) {
    const Mat32 F = edges(t, x) * t.rest_inverse;
    const Eigen::Matrix2d C = F.transpose() * F;
    w += t.rest_area * (C.trace() + g_of(C.determinant(), skin.area_floor).g - 3.0);
  }
  return 0.5 * skin.shear_modulus * skin.thickness * w;
}

void add_membrane_forces(const SkinMembrane& skin, const Points& x, Points& f, int threads, Points& corner) {
  const double hmu = skin.shear_modulus * skin.thickness;
  const long n = static_cast<long>(skin.triangles.size());
  if (corner.cols() != 3 * n) corner.resize(3, 3 * n);
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(static)
  for (long k = 0; k < n; ++k) {
    const MembraneTriangle& t = skin.triangles[static_cast<size_t>(k)];
    const Mat32 F = edges(t, x) * t.rest_inverse;
    const Eigen::Matrix2d C = F.transpose() * F;
    const Mat32 P = F + g_of(C.determinant(), skin.area_floor).d1 * (F * adjugate(C));  // / (h mu)
    const Mat32 g = (hmu * t.rest_area) * P * t.rest_inverse.transpose();  // dW/dD_s
    corner.col(3 * k) = g.col(0) + g.col(1);
    corner.col(3 * k + 1) = -g.col(0);
    corner.col(3 * k + 2) = -g.col(1);
  }
  for (long k = 0; k < n; ++k) {
    const MembraneTriangle& t = skin.triangles[static_cast<size_t>(k)];
    for (int i = 0; i < 3; ++i) f.col(t.nodes[static_cast<size_t>(i)]) += corner.col(3 * k + i);
  }
}

void add_membrane_forces(const SkinMembrane& skin, const Points& x, Points& f) {
  Points corner;
  add_membrane_forces(skin, x, f, 1, corner);
}

Mat9 membrane_triangle_stiffness(const SkinMembrane& skin, size_t k, const Points& x) {
  const MembraneTriangle& t = skin.triangles[k];
  const double c = skin.shear_modulus * skin.thickness * t.rest_area;
  const Mat32 F = edges(t, x) * t.rest_inverse;
  const Eigen::Matrix2d C = F.transpose() * F;
  const Eigen::Matrix2d A = adjugate(C);
  const G gj = g_of(C.determinant(), skin.area_floor);
  const Mat32 FA = F * A;
  Mat9 K;
  // Column (3 j + a): the forces' change for a unit move of node j along axis a.
  for (int j = 0; j < 3; ++j)
    for (int a = 0; a < 3; ++a) {
      Mat32 dDs = Mat32::Zero();
      if (j == 0) dDs.row(a).setConstant(-1.0);
      else dDs(a, j - 1) = 1.0;
      const Mat32 dF = dDs * t.rest_inverse;
      const Eigen::Matrix2d dC = dF.transpose() * F + F.transpose() * dF;
      const Mat32 dP = dF + gj.d1 * (dF * A + F * adjugate(dC)) + (gj.d2 * (A * dC).trace()) * FA;
      const Mat32 dg = c * dP * t.rest_inverse.transpose();
      const int col = 3 * j + a;
      K.block<3, 1>(0, col) = dg.col(0) + dg.col(1);
      K.block<3, 1>(3, col) = -dg.col(0);
      K.block<3, 1>(6, col) = -dg.col(1);
    }
  return K;
}

}  // namespace msd
