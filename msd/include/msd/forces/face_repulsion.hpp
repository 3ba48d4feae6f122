// Face repulsion with equalising forces (thesis 5.2.3-5.2.4, eq. 5.1-5.3;
// Appendix B eq. 4-5 in 2-D): each vertex is pushed away from the plane of its
// opposite face by
//   f(x) = k_r (x0^2 / x - x)                                    (eq. 5.1/5.2)
// where x is the vertex's signed height over that plane and x0 its rest value;
// f(x0) = 0 and f grows without bound as x -> 0+. The other three vertices take
// the equalising forces of eq. 5.3 so the element's net force and torque vanish.
//
// Two choices the thesis leaves open, made explicit here:
//  - x is signed (negative once the vertex has passed through the plane), so an
//    inverted element is pushed back rather than further through;
//  - below x_c = floor * x0 (floor in (0, 1)) f continues along its tangent at
//    x_c, so the force stays finite and keeps growing as the vertex goes through
//    and beyond the plane. With floor -> 0 this is exactly eq. 5.1.
// Both are conservative: the forces are minus the gradient of
// face_repulsion_energy.
#pragma once

#include "msd/forces/tet_frame.hpp"

#include <cmath>

namespace msd {

/// Magnitude f(x) of eq. 5.1 with the tangent continuation below floor * x0.
inline double face_repulsion_magnitude(double x, double x0, double kr, double floor) {
  const double xc = floor * x0;
  if (x >= xc) return kr * (x0 * x0 / x - x);
  const double fc = kr * (x0 * x0 / xc - xc);
  const double slope = -kr * (x0 * x0 / (xc * xc) + 1.0);
  return fc + slope * (x - xc);
}

/// Potential U(x) with U(x0) = 0 and dU/dx = -f(x).
inline double face_repulsion_potential(double x, double x0, double kr, double floor) {
  const double xc = floor * x0;
  auto u = [&](double s) { return -kr * (x0 * x0 * std::log(s / x0) - 0.5 * (s * s - x0 * x0)); };
  if (x >= xc) return u(x);
  const double fc = kr * (x0 * x0 / xc - xc);
  const double slope = -kr * (x0 * x0 / (xc * xc) + 1.0);
  const double d = x - xc;
  return u(xc) - fc * d - 0.5 * slope * d * d;
}

/// Adds repulsion and equalising forces for all four vertices of one tet.
/// x0[i]: rest height of vertex i; kr[i]: its repulsion constant (N/m).
inline void add_face_repulsion(const TetFrame& g, const double x0[4], const double kr[4],
                               double floor, Vec3 f[4]) {
  for (int i = 0; i < 4; ++i)
    add_balanced_normal_force(g, i, face_repulsion_magnitude(g.height[i], x0[i], kr[i], floor), f);
}

/// Energy of the four repulsion terms of one tet.
inline double face_repulsion_energy(const TetFrame& g, const double x0[4], const double kr[4],
                                    double floor) {
  double u = 0.0;
  for (int i = 0; i < 4; ++i) u += face_repulsion_potential(g.height[i], x0[i], kr[i], floor);
  return u;
}

}  // namespace msd
