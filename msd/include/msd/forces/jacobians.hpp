// Jacobians of the element force terms (thesis eq. 5.1-5.5) for the implicit
// integrator (msd/integrate/implicit.hpp). Each is the exact derivative of
// the force its kernel computes (edge_springs.hpp, edge_dampers.hpp,
// face_repulsion.hpp, volume_preservation.hpp, tet_frame.hpp), tested against
// central finite differences of those kernels.
//
// Edge terms act on l = x_b - x_a and w = v_b - v_a with F_b = -F_a, so one
// 3 x 3 block B = dF_a/dl gives all four: dF_a/dx_b = dF_b/dx_a = B and
// dF_a/dx_a = dF_b/dx_b = -B (the same for dF/dv with dF_a/dw).
//  - spring  F_a = k_s (1 - r/|l|) l:
//      dF_a/dl = k_s [ (1 - r/|l|) I + (r/|l|) u u^T ],   u = l/|l|;
//  - damper  F_a = k_d (w . l) l / |l|^2:
//      dF_a/dw = k_d u u^T,
//      dF_a/dl = k_d [ l w^T + (w . l) I - 2 (w . l) u u^T ] / |l|^2.
// The non-linear terms push vertex j by F_j = p_j m_j + sum_{i != j} s_i (m_i . m_j) m_i
// (tet_frame.hpp, add_balanced_normal_forces) with p_i = f_i / |m_i|,
// s_i = f_i / |m_i|^3, the magnitudes f_i of repulsion (a function of the
// height h_i = 6V / |m_i|) and volume (k_v 6 (V0 - V) / |m_i|). Their 12 x 12
// Jacobian is built column by column as the directional derivative along each
// vertex coordinate (forward mode, by the product and chain rules through
// m_i = d(6V)/dx_i, |m_i|, h_i and f_i); the volume term is not a gradient, so
// the matrix is not symmetric.
//
// The moving parts (msd/forces/parts.hpp):
//  - a contractile unit, F_a = phi(|l|) u with phi = F f_L(|l| / r):
//      dF_a/dl = phi/|l| (I - u u^T) + (F/r) f_L'(|l|/r) u u^T,
//      f_L' = 2 s / (1 - lambda_0) on the ascending limb (s as in
//      muscle_units.hpp), 0 elsewhere;
//  - a Hill unit (muscle_units.hpp), F_a = T(|l|, r) u with r = u . w the
//    lengthening rate (w = v_b - v_a):
//      dF_a/dl = T/|l| (I - u u^T) + dT/d|l| u u^T,   dF_a/dw = dT/dr u u^T;
//    the rate's own dependence on the direction, dT/dr u w^T (I - u u^T)/|l|,
//    is left out: it is not symmetric, vanishes when the unit does not turn
//    relative to its ends' motion, and Newton converges without it (more
//    slowly where units turn fast);
//  - a strand through points p_0 ... p_{m-1} with L = sum |d_s|, d_s = p_{s+1} - p_s,
//    gradient g = dL/dp (g_i = u_{i-1} - u_i) and T = T(L) > 0 (tendon.hpp;
//    dT/dL = k_t beyond the toe): the force is -T g, so
//      K = -dT/dL g g^T - T sum_s P_s / |d_s|   (P_s = I - u_s u_s^T in the
//      blocks (s, s), (s+1, s+1), and with a minus sign in (s, s+1), (s+1, s)),
//    dense over the strand's points and symmetric; 0 for a slack strand.
#pragma once

#include "msd/core/types.hpp"
#include "msd/model/model.hpp"

#include <Eigen/Core>

namespace msd {

using Mat12 = Eigen::Matrix<double, 12, 12>;

/// dF_a/dl of the edge spring (force on a, l = x_b - x_a).
Mat3 edge_spring_jacobian(const Vec3& l, double rest, double ks);

/// dF_a/dl and dF_a/dw of the edge damper (w = v_b - v_a).
void edge_damper_jacobians(const Vec3& l, const Vec3& w, double kd, Mat3& dfa_dl, Mat3& dfa_dw);

/// Derivative df/dx of face_repulsion_magnitude (with its tangent continuation).
double face_repulsion_slope(double x, double x0, double kr, double floor);

/// dF/dx (12 x 12; row 3 j + c: component c of the force on local vertex j;
/// column 3 k + d: component d of x_k) of the element's non-linear terms
/// (repulsion and volume, whichever the model has) at vertices x[0..3], into K
/// (overwritten). Returns false and leaves K zero when the thesis 5.8
/// threshold leaves the element out, exactly as add_nonlinear_element_forces.
bool nonlinear_element_jacobian(const Model& model, const Element& el, const Vec3 x[4], Mat12& K);

/// dF_a/dl of a contractile unit pulling its ends together with `force` times
/// f_L(|l| / rest_length) (add_muscle_forces; l = x_b - x_a).
Mat3 muscle_unit_jacobian(const Vec3& l, double rest_length, double force, const ForceLength& fl);

/// dF_a/dl and dF_a/dw of a Hill unit (add_hill_muscle_forces; l = x_b - x_a,
/// w = v_b - v_a), the direction term of the rate left out (above).
void hill_unit_jacobians(const Vec3& l, const Vec3& w, double rest_length, double activation, double unit_force,
                         const HillMuscle& hill, Mat3& dfa_dl, Mat3& dfa_dw);

/// dF/dp (3m x 3m; block (i, j) = dF_i/dp_j) of a tension-only strand through
/// the points p (3 x m) with the toe strain `toe_strain` (tendon.hpp) into K
/// (resized only when its size differs). Returns false and sets K to zero
/// when the strand is slack.
bool strand_jacobian(const Points& p, double natural_length, double k_t, Eigen::MatrixXd& K,
                     double toe_strain = 0.0);

}  // namespace msd
