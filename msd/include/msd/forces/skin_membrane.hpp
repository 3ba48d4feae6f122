// The skin as a membrane (issue 18, item 4): a thin layer of skin on the
// limb's outer surface, each surface triangle a constant-strain element of an
// incompressible neo-Hookean membrane of thickness h (plane stress, the
// thickness free to change so that the volume is kept). Skin is too thin
// (about 1-2 mm) for a layer of the lattice's tets (24.5 mm at the thesis'
// spacing), so it is meshed as the surface's own triangles: the membrane
// model of thin incompressible sheets (Green & Adkins 1960, "Large Elastic
// Deformations", ch. 4; as used for skin by Flynn, Taberner & Nielsen 2011,
// Biomech. Model. Mechanobiol. 10:27).
//
// Per triangle (rest corners X_0, X_1, X_2, area A0; current x_0, x_1, x_2):
//
//   D_m = the rest edges X_1 - X_0, X_2 - X_0 in the triangle's own 2-D frame
//         (2 x 2),   D_s = [x_1 - x_0, x_2 - x_0] (3 x 2),
//   F   = D_s D_m^-1 (3 x 2),   C = F^T F (2 x 2),   J2 = det C  (= the area
//         ratio squared),   adj C = J2 C^-1 = [[C_22, -C_12], [-C_12, C_11]],
//   W   = A0 h mu/2 (tr C + g(J2) - 3),   g(J2) = 1/J2
//
// (incompressible: the thickness stretch is 1/sqrt(J2), so the 3-D neo-Hookean
// I_1 - 3 becomes tr C + 1/J2 - 3). Linearised at rest this is a plane-stress
// sheet of Young's modulus E = 3 mu and Poisson's ratio 1/2, so mu = E / 3.
//
// 1/J2 grows without bound as a triangle's area goes to zero, and contact can
// flatten a triangle onto a line (a node pressed onto an obstacle's surface).
// Below the area ratio a_f (SkinMembrane::area_floor, 0.5: J2 below s = a_f^2)
// g continues as its second-order Taylor polynomial at s,
//   g(J2) = 1/s - (J2 - s)/s^2 + (J2 - s)^2/s^3,
// so the energy, forces and stiffness stay finite for every position (a skin
// compressed to half its area would have wrinkled long before: real skin
// carries little in-plane compression).
//
// Its first Piola-Kirchhoff stress (per unit rest area, times h) and forces,
// with dJ2/dF = 2 F adj C:
//
//   P   = dW/dF / A0 = h mu (F + g'(J2) F adj C),
//   f_1, f_2 = the columns of -A0 P D_m^-T,   f_0 = -(f_1 + f_2),
//
// and its stiffness from (adj is linear on symmetric 2 x 2 matrices)
//   dP  = h mu [dF + g' (dF adj C + F adj dC) + g'' tr(adj C dC) F adj C],
//   dC  = dF^T F + F^T dF,
// a 9 x 9 block per triangle, the Hessian of W (symmetric; indefinite under
// in-plane compression, where a real membrane would wrinkle).
//
// Equibiaxial stretch l (C = l^2 I) gives W = A0 h mu/2 (2 l^2 + l^-4 - 3) and
// the Cauchy stress mu (l^2 - l^-4) (Green & Adkins): the closed forms the
// tests check (above the floor).
#pragma once

#include "msd/core/types.hpp"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace msd {

using Mat9 = Eigen::Matrix<double, 9, 9>;

struct MembraneTriangle {
  std::array<int, 3> nodes{};
  Eigen::Matrix2d rest_inverse{Eigen::Matrix2d::Identity()};  ///< D_m^-1 (2 x 2)
  double rest_area = 0.0;                                       ///< A0, m^2
};

/// The skin: its triangles and the sheet's constants. Empty: no skin.
struct SkinMembrane {
  std::vector<MembraneTriangle> triangles;
  double shear_modulus = 0.0;  ///< mu = E / 3, Pa
  double thickness = 0.0;      ///< h, m
  double area_floor = 0.5;     ///< a_f: below this area ratio g(J2) continues as a polynomial (above)
  bool empty() const { return triangles.empty(); }
};

/// The membrane on `faces` of the rest positions (3 x N), with Young's modulus
/// E (Pa) and thickness h (m). Throws msd::Error unless E and h are positive
/// and finite, and naming a face whose rest area is zero or whose node is out
/// of range.
SkinMembrane make_skin_membrane(const Points& rest, const std::vector<Tri>& faces, double youngs_modulus,
                                double thickness);

/// The membrane's elastic energy at positions x (3 x N), J.
double membrane_energy(const SkinMembrane& skin, const Points& x);

/// Adds the membrane's forces at x to f (3 x N). Each triangle's corner forces
/// are computed on `threads` threads into `corner` (3 x 3T: triangle k's
/// corners at columns 3k ... 3k+2; resized only when its size differs), then
/// added to f in triangle order, so f is bit-identical for every thread count.
void add_membrane_forces(const SkinMembrane& skin, const Points& x, Points& f, int threads, Points& corner);

/// The same on one thread with a buffer of its own (allocates; for tests and tools).
void add_membrane_forces(const SkinMembrane& skin, const Points& x, Points& f);

/// Triangle k's stiffness df/dx at x (9 x 9; block (i, j) = df_i / dx_j over
/// its nodes in order).
Mat9 membrane_triangle_stiffness(const SkinMembrane& skin, size_t k, const Points& x);

}  // namespace msd
