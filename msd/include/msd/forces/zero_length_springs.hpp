// Zero-length springs with cotangent weights: the neo-Hookean lattice's
// springs (issue 17, a lattice that matches the continuum).
//
// Why. A spring with a rest length, k (|l| - r)^2 / 2, has a Biot-type energy
// (quadratic in the stretch): on the lattice its uni-axial curve is nearly
// symmetric about rest, and at nu = 0.495 it is +50 % stiffer than the
// neo-Hookean FEM in extension at strain +0.4 (benchmarks/results/
// 2026-12-04-bulk-term.md). A spring of rest length zero has the energy
// k |l|^2 / 2, quadratic in the positions, and a tet's six such springs with
// the weights below have exactly the energy of the linear finite element's
// Dirichlet term:
//     sum over edges (i, j) of k_ij |x_i - x_j|^2 / 2 = mu V tr(F^T F) / 2,
//     k_ij = mu w_ij,   w_ij = -V grad(phi_i) . grad(phi_j) = -g_i . g_j / V,
// phi_i the tet's barycentric coordinates, g_i = dV/dx_i = V grad(phi_i) the
// volume gradient at rest (bulk_volume.hpp), so the weights sum the edges'
// second moment to sum w_ij l_ij l_ij^T = V I. (The cotangent formula:
// w_ij = l_kl cot(theta_kl) / 6 with theta_kl the dihedral angle at the
// opposite edge (k, l); Duffin 1959, J. Math. Mech. 8(5): 793-826, for the
// linear element's stiffness; Pinkall & Polthier 1993, Experiment. Math.
// 2(1): 15-36, for the 2-D form.)
//
// On the five-tet cube of side h the weights are h/6 on the cube's edges (from
// the corner tets, where the face diagonals' dihedral angle is 90 degrees and
// their weight 0) and h/12 on the six face diagonals (the regular central tet):
// a = 2 d, the two classes of spring_law.hpp in fixed proportion.
//
// Summed over a body the springs give mu/2 int tr(C) exactly for every
// deformation of the mesh - the isochoric-plus-spherical part of the
// compressible neo-Hookean energy
//     W = mu/2 (tr C - 3) - mu ln J + lambda/4 (J^2 - 1 - 2 ln J)
// (Ogden 1984, Non-linear Elastic Deformations, 4.4; Simo & Pister 1984 for
// the volumetric form). They pull every edge at rest; the bulk term's
// neo-Hookean law (bulk_volume.hpp) carries the rest of W, per cube, and its
// -mu ln J holds that pull: each cube's springs and its rest pressure -mu
// balance at every corner of the cube (the corner's spring pull
// h (k_a + 2 k_d) = mu h^2 / 3 = mu |dV/dx| at a central-tet corner,
// h k_a = mu h^2 / 6 at the others), so any body of whole cubes is force-free
// at rest. Small strain: shear modulus mu and Lame constant lambda, the
// continuum's, with no class factor to fit.
//
// The spring force and its derivative are edge_springs.hpp's with rest
// length 0: F_a = k l (l = x_b - x_a), dF_a/dl = k I - linear, so Newton's
// matrix of the springs does not change from step to step.
//
// The dampers stay the lattice's edge dampers of the physical rule,
// k_d = damping_time k_s with k_s = s_lattice E V / L^2 (tissue_material.hpp):
// that network of axial elements has the modulus E, so its dampers give the
// viscous modulus damping_time E of the FEM's stiffness-proportional damping.
// Dampers k_d = damping_time k on the zero-length springs would damp too
// little: an edge damper resists the edge's stretching rate only, while a
// zero-length spring's stiffness k I acts across its edge as much as along
// it. Measured on the ring-down (vibration.yaml): damping ratio 0.060 with
// those against the FEM's 0.173; 0.201 with the physical rule's
// (benchmarks/results/2026-12-04-neo-lattice.md).
#pragma once

#include "msd/core/types.hpp"

namespace msd {

/// The six weights w_ij (m) of a tet with rest corners X[0..3], kTetEdges
/// order: w_ij = -g_i . g_j / V (above). Throws msd::Error unless V > 0.
/// A weight may be negative where the opposite dihedral angle is obtuse; the
/// tet's total energy mu V tr(F^T F) / 2 stays non-negative.
void cotangent_weights(const Vec3 X[4], double w[6]);

/// The springs' energy for a tet, sum k_e |l_e|^2 / 2 (J), k kTetEdges order.
double zero_length_spring_energy(const Vec3 x[4], const double k[6]);

}  // namespace msd
