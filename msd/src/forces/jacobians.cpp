#include "msd/forces/jacobians.hpp"

#include "msd/forces/element_forces.hpp"

#include "msd/forces/face_repulsion.hpp"
#include "msd/forces/muscle_units.hpp"
#include "msd/forces/tendon.hpp"
#include "msd/forces/tet_frame.hpp"
#include "msd/forces/volume_preservation.hpp"

#include <algorithm>

namespace msd {

Mat3 edge_spring_jacobian(const Vec3& l, double rest, double ks) {
  const double length = l.norm();
  const Vec3 u = l / length;
  return ks * ((1.0 - rest / length) * Mat3::Identity() + (rest / length) * u * u.transpose());
}

void edge_damper_jacobians(const Vec3& l, const Vec3& w, double kd, Mat3& dfa_dl, Mat3& dfa_dw) {
  const double l2 = l.squaredNorm();
  const double wl = w.dot(l);
  dfa_dw = (kd / l2) * l * l.transpose();
  dfa_dl = (kd / l2) * (l * w.transpose() + wl * Mat3::Identity() - (2.0 * wl / l2) * l * l.transpose());
}

double face_repulsion_slope(double x, double x0, double kr, double floor) {
  const double xc = floor * x0;
  const double at = x >= xc ? x : xc;
  return -kr * (x0 * x0 / (at * at) + 1.0);
}

namespace {

// The shape measures of tet_frame plus the edges they came from.
struct Frame {
  TetFrame g;
  Vec3 e[4];  // e[1..3] = x_k - x_0
  double n[4];
  double six_v;
};

Frame frame(const Vec3 x[4]) {
  Frame f;
  f.g = tet_frame(x);
  for (int k = 1; k < 4; ++k) f.e[k] = x[k] - x[0];
  for (int i = 0; i < 4; ++i) f.n[i] = 1.0 / f.g.inv_norm[i];
  f.six_v = 6.0 * f.g.volume;
  return f;
}

}  // namespace

bool nonlinear_element_jacobian(const Model& model, const Element& el, const Vec3 x[4], Mat12& K) {
  K.setZero();
  const unsigned terms = model.terms;
  if (!(terms & (kRepulsion | kVolume))) return false;
  if (model.nonlinear_threshold > 0.0 && !nonlinear_terms_active(el, model.nonlinear_threshold, x)) return false;
  const Frame fr = frame(x);
  const TetFrame& g = fr.g;
  const bool rep = terms & kRepulsion, vol = terms & kVolume;
  // Magnitudes and their derivatives with respect to h_i (repulsion) and to
  // 6V and |m_i| (volume), at the current shape.
  double f[4], dfdh[4], p[4], s[4], d[4][4];
  for (int i = 0; i < 4; ++i) {
    f[i] = 0.0;
    dfdh[i] = 0.0;
    if (rep) {
      f[i] += face_repulsion_magnitude(g.height[i], el.rest_height[i], el.k.k_r[i], el.floor);
      dfdh[i] = face_repulsion_slope(g.height[i], el.rest_height[i], el.k.k_r[i], el.floor);
    }
    if (vol) f[i] += volume_force_magnitude(g, i, el.rest_volume, el.k.k_v[i]);
    p[i] = f[i] / fr.n[i];
    s[i] = p[i] / (fr.n[i] * fr.n[i]);
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) d[i][j] = g.m[i].dot(g.m[j]);
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) {
      // Direction: x_k moves along axis c.
      Vec3 de[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
      for (int q = 1; q < 4; ++q) {
        if (q == k) de[q][c] += 1.0;
        if (k == 0) de[q][c] -= 1.0;
      }
      Vec3 dm[4];
      dm[1] = de[2].cross(fr.e[3]) + fr.e[2].cross(de[3]);
      dm[2] = de[3].cross(fr.e[1]) + fr.e[3].cross(de[1]);
      dm[3] = de[1].cross(fr.e[2]) + fr.e[1].cross(de[2]);
      dm[0] = -(dm[1] + dm[2] + dm[3]);
      const double d6v = g.m[k][c];  // d(6V)/dx_k = m_k
      double df[4], dp[4], ds[4];
      for (int i = 0; i < 4; ++i) {
        const double n = fr.n[i];
        const double dn = g.m[i].dot(dm[i]) / n;
        df[i] = 0.0;
        if (rep) df[i] += dfdh[i] * (d6v / n - fr.six_v * dn / (n * n));
        if (vol) {
          const double kv = el.k.k_v[i];
          df[i] += -kv * d6v / n - kv * 6.0 * (el.rest_volume - g.volume) * dn / (n * n);
        }
        dp[i] = df[i] / n - f[i] * dn / (n * n);
        ds[i] = df[i] / (n * n * n) - 3.0 * f[i] * dn / (n * n * n * n);
      }
      for (int j = 0; j < 4; ++j) {
        Vec3 dF = dp[j] * g.m[j] + p[j] * dm[j];
        for (int i = 0; i < 4; ++i) {
          if (i == j) continue;
          const double ddij = dm[i].dot(g.m[j]) + g.m[i].dot(dm[j]);
          dF += (ds[i] * d[i][j] + s[i] * ddij) * g.m[i] + (s[i] * d[i][j]) * dm[i];
        }
        K.block<3, 1>(3 * j, 3 * k + c) = dF;
      }
    }
  return true;
}

Mat3 muscle_unit_jacobian(const Vec3& l, double rest_length, double force, const ForceLength& fl) {
  const double len = l.norm();
  if (!(len > 0.0) || force == 0.0) return Mat3::Zero();
  const Vec3 u = l / len;
  const double lambda = len / rest_length;
  const double fL = fl.enabled ? force_length_factor(lambda, fl.zero_at) : 1.0;
  double slope = 0.0;  // d f_L / d lambda
  if (fl.enabled && lambda > fl.zero_at && lambda < 1.0) slope = 2.0 * (1.0 - lambda) / ((1.0 - fl.zero_at) * (1.0 - fl.zero_at));
  const Mat3 uu = u * u.transpose();
  return (force * fL / len) * (Mat3::Identity() - uu) + (force * slope / rest_length) * uu;
}

void hill_unit_jacobians(const Vec3& l, const Vec3& w, double rest_length, double activation, double unit_force,
                         const HillMuscle& hill, Mat3& dfa_dl, Mat3& dfa_dw) {
  const double len = l.norm();
  if (!(len > 0.0)) {
    dfa_dl.setZero();
    dfa_dw.setZero();
    return;
  }
  const Vec3 u = l / len;
  const UnitTension t = hill_unit_tension(len, u.dot(w), rest_length, activation, unit_force, hill);
  const Mat3 uu = u * u.transpose();
  dfa_dl = (t.T / len) * (Mat3::Identity() - uu) + t.dT_dlength * uu;
  dfa_dw = t.dT_drate * uu;
}

bool strand_jacobian(const Points& p, double natural_length, double k_t, Eigen::MatrixXd& K, double toe) {
  const Eigen::Index m = p.cols();
  if (K.rows() != 3 * m || K.cols() != 3 * m) K.resize(3 * m, 3 * m);
  K.setZero();
  double length = 0.0;
  for (Eigen::Index s = 0; s + 1 < m; ++s) length += (p.col(s + 1) - p.col(s)).norm();
  double slope = 0.0;
  const double tension = tendon_tension(length, natural_length, k_t, toe, &slope);
  if (!(tension > 0.0)) return false;
  // The curvature blocks of sum |d_s|.
  for (Eigen::Index s = 0; s + 1 < m; ++s) {
    const Vec3 d = p.col(s + 1) - p.col(s);
    const double len = d.norm();
    if (!(len > 0.0)) continue;  // coincident points: no direction, no force (add_tendon_forces)
    const Vec3 u = d / len;
    const Mat3 c = (tension / len) * (Mat3::Identity() - u * u.transpose());
    K.block<3, 3>(3 * s, 3 * s) -= c;
    K.block<3, 3>(3 * (s + 1), 3 * (s + 1)) -= c;
    K.block<3, 3>(3 * s, 3 * (s + 1)) += c;
    K.block<3, 3>(3 * (s + 1), 3 * s) += c;
  }
  // -slope g g^T with g_i = dL/dp_i = u_{i-1} - u_i (no allocation: the
  // IMEX step calls this every step, imex_strands.hpp).
  auto unit = [&](Eigen::Index s) -> Vec3 {
    if (s < 0 || s + 1 >= m) return Vec3::Zero();
    const Vec3 d = p.col(s + 1) - p.col(s);
    const double len = d.norm();
    return len > 0.0 ? Vec3(d / len) : Vec3::Zero();
  };
  for (Eigen::Index i = 0; i < m; ++i) {
    const Vec3 gi = slope * (unit(i - 1) - unit(i));
    for (Eigen::Index j = 0; j < m; ++j) K.block<3, 3>(3 * i, 3 * j) -= gi * (unit(j - 1) - unit(j)).transpose();
  }
  return true;
}

}  // namespace msd
