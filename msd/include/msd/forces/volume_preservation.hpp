// Volume preservation with equalising forces (thesis 5.2.5, eq. 5.5): each vertex
// is pulled towards the height over its opposite face at which the tet would
// have its rest volume V0,
//   V_A = k_v (3 V0 / Area_BCD - PA) PA / |PA|                      (eq. 5.5)
//       = k_v 6 (V0 - V) / |m_A| n_A      (with signed height PA = 6 V / |m_A|),
// a spring whose natural length follows the current face area. The other three
// vertices take the equalising forces of eq. 5.3. The force vanishes exactly at
// V = V0 and, being signed, drives an inverted tet (V < 0) back towards V0.
// Unlike face repulsion it is not the gradient of an energy (the equalising
// forces are normal to the face only), but net force and torque are zero.
#pragma once

#include "msd/forces/tet_frame.hpp"

namespace msd {

/// Signed magnitude of eq. 5.5 for vertex i (positive: away from its face).
inline double volume_force_magnitude(const TetFrame& g, int i, double rest_volume, double kv) {
  return kv * 6.0 * (rest_volume - g.volume) * g.inv_norm[i];
}

/// Adds volume-preserving and equalising forces for all four vertices of a tet.
inline void add_volume_preservation(const TetFrame& g, double rest_volume, const double kv[4],
                                    Vec3 f[4]) {
  for (int i = 0; i < 4; ++i)
    add_balanced_normal_force(g, i, volume_force_magnitude(g, i, rest_volume, kv[i]), f);
}

}  // namespace msd
