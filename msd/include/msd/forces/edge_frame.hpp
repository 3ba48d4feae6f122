// Current edge vectors and lengths of one tetrahedron, computed once per element
// and shared by the edge springs and edge dampers (thesis 5.1.2).
#pragma once

#include "msd/core/types.hpp"
#include "msd/mesh/tet_mesh.hpp"

namespace msd {

/// For edge e = (a, b) of kTetEdges: l[e] = x[b] - x[a], its length and inverse.
struct EdgeFrame {
  Vec3 l[6];
  double length[6];
  double inv_length[6];
};

inline EdgeFrame edge_frame(const Vec3 x[4]) {
  EdgeFrame g;
  for (int e = 0; e < 6; ++e) {
    g.l[e] = x[kTetEdges[e][1]] - x[kTetEdges[e][0]];
    g.length[e] = g.l[e].norm();
    g.inv_length[e] = 1.0 / g.length[e];
  }
  return g;
}

}  // namespace msd
