#include "msd/integrate/imex_strands.hpp"

#include "msd/forces/jacobians.hpp"
#include "msd/forces/parts.hpp"
#include "msd/integrate/step.hpp"

#include <numeric>

namespace msd {

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i) {
    parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    i = parent[static_cast<size_t>(i)];
  }
  return i;
}

}  // namespace

void prepare_strand_sets(const Model& model, StrandSolveWorkspace& ws) {
  if (ws.model == &model && ws.strands == model.strands.size()) return;
  ws = StrandSolveWorkspace{};
  ws.model = &model;
  ws.strands = model.strands.size();
  const int n = model.num_nodes();
  std::vector<char> prescribed(static_cast<size_t>(n), 0);
  for (const KinematicGroup& g : model.groups)
    for (int i : g.nodes) prescribed[static_cast<size_t>(i)] = 1;
  // Union-find over the strands' free nodes: a strand joins all of its own.
  std::vector<int> parent(static_cast<size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> used(static_cast<size_t>(n), 0);
  for (const Strand& s : model.strands) {
    int first = -1;
    for (int i : s.nodes) {
      if (prescribed[static_cast<size_t>(i)]) continue;
      used[static_cast<size_t>(i)] = 1;
      if (first < 0)
        first = i;
      else
        parent[static_cast<size_t>(find_root(parent, i))] = find_root(parent, first);
    }
  }
  // Sets numbered by their first node in increasing order; nodes in order.
  std::vector<int> set_of_root(static_cast<size_t>(n), -1), set_of_node(static_cast<size_t>(n), -1);
  std::vector<std::vector<int>> members;
  for (int i = 0; i < n; ++i) {
    if (!used[static_cast<size_t>(i)]) continue;
    const int r = find_root(parent, i);
    int& c = set_of_root[static_cast<size_t>(r)];
    if (c < 0) {
      c = static_cast<int>(members.size());
      members.emplace_back();
    }
    set_of_node[static_cast<size_t>(i)] = c;
    members[static_cast<size_t>(c)].push_back(i);
  }
  const size_t sets = members.size();
  ws.node_offset.assign(1, 0);
  std::vector<int> place(static_cast<size_t>(n), -1);
  for (const auto& m : members) {
    for (size_t k = 0; k < m.size(); ++k) {
      ws.nodes.push_back(m[k]);
      place[static_cast<size_t>(m[k])] = static_cast<int>(k);
    }
    ws.node_offset.push_back(static_cast<int>(ws.nodes.size()));
  }
  // Each strand's set (a strand with no free node belongs to none) and the
  // places of its points.
  std::vector<std::vector<int>> strands_of(sets);
  ws.point_offset.assign(1, 0);
  for (size_t si = 0; si < model.strands.size(); ++si) {
    const Strand& s = model.strands[si];
    int set = -1;
    for (int i : s.nodes) {
      const bool free = !prescribed[static_cast<size_t>(i)];
      ws.local.push_back(free ? place[static_cast<size_t>(i)] : -1);
      if (free) set = set_of_node[static_cast<size_t>(i)];
    }
    if (s.anchor_group >= 0) ws.local.push_back(-1);
    ws.point_offset.push_back(static_cast<int>(ws.local.size()));
    if (set >= 0) strands_of[static_cast<size_t>(set)].push_back(static_cast<int>(si));
  }
  ws.strand_offset.assign(1, 0);
  for (const auto& list : strands_of) {
    ws.strand_of.insert(ws.strand_of.end(), list.begin(), list.end());
    ws.strand_offset.push_back(static_cast<int>(ws.strand_of.size()));
  }
  ws.matrix.resize(sets);
  ws.llt.resize(sets);
  ws.rhs.resize(sets);
  ws.stiff.assign(sets, 0);
  for (size_t c = 0; c < sets; ++c) {
    const Eigen::Index dim = 3 * static_cast<Eigen::Index>(members[c].size());
    ws.matrix[c].setZero(dim, dim);
    // Sizes its storage. (Computed in place: an LLT made from a size alone
    // leaves its info unset, and copying it reads that - UBSan catches it.)
    ws.llt[c].compute(ws.matrix[c] + Eigen::MatrixXd::Identity(dim, dim));
    ws.rhs[c].setZero(dim);
  }
  ws.held.assign(ws.local.size(), Vec3::Zero());
  ws.held_first.assign(model.strands.size(), Vec3::Zero());
  ws.taut.assign(model.strands.size(), 0);
  ws.points.resize(model.strands.size());
  ws.jacobian.resize(model.strands.size());
  for (size_t si = 0; si < model.strands.size(); ++si) {
    const Eigen::Index m = ws.point_offset[si + 1] - ws.point_offset[si];
    ws.points[si].setZero(3, m);
    ws.jacobian[si].setZero(3 * m, 3 * m);
  }
}

void assemble_strand_systems(const Model& model, const State& state, const Controls& controls, double dt,
                             StrandSolveWorkspace& ws) {
  prepare_strand_sets(model, ws);
  const Points& x = state.x;
  const std::vector<HingeState>& joints = state.joints;
  const double h2 = dt * dt;
  for (size_t c = 0; c + 1 < ws.node_offset.size(); ++c) {
    Eigen::MatrixXd& A = ws.matrix[c];
    A.setZero();
    for (int k = ws.node_offset[c]; k < ws.node_offset[c + 1]; ++k) {
      const Eigen::Index d = 3 * (k - ws.node_offset[c]);
      A.block<3, 3>(d, d).diagonal().setConstant(model.mass[ws.nodes[static_cast<size_t>(k)]]);
    }
    ws.stiff[c] = 0;
    for (int j = ws.strand_offset[c]; j < ws.strand_offset[c + 1]; ++j) {
      const size_t si = static_cast<size_t>(ws.strand_of[static_cast<size_t>(j)]);
      const Strand& s = model.strands[si];
      Points& p = ws.points[si];
      const Eigen::Index m = static_cast<Eigen::Index>(s.nodes.size());
      for (Eigen::Index k = 0; k < m; ++k) p.col(k) = x.col(s.nodes[static_cast<size_t>(k)]);
      if (s.anchor_group >= 0) p.col(m) = group_point(model, s.anchor_group, s.anchor_rest, x, joints, controls);
      const int* local = ws.local.data() + ws.point_offset[si];
      Vec3* held = ws.held.data() + ws.point_offset[si];
      for (Eigen::Index k = 0; k < m; ++k)
        if (local[k] < 0) held[k] = state.v.col(s.nodes[static_cast<size_t>(k)]);
      if (s.anchor_group >= 0) {
        held[m] = p.col(m);
        const KinematicGroup& g = model.groups[static_cast<size_t>(s.anchor_group)];
        if (!g.nodes.empty()) ws.held_first[si] = state.v.col(g.nodes.front());
      }
      Eigen::MatrixXd& K = ws.jacobian[si];
      ws.taut[si] = strand_jacobian(p, strand_natural_length(model, si, controls), s.k_t, K, s.toe_strain);
      if (!ws.taut[si]) continue;
      ws.stiff[c] = 1;
      for (Eigen::Index a = 0; a < p.cols(); ++a) {
        if (local[a] < 0) continue;
        for (Eigen::Index b = 0; b < p.cols(); ++b) {
          if (local[b] < 0) continue;
          A.block<3, 3>(3 * local[a], 3 * local[b]) -= h2 * K.block<3, 3>(3 * a, 3 * b);
        }
      }
    }
  }
}

namespace {

// How far held point k of strand si moves over the step: a prescribed node
// at its start velocity; the anchor from its start position to where the
// stepped joints and the end controls put it (a group translated with its
// first node: that node's start velocity, as the node itself).
Vec3 held_motion(const Model& model, size_t si, Eigen::Index k, const Controls& controls, double dt,
                 const StrandSolveWorkspace& ws, const State& state) {
  const Strand& s = model.strands[si];
  const Vec3& held = ws.held[static_cast<size_t>(ws.point_offset[si] + k)];
  if (k < static_cast<Eigen::Index>(s.nodes.size())) return dt * held;
  const Vec3 end = group_point(model, s.anchor_group, s.anchor_rest, state.x, state.joints, controls);
  const KinematicGroup& g = model.groups[static_cast<size_t>(s.anchor_group)];
  const bool with_first_node = g.joint < 0 && !group_motion(controls, s.anchor_group) && !g.nodes.empty();
  // (state.x still holds the step's start there; the first node's motion is its prescribed velocity.)
  return end - held + (with_first_node ? Vec3(dt * ws.held_first[si]) : Vec3::Zero());
}

}  // namespace

void solve_strand_velocities(const Model& model, const Controls& controls, double dt, StrandSolveWorkspace& ws,
                             State& state) {
  Points& v = state.v;
  for (size_t c = 0; c + 1 < ws.node_offset.size(); ++c) {
    if (!ws.stiff[c]) continue;
    const int first = ws.node_offset[c], count = ws.node_offset[c + 1] - first;
    Eigen::VectorXd& r = ws.rhs[c];
    for (int k = 0; k < count; ++k) {
      const int i = ws.nodes[static_cast<size_t>(first + k)];
      r.segment<3>(3 * k) = model.mass[i] * v.col(i);
    }
    // + dt K_sp dx_p: the held points' motion, through the strands' coupling blocks.
    for (int j = ws.strand_offset[c]; j < ws.strand_offset[c + 1]; ++j) {
      const size_t si = static_cast<size_t>(ws.strand_of[static_cast<size_t>(j)]);
      const int* local = ws.local.data() + ws.point_offset[si];
      const Eigen::Index points = ws.point_offset[si + 1] - ws.point_offset[si];
      if (!ws.taut[si]) continue;
      for (Eigen::Index b = 0; b < points; ++b) {
        if (local[b] >= 0) continue;
        const Vec3 dx = held_motion(model, si, b, controls, dt, ws, state);
        for (Eigen::Index a = 0; a < points; ++a)
          if (local[a] >= 0) r.segment<3>(3 * local[a]) += dt * (ws.jacobian[si].block<3, 3>(3 * a, 3 * b) * dx);
      }
    }
    ws.llt[c].compute(ws.matrix[c]);
    if (ws.llt[c].info() != Eigen::Success)
      throw SimulationFailure("the strands' implicit system is not positive definite", state.t, state.step, -1,
                              ws.nodes[static_cast<size_t>(first)]);
    ws.llt[c].solveInPlace(r);
    for (int k = 0; k < count; ++k) v.col(ws.nodes[static_cast<size_t>(first + k)]) = r.segment<3>(3 * k);
  }
}

}  // namespace msd
