// Edge dampers of the MSD element (thesis 5.1.2, second line of eq. 5.4): a
// dashpot in parallel with each edge spring, acting along the edge on the rate
// of change of its length,
//   F_a = k_d ((v_b - v_a) . l / |l|) l / |l|  on vertex a, l = x_b - x_a,
// and the opposite force on b. It dissipates energy at the rate
// k_d (d|l|/dt)^2 and exerts no force on rigid motions.
#pragma once

#include "msd/forces/edge_frame.hpp"

namespace msd {

/// The damper force on vertex a as a multiple of l: k_d ((v_b - v_a) . l) / |l|^2,
/// from that dot product and 1 / |l|. Shared by the per-tet loop and the
/// engine's edge pass.
inline double edge_damper_factor(double kd, double rate_dot, double inv_length) {
  return kd * rate_dot * inv_length * inv_length;
}

/// Adds the six damper forces of one tet to f[0..3] (kd in edge order).
inline void add_edge_dampers(const EdgeFrame& g, const Vec3 v[4], const double kd[6], Vec3 f[4]) {
  for (int e = 0; e < 6; ++e) {
    const int a = kTetEdges[e][0], b = kTetEdges[e][1];
    const Vec3 fa = edge_damper_factor(kd[e], (v[b] - v[a]).dot(g.l[e]), g.inv_length[e]) * g.l[e];
    f[a] += fa;
    f[b] -= fa;
  }
}

}  // namespace msd
