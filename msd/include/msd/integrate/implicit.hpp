// Backward Euler for stiff scenes (issue 16): the step solves, for the
// velocities v+ at t + dt,
//   G(v+) = M (v+ - v) - dt [ f(x + dt v+, v+) + s f_ext + s M g ] = 0,
//   x+ = x + dt v+,
// by Newton's method with the exact Jacobian
//   dG/dv+ = M - dt D - dt^2 K,   K = df/dx,  D = df/dv
// of every element term (msd/forces/jacobians.hpp), assembled into one sparse
// matrix with a fixed pattern (a 3 x 3 block per node and per edge: every pair
// of a tet's vertices is an edge) and solved by Eigen's sparse LU (the volume
// term is not a gradient, so the matrix is not symmetric), with a backtracking
// line search on |G|. Prescribed components (kinematic groups) take their
// values at t + dt and drop out of the system. A node lying on an
// obstacle's surface at the step's start is held by it: on a stick obstacle
// it moves with the obstacle over the step and drops out too; on a
// frictionless one only its motion along the normal does, its tangential
// motion stays free. A held node is let go (the solve repeated) when holding
// it would take a pull. New contacts are resolved after the solve, as in the
// explicit steppers (step.hpp). First order and
// unconditionally stable for the linear terms: it damps the highest
// frequencies instead of blowing up, so its step is chosen for accuracy,
// not for the stiffest spring.
#pragma once

#include "msd/model/model.hpp"

#include <Eigen/SparseCore>

namespace msd {

/// The matrix layout: 3N x 3N column-compressed with one 3 x 3 block per node
/// and per ordered pair of nodes that share an edge. Built once per model.
struct SystemLayout {
  Eigen::SparseMatrix<double> pattern;  ///< every stored entry, values zero
  /// For each block, the index into the value array of row 0 of its column c
  /// (c = 0, 1, 2: entry (r, c) of the block at [3 id + c] + r). Blocks: node
  /// n's diagonal is n; edge e's (a, b) block is N + 2 e, its (b, a) block N + 2 e + 1.
  std::vector<int> column_start;
  /// Per tet, the block of its local vertex pair (i, j) at [16 t + 4 i + j].
  std::vector<int> tet_block;
  /// Per strand s, the blocks of its node pairs (i, j), m x m row-major, at
  /// strand_block[strand_block_offset[s] + i m + j].
  std::vector<int> strand_block_offset, strand_block;
  /// Per muscle unit (muscles in order, units in order): its (a, b) and (b, a) blocks.
  std::vector<int> unit_block;
  /// Per skin triangle k (Model::skin), the blocks of its node pairs (i, j) at
  /// skin_block[9 k + 3 i + j].
  std::vector<int> skin_block;
  /// Per volume group g of the continuum element (Model::volume_groups), the
  /// blocks of its node pairs (i, j), m x m row-major (m its node count), at
  /// group_block[group_block_offset[g] + i m + j].
  std::vector<int> group_block_offset, group_block;
  /// Per degree of freedom (3 n + axis): prescribed by a kinematic group.
  std::vector<char> fixed;
  /// Per block: its (row, column) nodes.
  std::vector<std::pair<int, int>> block_nodes;
};

SystemLayout make_system_layout(const Model& model);

/// Assembles  A = c_m M + c_d D + c_k K  at (x, v) into A (which must have the
/// layout's pattern; values overwritten). K and D are the exact Jacobians of the
/// internal forces (springs, dampers, repulsion, volume, as the model has them;
/// gravity and dead loads do not depend on x or v). Prescribed rows and columns
/// are left as assembled. The moving parts are taken relaxed (no activation,
/// the model's natural lengths) with every joint at angle 0: for a model with
/// parts use the overload below.
void assemble_system(const Model& model, const SystemLayout& layout, const Points& x, const Points& v, double c_m,
                     double c_d, double c_k, Eigen::SparseMatrix<double>& A);

/// The same with the moving parts' stiffness (strands and muscles, jacobians.hpp)
/// under `controls`, anchors placed with the joints' states `joints`.
void assemble_system(const Model& model, const SystemLayout& layout, const Points& x, const Points& v,
                     const std::vector<HingeState>& joints, const Controls& controls, double c_m, double c_d,
                     double c_k, Eigen::SparseMatrix<double>& A);

/// One backward-Euler step (called by step() for Integrator::BackwardEuler).
/// Throws SimulationFailure naming the time, step, node with the largest
/// residual and the residual when Newton does not converge in
/// model.newton.max_iterations.
void step_backward_euler(const Model& model, State& state, const Controls& controls, double dt, Scratch& scratch);

/// One BDF2 step (Integrator::Bdf2): the same Newton solve with the base
///   x+ = a x - b x- + h v+,  M (v+ - (a v - b v-)) = h F(x+, v+),
/// a = (1+w)^2/(1+2w), b = w^2/(1+2w), h = (1+w)/(1+2w) dt, w = dt / dt-
/// (for equal steps a = 4/3, b = 1/3, h = 2/3 dt), from the state one step
/// back kept in State::x_prev, v_prev, dt_prev, which it updates. A step
/// without that history (the first, or after another integrator) or more
/// than twice the last one is a backward-Euler step. Second order; A-stable
/// on linear problems (and L-stable), so like backward Euler its step is
/// chosen for accuracy, but it damps a resolved vibration far less.
void step_bdf2(const Model& model, State& state, const Controls& controls, double dt, Scratch& scratch);

/// One quasi-static step (Integrator::QuasiStatic): the equilibrium at the
/// step's end,
///   f(x+, 0) + load(t + dt) = 0,
/// prescribed nodes at their positions then - the problem the FEM reference
/// solves for static, uni-axial and shear loading (docs/fem-reference.md,
/// quasi-static solution). No inertia and no dampers (the forces are taken at
/// zero velocity); the same Newton solve and step cuts as backward Euler with
/// the matrix -dt^2 K, and the load halfway in a cut step. The state's velocity is the step's mean
/// rate (x+ - x) / dt, the next step's predictor. Its matrix is singular when
/// some part of the model is held by nothing (a free body, a sliding sample
/// with nothing against its sideways drift); the step then fails with Newton's
/// "singular matrix". A model with joints is refused (msd::Error): a hinge's
/// motion is dynamic; so is one with rigid obstacles or self-contact (their
/// contact is held through the step's velocities, which this step does not
/// have). The dampers do not act in the solve, but forces evaluated on the
/// state afterwards (a rig's sampled stress) see its velocity: leave
/// `dampers` out of the terms for a static comparison.
void step_quasi_static(const Model& model, State& state, const Controls& controls, double dt, Scratch& scratch);

}  // namespace msd
