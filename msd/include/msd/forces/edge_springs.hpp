// Edge springs of the MSD element (thesis 5.1.2, first line of eq. 5.4): a
// linear spring on each of the six tet edges,
//   F_a = k_s (|l| - r) l / |l|  on vertex a of edge (a, b), l = x_b - x_a,
// and the opposite force on b. Energy: k_s (|l| - r)^2 / 2 per edge.
#pragma once

#include "msd/forces/edge_frame.hpp"
#include "msd/forces/spring_law.hpp"

#include <array>

namespace msd {

/// The spring force on vertex a as a multiple of l: k_s (|l| - r) / |l|, from
/// |l| and 1 / |l|. Shared by the per-tet loop and the engine's edge pass.
inline double edge_spring_factor(double ks, double length, double inv_length, double rest) {
  return ks * (length - rest) * inv_length;
}

/// Adds the six spring forces of one tet to f[0..3].
/// rest[e] and ks[e] follow the edge order of kTetEdges.
inline void add_edge_springs(const EdgeFrame& g, const double rest[6], const double ks[6], Vec3 f[4]) {
  for (int e = 0; e < 6; ++e) {
    const Vec3 fa = edge_spring_factor(ks[e], g.length[e], g.inv_length[e], rest[e]) * g.l[e];
    f[kTetEdges[e][0]] += fa;
    f[kTetEdges[e][1]] -= fa;
  }
}

/// Elastic energy of the six springs of one tet.
inline double edge_spring_energy(const Vec3 x[4], const double rest[6], const double ks[6]) {
  double u = 0.0;
  for (int e = 0; e < 6; ++e) {
    const double d = (x[kTetEdges[e][1]] - x[kTetEdges[e][0]]).norm() - rest[e];
    u += 0.5 * ks[e] * d * d;
  }
  return u;
}

/// The same with each edge's spring law (msd/forces/spring_law.hpp): edge e
/// pulls with k_s[e] r phi(lambda) along l[e], its law laws[cls[e]].
inline void add_edge_springs(const EdgeFrame& g, const double rest[6], const double ks[6], const EdgeClass cls[6],
                             const std::array<SpringLaw, kEdgeClasses>& laws, Vec3 f[4]) {
  for (int e = 0; e < 6; ++e) {
    const SpringLaw& law = laws[static_cast<size_t>(cls[e])];
    const Vec3 fa = spring_law_factor(ks[e], g.length[e], g.inv_length[e], rest[e], law.tension_exponent,
                                      law.compression_exponent) * g.l[e];
    f[kTetEdges[e][0]] += fa;
    f[kTetEdges[e][1]] -= fa;
  }
}

/// Elastic energy of the six springs with their laws: k_s r^2 Psi(lambda) each.
inline double edge_spring_energy(const Vec3 x[4], const double rest[6], const double ks[6], const EdgeClass cls[6],
                                 const std::array<SpringLaw, kEdgeClasses>& laws) {
  double u = 0.0;
  for (int e = 0; e < 6; ++e) {
    const SpringLaw& law = laws[static_cast<size_t>(cls[e])];
    const double stretch = (x[kTetEdges[e][1]] - x[kTetEdges[e][0]]).norm() / rest[e];
    u += ks[e] * rest[e] * rest[e] * spring_law_energy(law.tension_exponent, law.compression_exponent, stretch);
  }
  return u;
}

}  // namespace msd
