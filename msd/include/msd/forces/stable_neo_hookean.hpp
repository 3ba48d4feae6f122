// The stable neo-Hookean constant-strain tetrahedron: a continuum element on
// the MSD model's own mesh, integrated by the same step (issue 17's model
// ladder). Smith, de Goes & Kim 2018, "Stable Neo-Hookean Flesh Simulation",
// ACM Trans. Graph. 37(2):12, eq. 14 and section 3.4:
//
//   Psi(F) = mu/2 (I_C - 3) + lambda/2 (J - alpha)^2 - mu/2 log(I_C + 1),
//   alpha  = 1 + 3 mu / (4 lambda),   I_C = tr(F^T F),   J = det F,
//
// with F = D_s D_m^-1 constant over the tet (D_s = [x1-x0, x2-x0, x3-x0],
// D_m the same at rest) and element energy V0 Psi(F). Psi is finite for every
// F - an inverted element (J <= 0) has finite energy and is pushed back by the
// lambda term, and an element collapsed to a point (F = 0) too - so no element
// state makes the force non-finite. alpha makes the rest state stress-free.
// Linearised at F = I it is linear elasticity with Lame constants
// (mu_L, lambda_L) when
//   mu = 4/3 mu_L,   lambda = lambda_L + 5/6 mu_L
// (Smith et al. 3.4; the second variation at F = I is
// 3 mu/4 (H:H + tr H^2) + (lambda - 5 mu/8) (tr H)^2, docs/msd-model.md).
//
// First Piola-Kirchhoff stress and its derivative (vec column-major, 9 x 9):
//   P = mu (1 - 1/(I_C+1)) F + lambda (J - alpha) dJ/dF,
//       dJ/dF = [f1 x f2, f2 x f0, f0 x f1]   (f_c: column c of F);
//   dP/dF = mu (1 - 1/(I_C+1)) I_9 + 2 mu/(I_C+1)^2 vec F vec F^T
//           + lambda g g^T + lambda (J - alpha) H_J,   g = vec dJ/dF,
//   H_J: blocks (c, d) of d^2 J / df_c df_d = [[0, -f2^, f1^], [f2^, 0, -f0^], [-f1^, f0^, 0]]
//   (v^ the cross-product matrix of v).
// Nodal forces: f_i = -V0 P G_i with G the shape-function gradients
// (G_{k+1} = row k of D_m^-1, G_0 = -(G_1 + G_2 + G_3)); stiffness
// df_i/dx_j = -V0 B_i^T dP/dF B_j. The energy's Hessian is symmetric and,
// away from rest, indefinite (the lambda (J - alpha) H_J term).
#pragma once

#include "msd/core/types.hpp"

#include <Eigen/Core>

namespace msd {

using Mat9 = Eigen::Matrix<double, 9, 9>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

/// The energy's constants (Pa; alpha dimensionless).
struct SnhConstants {
  double mu = 0.0, lambda = 0.0, alpha = 1.0;
};

/// From Young's modulus E (Pa) and Poisson's ratio nu in (-1, 0.5): the Lame
/// constants mu_L = E / 2(1 + nu), lambda_L = E nu / (1 + nu)(1 - 2 nu), mapped
/// as above (times `scale`, a calibration factor on both).
SnhConstants snh_constants(double youngs_modulus, double poisson_ratio, double scale = 1.0);

/// Psi(F), Pa (energy per rest volume).
double snh_energy_density(const Mat3& F, const SnhConstants& c);

/// P(F), Pa.
Mat3 snh_stress(const Mat3& F, const SnhConstants& c);

/// dP/dF, 9 x 9: entry (a + 3 c, b + 3 d) = dP_ac / dF_bd.
Mat9 snh_stress_derivative(const Mat3& F, const SnhConstants& c);

/// D_m^-1 of a tet at rest (throws msd::Error for a degenerate one).
Mat3 rest_shape_inverse(const Vec3 x[4]);

/// F = D_s D_m^-1 at vertices x[0..3].
Mat3 deformation_gradient(const Vec3 x[4], const Mat3& dm_inv);

/// V0 Psi(F) of one element, J.
double snh_element_energy(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c);

/// Adds the element's forces -d(V0 Psi)/dx_i to f[0..3].
void add_snh_forces(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c, Vec3 f[4]);

/// dF/dx of those forces (12 x 12; row 3 j + a: component a of the force on
/// vertex j; column 3 k + b: component b of x_k) into K (overwritten).
void snh_force_jacobian(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c, Mat12& K);

// Mean dilatation (the continuum element's `per_cube` volume): the volume
// term lambda/2 (J - alpha)^2 is taken once per group of tets (a cube of the
// lattice) with the group's volume ratio Jbar = sum V_t / sum V0_t in place of
// each tet's J (Nagtegaal, Parks & Rice 1974; Hughes 1980, the B-bar method;
// the FEM reference's Q1-P0 three-field element is the same idea on hexes).
// One volume constraint per cube instead of five stops the lattice locking
// at nu near 0.5. The energy is
//   sum_t V0_t Psi_shear(F_t) + sum_g V0_g lambda/2 (Jbar_g - alpha)^2,
//   Psi_shear(F) = mu/2 (I_C - 3) - mu/2 log(I_C + 1),
// so each tet of group g takes the shear forces of its own F and the
// pressure p_g = lambda (Jbar_g - alpha) times -dV_t/dx; its stiffness adds
// -(lambda / V0_g) g g^T over the group's nodes, g = sum_t dV_t/dx.
// With groups of one tet this is the element above, exactly.

/// Psi_shear(F), Pa.
double snh_shear_energy_density(const Mat3& F, const SnhConstants& c);

/// lambda (J - alpha): the volume term's pressure at volume ratio J, Pa.
inline double snh_pressure(double J, const SnhConstants& c) { return c.lambda * (J - c.alpha); }

/// Adds the forces of Psi_shear(F) and of a pressure p acting on the tet's
/// volume: -V0 (dPsi_shear/dF + p dJ/dF) G_i. With p = snh_pressure(J) these
/// are add_snh_forces' forces.
void add_snh_forces_at_pressure(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c,
                                double pressure, Vec3 f[4]);

/// dV/dx_i of the tet (3 x 4; column i), V0 dJ/dF G_i.
Eigen::Matrix<double, 3, 4> volume_gradient(const Vec3 x[4], const Mat3& dm_inv, double rest_volume);

/// dF/dx of add_snh_forces_at_pressure's forces at a fixed pressure (the
/// group's g g^T term is the caller's) into K (overwritten).
void snh_force_jacobian_at_pressure(const Vec3 x[4], const Mat3& dm_inv, double rest_volume, const SnhConstants& c,
                                    double pressure, Mat12& K);

}  // namespace msd
