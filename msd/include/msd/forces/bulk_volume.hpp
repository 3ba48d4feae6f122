// The lattice's bulk term: one volume ratio per cube (issue 17, a volume term
// that does not lock in bending).
//
// Why. The thesis' volume term (volume_preservation.hpp) pushes every tet back
// to its own rest volume. Near incompressibility that is one constraint per
// tet, five per cube against about three degrees of freedom per node - one
// node per cube - so the lattice locks: it cannot bend without changing some
// tet's volume, and a cantilever comes out stiff (measured: the fitted volume
// factor moves the held-out bending error from 15.9 % to 21.3 %,
// benchmarks/results/2026-12-04-edge-classes.md). Mean dilatation - one
// volume ratio per element patch instead of per tet (Nagtegaal, Parks & Rice
// 1974, Comput. Methods Appl. Mech. Eng. 4: 153-177; the averaged nodal
// pressure of Bonet & Burton 1998, Commun. Numer. Meth. Eng. 14: 437-449, is
// the same idea per node) - leaves one constraint per cube, which the lattice
// can meet while it bends.
//
// The term. A group g of tets (the five of one cube) with rest volume V0_g
// and current volume V_g = sum over its tets of their signed volumes has the
// volume ratio Jbar_g = V_g / V0_g and the energy
//     U_g = K V0_g (Jbar_g - 1)^2 / 2,
// K the term's bulk modulus (Pa). Its pressure p_g = K (Jbar_g - 1) pushes
// every node of every tet t in the group with
//     f_i = -p_g dV_t/dx_i,   dV_t/dx_i = (area normal of the face opposite i) / 3,
// so U_g = V0_g p_g^2 / (2K). The force's derivative (for Newton) is
//     df/dx = -(K / V0_g) G G^T - p_g sum_t d2V_t/dx2,
// G the group's volume gradient. The forces of a tet's corners sum to zero and
// their torque is zero (dV/dx is invariant under translation and rotation).
//
// Small strain. Under an affine strain eps the term's energy density is
// K tr(eps)^2 / 2: it adds K to C11 and C12 and nothing to C44. Springs with
// the isotropic class factors (spring_law.hpp: a = d/2) have lambda_s = mu_s =
// mu, so K = lambda - mu gives the lattice the continuum's small-strain
// elasticity (the Cauchy-Born estimate; the five-tet split's non-affine
// relaxation softens it, which the calibration measures). lattice_bulk_law
// (tissue_material.hpp) computes that K from E and nu.
//
// The tet's signed volume is msd/mesh/tet_mesh.hpp's tet_signed_volume.
// Arrays: x[4] a tet's corner positions (m); gradients and forces 4 x Vec3;
// Hessians Mat12 in corner-major order (rows 3 i + c).
#pragma once

#include "msd/core/types.hpp"

namespace msd {

using Mat12 = Eigen::Matrix<double, 12, 12>;

/// dV/dx_i for i = 0..3 (m^2): g[1] = (x2 - x0) x (x3 - x0) / 6 and cyclic,
/// g[0] = -(g[1] + g[2] + g[3]).
void tet_volume_gradient(const Vec3 x[4], Vec3 g[4]);

/// d2V/(dx_i dx_j) (m), 12 x 12: with a, b, c = x1, x2, x3 - x0 the blocks
/// are d2V/da db = -[c]x / 6, d2V/da dc = [b]x / 6, d2V/db dc = -[a]x / 6
/// (zero on the diagonal, transposes below it), and x0's row and column
/// minus the sums of the others' (V does not change under translation).
Mat12 tet_volume_hessian(const Vec3 x[4]);

/// p = K (V / V0 - 1), Pa.
inline double bulk_pressure(double volume, double rest_volume, double bulk_modulus) {
  return bulk_modulus * (volume / rest_volume - 1.0);
}

/// U = K V0 (V / V0 - 1)^2 / 2, J.
inline double bulk_energy(double volume, double rest_volume, double bulk_modulus) {
  const double e = volume / rest_volume - 1.0;
  return 0.5 * bulk_modulus * rest_volume * e * e;
}

/// The bulk term's volume law of one group, U_g = V0_g W(Jbar_g):
///  - quadratic, with springs of a rest length: W(J) = K (J - 1)^2 / 2, the
///    law above (modulus = K = lambda - mu);
///  - neo-Hookean, with zero-length springs (zero_length_springs.hpp):
///        W(J) = -mu ln J + lambda/4 (J^2 - 1 - 2 ln J)
///    (modulus = lambda, rest_modulus = mu): -mu ln J holds the springs' rest
///    pull (W'(1) = -mu), the rest is the volumetric energy of the FEM
///    reference's law (reference_fem/src/neo_hookean.h, its kappa/4 form),
///    with lambda so that the lattice's bulk modulus, lambda + 2 mu / 3, is
///    the continuum's. Below J = kBulkFloor W is continued by its
///    second-order Taylor polynomial at the floor, so energy and pressure stay
///    finite (and push outwards, W' < 0) for a crushed or inverted cube.
/// p = W'(J) is the group's pressure, d2W/dJ2 its stiffness (Newton's matrix
/// takes -(W''(J) / V0) G G^T - p sum_t d2V_t/dx2).
struct BulkLaw {
  double modulus = 0.0;       ///< K (quadratic) or lambda (neo-Hookean), Pa
  double rest_modulus = 0.0;  ///< mu (neo-Hookean), Pa
  bool neo_hookean = false;
};

/// Where the neo-Hookean law's Taylor continuation starts.
inline constexpr double kBulkFloor = 0.1;

/// W(J) (J/m^3), p = W'(J) (Pa) and W''(J) (Pa) of the law.
double bulk_law_energy(const BulkLaw& law, double J);
double bulk_law_pressure(const BulkLaw& law, double J);
double bulk_law_stiffness(const BulkLaw& law, double J);

/// f_i += -p dV/dx_i: one tet's share of its group's pressure p.
void add_bulk_forces(const Vec3 x[4], double pressure, Vec3 f[4]);

/// K += -p d2V/dx2: one tet's share of the force derivative (without the
/// group's coupling -(K / V0) G G^T, which spans the group's nodes).
void add_bulk_pressure_jacobian(const Vec3 x[4], double pressure, Mat12& K);

}  // namespace msd
