// Current shape measures of one tetrahedron used by the non-linear element terms
// (thesis 5.2.3-5.2.5): signed volume, the face area vectors, the signed height of
// each vertex over the plane of its opposite face, and where each vertex projects
// onto that plane in barycentric coordinates (the moment arms of eq. 5.3).
#pragma once

#include "msd/core/types.hpp"

namespace msd {

/// For vertices x[0..3] of a tet:
///  - volume: signed volume, positive for the rest orientation;
///  - m[i]  = d(6 V)/d x[i] = twice the area of the face opposite vertex i times
///            the unit normal of that face pointing towards x[i] while the tet is
///            positively oriented (m[1] = e2 x e3, m[2] = e3 x e1, m[3] = e1 x e2
///            with e_k = x[k] - x[0], and m[0] = -(m[1] + m[2] + m[3]));
///  - inv_norm[i] = 1 / |m[i]|;
///  - height[i] = 6 V / |m[i]|: signed distance of x[i] from the plane of its
///            opposite face, negative once the vertex has passed through it.
struct TetFrame {
  double volume;
  Vec3 m[4];
  double inv_norm[4];
  double height[4];
};

inline TetFrame tet_frame(const Vec3 x[4]) {
  TetFrame g;
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  g.m[1] = e2.cross(e3);
  g.m[2] = e3.cross(e1);
  g.m[3] = e1.cross(e2);
  g.m[0] = -(g.m[1] + g.m[2] + g.m[3]);
  const double six_v = e1.dot(g.m[1]);
  g.volume = six_v / 6.0;
  for (int i = 0; i < 4; ++i) {
    g.inv_norm[i] = 1.0 / g.m[i].norm();
    g.height[i] = six_v * g.inv_norm[i];
  }
  return g;
}

/// Barycentric coordinate, with respect to face vertex j, of the projection P_i
/// of vertex i onto the plane of its opposite face:
///   beta_ij = -(m[i] . m[j]) / |m[i]|^2,   sum over j != i of beta_ij = 1.
/// It equals the ratio of moment arms d^P / d^j of thesis eq. 5.3 (signed, so
/// the balance also holds when P_i falls outside the face).
inline double projection_weight(const TetFrame& g, int i, int j) {
  return -g.m[i].dot(g.m[j]) * g.inv_norm[i] * g.inv_norm[i];
}

/// Applies an internal force of signed magnitude `f` to vertex i along the unit
/// normal of its opposite face (positive: away from the face), and the
/// equalising forces of thesis eq. 5.3 to the other three vertices:
///   F_i = f n_i,   F_j = -beta_ij F_i   (j != i).
/// The four forces sum to zero and have zero moment about any point, because
/// sum_j beta_ij x_j is the projection P_i and F_i is parallel to x_i - P_i.
inline void add_balanced_normal_force(const TetFrame& g, int i, double f, Vec3 out[4]) {
  const Vec3 fi = (f * g.inv_norm[i]) * g.m[i];
  out[i] += fi;
  for (int j = 0; j < 4; ++j)
    if (j != i) out[j] -= projection_weight(g, i, j) * fi;
}

/// add_balanced_normal_force for all four vertices at once, with magnitudes
/// f[0..3]. Same result, fewer operations: with p_i = f_i / |m_i| and
/// s_i = f_i / |m_i|^3, vertex j receives  p_j m_j + sum_{i != j} s_i (m_i . m_j) m_i.
inline void add_balanced_normal_forces(const TetFrame& g, const double f[4], Vec3 out[4]) {
  double p[4], s[4];
  for (int i = 0; i < 4; ++i) {
    p[i] = f[i] * g.inv_norm[i];
    s[i] = p[i] * g.inv_norm[i] * g.inv_norm[i];
  }
  double d[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) d[i][j] = d[j][i] = g.m[i].dot(g.m[j]);
  for (int j = 0; j < 4; ++j) {
    Vec3 acc = p[j] * g.m[j];
    for (int i = 0; i < 4; ++i)
      if (i != j) acc += (s[i] * d[i][j]) * g.m[i];
    out[j] += acc;
  }
}

}  // namespace msd
