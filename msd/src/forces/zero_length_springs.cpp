#include "msd/forces/zero_length_springs.hpp"

#include "msd/forces/bulk_volume.hpp"
#include "msd/mesh/tet_mesh.hpp"

namespace msd {

void cotangent_weights(const Vec3 X[4], double w[6]) {
  const double v = tet_signed_volume(X[0], X[1], X[2], X[3]);
  if (!(v > 0.0)) throw Error("cotangent_weights: the tet's rest volume is not positive (" + std::to_string(v) + " m^3)");
  Vec3 g[4];
  tet_volume_gradient(X, g);
  for (int e = 0; e < 6; ++e) w[e] = -g[kTetEdges[e][0]].dot(g[kTetEdges[e][1]]) / v;
}

double zero_length_spring_energy(const Vec3 x[4], const double k[6]) {
  double u = 0.0;
  for (int e = 0; e < 6; ++e) u += 0.5 * k[e] * (x[kTetEdges[e][1]] - x[kTetEdges[e][0]]).squaredNorm();
  return u;
}

}  // namespace msd
