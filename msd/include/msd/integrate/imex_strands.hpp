// IMEX Euler: symplectic Euler for everything except the tendon strands'
// stiffness, which is taken linearly implicitly (an implicit-explicit split,
// Ascher, Ruuth & Wetton 1995, SIAM J. Numer. Anal. 32; the linearly implicit
// step for stiff springs of Baraff & Witkin 1998, SIGGRAPH, restricted to the
// stiff part).
//
// Why. A real tendon (about 1.2 GPa, tendon.hpp) on the thesis' 24.5 mm mesh
// is a strand of k_t = E A / L0 of 1e5-4e5 N/m pulling a tissue node of a few
// grams: omega = sqrt(k_t / m) is near 10^4 rad/s, so symplectic Euler needs
// dt < 2 / omega, about 2e-4 s, below the step the tissue itself allows, and
// stops being stable when several strands share a node. Backward Euler and
// BDF2 (implicit.hpp) are stable at any step but solve the whole tissue.
// Here only the strands' few free nodes are solved for.
//
// The step. With f(x, v) every force at the step's start (elements, parts,
// loads), K_s = d f_strands / dx there (jacobians.hpp, strand_jacobian: the
// strands' stiffness, the anchors and prescribed nodes held), M the lumped
// masses:
//
//   (M - dt^2 K_s) v+ = M v + dt f(x, v) + dt K_sp dx_p,    x+ = x + dt v+,
//
// where dx_p is how far the strands' held points (anchors, prescribed nodes)
// move over the step: the linearised force f(x+) = f(x) + K (x+ - x) over
// every point of the strand, the held ones' motion known. (Without it a
// strand whose anchor and node move together would pull back on the node
// with k_t dt times its speed: a numerical damper on every taut strand that
// a turning bone drags along.)
//
// K_s is non-zero only on the free nodes of taut strands: each connected set
// of them (strands sharing a node are one set) is a small dense system,
// solved by Cholesky (Eigen's LLT). A strand's energy is a convex function of
// its length, which is convex in the points, so -K_s is positive
// semi-definite and M - dt^2 K_s is positive definite. Every other node takes
// symplectic Euler's v+ = v + dt a unchanged, and a model without a taut
// strand steps exactly as symplectic Euler, bit for bit.
//
// For one linear strand mode (frequency omega, h = dt) one step maps
// (x, v) to x+ = x + h v+, v+ = (v - h omega^2 x) / (1 + h^2 omega^2): the
// eigenvalues have |lambda|^2 = 1 / (1 + h^2 omega^2) < 1, stable at every
// step and damping the stiff mode as backward Euler does. First order, like
// symplectic Euler. The joints are stepped explicitly from the strands'
// forces at the step's start (step_joints), as with symplectic Euler: a
// stiff strand's pull on a bone of large inertia is not what limits the step.
// Nodes in a kinematic group are never solved for (they are prescribed).
#pragma once

#include "msd/model/model.hpp"

#include <Eigen/Cholesky>

namespace msd {

/// The sets of strand nodes solved together, built once per model (sized on
/// the first step; no allocation after that).
struct StrandSolveWorkspace {
  const Model* model = nullptr;  ///< the model it was made for
  size_t strands = 0;            ///< and its strand count
  /// Set c's free nodes: nodes[node_offset[c] .. node_offset[c+1]); its strands:
  /// strand_of[strand_offset[c] .. strand_offset[c+1]).
  std::vector<int> node_offset, nodes, strand_offset, strand_of;
  /// Per strand, per point (its nodes, then its anchor): the place of the
  /// point in its set's node list, or -1 (prescribed node, or the anchor).
  std::vector<int> point_offset, local;
  std::vector<Eigen::MatrixXd> matrix;        ///< per set: M - dt^2 K_s (3 m x 3 m)
  std::vector<Eigen::LLT<Eigen::MatrixXd>> llt;  ///< per set
  std::vector<Eigen::VectorXd> rhs;           ///< per set
  std::vector<char> stiff;                    ///< per set: a strand of it is taut
  std::vector<Points> points;                 ///< per strand: its points (buffer)
  /// Per strand point (point_offset): a prescribed node's start velocity, or
  /// the anchor's start position (buffer).
  std::vector<Vec3> held;
  std::vector<Vec3> held_first;  ///< per strand: its anchor group's first node's start velocity (buffer)
  std::vector<char> taut;        ///< per strand, at the step's start (buffer)
  std::vector<Eigen::MatrixXd> jacobian;      ///< per strand (buffer)
};

/// Makes (or re-uses, when made for this model) the workspace's sets.
void prepare_strand_sets(const Model& model, StrandSolveWorkspace& ws);

/// Assembles each set's M - dt^2 K_s at the state's positions with the joints
/// and controls of the step's start (where add_part_forces saw the anchors),
/// and records where the held points are and how fast they move.
void assemble_strand_systems(const Model& model, const State& state, const Controls& controls, double dt,
                             StrandSolveWorkspace& ws);

/// Replaces the velocities of each taut set's nodes in state.v - which holds
/// symplectic Euler's v + dt a on entry - by the solution of the set's system,
/// (M - dt^2 K_s) v+ = M (v + dt a) + dt K_sp dx_p, the anchors' motion dx_p
/// from the joints stepped into `state` and the step's end `controls`.
/// Throws SimulationFailure (at the state's time and step, naming a node of
/// the set) if a system is not positive definite.
void solve_strand_velocities(const Model& model, const Controls& controls, double dt, StrandSolveWorkspace& ws,
                             State& state);

}  // namespace msd
