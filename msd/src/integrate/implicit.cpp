#include "msd/integrate/implicit.hpp"

#include "msd/forces/bulk_volume.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/forces/jacobians.hpp"
#include "msd/forces/parts.hpp"
#include "msd/forces/stable_neo_hookean.hpp"
#include "msd/integrate/step.hpp"
#include "msd/mesh/tet_mesh.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <algorithm>
#include <map>
#include <cmath>
#include <sstream>
#include <limits>

namespace msd {

namespace {

// The block of node pair (a, b): a's diagonal, the edge joining them, or one
// of the extra pairs (-1: none).
int find_block(const Model& model, const std::map<std::pair<int, int>, int>& extra, int a, int b) {
  if (a == b) return a;
  const ForcePlan& p = model.plan;
  for (int k = p.node_edge_offset[static_cast<size_t>(a)]; k < p.node_edge_offset[static_cast<size_t>(a) + 1]; ++k) {
    const int r = p.node_edge[static_cast<size_t>(k)];
    const int e = r / 2;
    const bool a_is_b_end = r & 1;
    const int other = a_is_b_end ? p.edge_a[static_cast<size_t>(e)] : p.edge_b[static_cast<size_t>(e)];
    if (other == b) return model.num_nodes() + 2 * e + (a_is_b_end ? 1 : 0);
  }
  const auto it = extra.find({a, b});
  return it == extra.end() ? -1 : it->second;
}

}  // namespace

SystemLayout make_system_layout(const Model& model) {
  const int n = model.num_nodes();
  const ForcePlan& p = model.plan;
  std::vector<std::pair<int, int>> block_nodes(static_cast<size_t>(n + 2 * p.num_edges()));
  for (int i = 0; i < n; ++i) block_nodes[static_cast<size_t>(i)] = {i, i};
  for (int e = 0; e < p.num_edges(); ++e) {
    block_nodes[static_cast<size_t>(n + 2 * e)] = {p.edge_a[static_cast<size_t>(e)], p.edge_b[static_cast<size_t>(e)]};
    block_nodes[static_cast<size_t>(n + 2 * e + 1)] = {p.edge_b[static_cast<size_t>(e)], p.edge_a[static_cast<size_t>(e)]};
  }
  // Pairs the moving parts couple that no edge joins: every pair of a
  // strand's nodes (its Jacobian is dense), each muscle unit's ends.
  std::map<std::pair<int, int>, int> extra;
  const auto need = [&](int a, int b) {
    if (find_block(model, extra, a, b) >= 0) return;
    extra[{a, b}] = static_cast<int>(block_nodes.size());
    block_nodes.emplace_back(a, b);
  };
  for (const Strand& st : model.strands)
    for (int a : st.nodes)
      for (int b : st.nodes) need(a, b);
  for (const Muscle& mu : model.muscles)
    for (const ContractileUnit& u : mu.units) {
      need(u.a, u.b);
      need(u.b, u.a);
    }
  // The skin's triangles are faces of the mesh's tets, so their node pairs are
  // edges; a membrane on other triangles gets its pairs here.
  for (const MembraneTriangle& t : model.skin.triangles)
    for (int a : t.nodes)
      for (int b : t.nodes) need(a, b);
  // The continuum element's volume groups couple every pair of a group's nodes.
  const VolumeGroups& groups = model.volume_groups;
  const auto group_nodes = [&](int g) {
    return std::make_pair(groups.nodes.begin() + groups.node_offset[static_cast<size_t>(g)],
                          groups.nodes.begin() + groups.node_offset[static_cast<size_t>(g) + 1]);
  };
  for (int g = 0; g < groups.size(); ++g) {
    const auto [first, last] = group_nodes(g);
    for (auto a = first; a != last; ++a)
      for (auto b = first; b != last; ++b) need(*a, *b);
  }
  const int blocks = static_cast<int>(block_nodes.size());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(9 * static_cast<size_t>(blocks));
  for (const auto& [r, c] : block_nodes)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) entries.emplace_back(3 * r + i, 3 * c + j, 0.0);
  SystemLayout L;
  L.pattern.resize(3 * n, 3 * n);
  L.pattern.setFromTriplets(entries.begin(), entries.end());
  L.pattern.makeCompressed();
  L.column_start.resize(3 * static_cast<size_t>(blocks));
  const int* outer = L.pattern.outerIndexPtr();
  const int* inner = L.pattern.innerIndexPtr();
  for (int b = 0; b < blocks; ++b) {
    const auto [r, c] = block_nodes[static_cast<size_t>(b)];
    for (int j = 0; j < 3; ++j) {
      const int col = 3 * c + j;
      const int* at = std::lower_bound(inner + outer[col], inner + outer[col + 1], 3 * r);
      L.column_start[3 * static_cast<size_t>(b) + static_cast<size_t>(j)] = static_cast<int>(at - inner);
    }
  }
  // Each tet's vertex pairs: the node's diagonal or the edge joining them.
  L.tet_block.resize(16 * model.elements.size());
  for (size_t t = 0; t < model.elements.size(); ++t) {
    const Tet& nodes = model.elements[t].nodes;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const int id = find_block(model, extra, nodes[static_cast<size_t>(i)], nodes[static_cast<size_t>(j)]);
        if (id < 0) throw Error("system layout: tet " + std::to_string(t) + " has a vertex pair without an edge");
        L.tet_block[16 * t + 4 * static_cast<size_t>(i) + static_cast<size_t>(j)] = id;
      }
  }
  L.strand_block_offset.assign(1, 0);
  for (const Strand& st : model.strands) {
    for (int a : st.nodes)
      for (int b : st.nodes) L.strand_block.push_back(find_block(model, extra, a, b));
    L.strand_block_offset.push_back(static_cast<int>(L.strand_block.size()));
  }
  for (const Muscle& mu : model.muscles)
    for (const ContractileUnit& u : mu.units) {
      L.unit_block.push_back(find_block(model, extra, u.a, u.b));
      L.unit_block.push_back(find_block(model, extra, u.b, u.a));
    }
  for (const MembraneTriangle& t : model.skin.triangles)
    for (int a : t.nodes)
      for (int b : t.nodes) L.skin_block.push_back(find_block(model, extra, a, b));
  L.group_block_offset.assign(1, 0);
  for (int g = 0; g < groups.size(); ++g) {
    const auto [first, last] = group_nodes(g);
    for (auto a = first; a != last; ++a)
      for (auto b = first; b != last; ++b) L.group_block.push_back(find_block(model, extra, *a, *b));
    L.group_block_offset.push_back(static_cast<int>(L.group_block.size()));
  }
  L.block_nodes = std::move(block_nodes);
  L.fixed.assign(3 * static_cast<size_t>(n), 0);
  for (const KinematicGroup& g : model.groups)
    for (int node : g.nodes)
      for (int a = 0; a < 3; ++a)
        if (g.axes[a]) L.fixed[3 * static_cast<size_t>(node) + static_cast<size_t>(a)] = 1;
  return L;
}

namespace {

inline void add_block(double* values, const SystemLayout& L, int block, const Mat3& B, double c) {
  for (int j = 0; j < 3; ++j) {
    double* col = values + L.column_start[3 * static_cast<size_t>(block) + static_cast<size_t>(j)];
    for (int i = 0; i < 3; ++i) col[i] += c * B(i, j);
  }
}

// An edge term's four blocks from B = dF_a/dl: (a,a) and (b,b) get -B, (a,b)
// and (b,a) get +B.
inline void add_edge_blocks(double* values, const SystemLayout& L, int n, int e, int a, int b, const Mat3& B,
                            double c) {
  add_block(values, L, a, B, -c);
  add_block(values, L, b, B, -c);
  add_block(values, L, n + 2 * e, B, c);
  add_block(values, L, n + 2 * e + 1, B, c);
}

// The strands', muscles' and skin's stiffness (jacobians.hpp, skin_membrane.hpp), times c_k, and a Hill
// unit's damping (its force-velocity relation), times c_d. An anchored
// strand's anchor is not a degree of freedom: its rows and columns are
// dropped.
void assemble_parts(const Model& model, const SystemLayout& L, const Points& x, const Points& v,
                    const std::vector<HingeState>& joints, const Controls& controls, double c_d, double c_k,
                    double* values) {
  // Each strand's points and Jacobian in buffers of its own size, kept from
  // one assembly to the next (strands differ in length: one shared buffer
  // would be resized, and allocate, at every strand).
  thread_local std::vector<Points> points_of;
  thread_local std::vector<Eigen::MatrixXd> jacobian_of;
  if (points_of.size() < model.strands.size()) {
    points_of.resize(model.strands.size());
    jacobian_of.resize(model.strands.size());
  }
  for (size_t si = 0; c_k != 0.0 && si < model.strands.size(); ++si) {
    const Strand& s = model.strands[si];
    const Eigen::Index m = static_cast<Eigen::Index>(s.nodes.size());
    const Eigen::Index points = m + (s.anchor_group >= 0 ? 1 : 0);
    Points& p = points_of[si];
    Eigen::MatrixXd& K = jacobian_of[si];
    if (p.cols() != points) p.resize(3, points);
    for (Eigen::Index k = 0; k < m; ++k) p.col(k) = x.col(s.nodes[static_cast<size_t>(k)]);
    if (s.anchor_group >= 0) p.col(m) = group_point(model, s.anchor_group, s.anchor_rest, x, joints, controls);
    if (!strand_jacobian(p, strand_natural_length(model, si, controls), s.k_t, K, s.toe_strain)) continue;
    const int* ids = L.strand_block.data() + L.strand_block_offset[si];
    for (Eigen::Index i = 0; i < m; ++i)
      for (Eigen::Index j = 0; j < m; ++j)
        add_block(values, L, ids[i * m + j], K.block<3, 3>(3 * i, 3 * j), c_k);
  }
  // A unit's blocks from B = dF_a/dl (or dF_a/dw): (a,a), (b,b) get -B; (a,b), (b,a) +B.
  auto unit_blocks = [&](const ContractileUnit& u, size_t unit, const Mat3& B, double c) {
    add_block(values, L, u.a, B, -c);
    add_block(values, L, u.b, B, -c);
    add_block(values, L, L.unit_block[2 * unit], B, c);
    add_block(values, L, L.unit_block[2 * unit + 1], B, c);
  };
  size_t unit = 0;
  for (size_t mi = 0; mi < model.muscles.size(); ++mi) {
    const Muscle& mu = model.muscles[mi];
    const double a = mi < controls.activation.size() ? controls.activation[mi] : 0.0;
    if (mu.hill.enabled) {
      Mat3 dl, dw;
      for (const ContractileUnit& u : mu.units) {
        hill_unit_jacobians(Vec3(x.col(u.b) - x.col(u.a)), Vec3(v.col(u.b) - v.col(u.a)), u.rest_length, a,
                            mu.unit_force, mu.hill, dl, dw);
        if (c_k != 0.0) unit_blocks(u, unit, dl, c_k);
        if (c_d != 0.0) unit_blocks(u, unit, dw, c_d);
        ++unit;
      }
      continue;
    }
    if (!(a > 0.0) || c_k == 0.0) {
      unit += mu.units.size();
      continue;
    }
    for (const ContractileUnit& u : mu.units) {
      unit_blocks(u, unit, muscle_unit_jacobian(Vec3(x.col(u.b) - x.col(u.a)), u.rest_length, a * mu.unit_force, mu.force_length), c_k);
      ++unit;
    }
  }
  // The skin: each triangle's 9 x 9 stiffness (skin_membrane.hpp).
  for (size_t k = 0; c_k != 0.0 && k < model.skin.triangles.size(); ++k) {
    const Mat9 Ks = membrane_triangle_stiffness(model.skin, k, x);
    const int* ids = L.skin_block.data() + 9 * k;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) add_block(values, L, ids[3 * i + j], Ks.block<3, 3>(3 * i, 3 * j), c_k);
  }
}

// The volume groups' coupling, -(lambda / V0_g) g g^T with g = sum over the
// group's tets of dV_t/dx (stable_neo_hookean.hpp), times c_k.
// With the bulk term (bulk_volume.hpp) the modulus is its law's W''(Jbar_g).
void assemble_volume_groups(const Model& model, const SystemLayout& L, const Points& x, double c_k, double* values) {
  const VolumeGroups& G = model.volume_groups;
  const bool bulk = model.terms & kBulk;
  thread_local Eigen::Matrix3Xd grad_buffer;  // the largest group's size: no resize per group
  for (int g = 0; g < G.size(); ++g) {
    const size_t gi = static_cast<size_t>(g);
    const int m = G.node_offset[gi + 1] - G.node_offset[gi];
    if (grad_buffer.cols() < m) grad_buffer.resize(3, m);
    auto grad = grad_buffer.leftCols(m);
    grad.setZero();
    double modulus = 0.0, volume = 0.0;
    for (int q = G.tet_offset[gi]; q < G.tet_offset[gi + 1]; ++q) {
      const size_t t = static_cast<size_t>(G.tets[static_cast<size_t>(q)]);
      const Element& el = model.elements[t];
      Vec3 xe[4];
      for (int i = 0; i < 4; ++i) xe[i] = x.col(el.nodes[static_cast<size_t>(i)]);
      if (bulk) {
        Vec3 dv[4];
        tet_volume_gradient(xe, dv);
        for (int i = 0; i < 4; ++i) grad.col(G.corner_slot[4 * t + static_cast<size_t>(i)]) += dv[i];
        volume += tet_signed_volume(xe[0], xe[1], xe[2], xe[3]);
      } else {
        const Eigen::Matrix<double, 3, 4> dv = volume_gradient(xe, model.continuum.dm_inv[t], el.rest_volume);
        for (int i = 0; i < 4; ++i) grad.col(G.corner_slot[4 * t + static_cast<size_t>(i)]) += dv.col(i);
        modulus = model.continuum.constants[t].lambda;
      }
    }
    if (bulk) modulus = bulk_law_stiffness(G.bulk_law[gi], volume / G.rest_volume[gi]);
    const double c = -c_k * modulus / G.rest_volume[gi];
    const int* ids = L.group_block.data() + L.group_block_offset[gi];
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) add_block(values, L, ids[i * m + j], grad.col(i) * grad.col(j).transpose(), c);
  }
}

}  // namespace

void assemble_system(const Model& model, const SystemLayout& L, const Points& x, const Points& v, double c_m,
                     double c_d, double c_k, Eigen::SparseMatrix<double>& A) {
  static const Controls none;
  static const std::vector<HingeState> rest_joints;
  assemble_system(model, L, x, v, model.joints.empty() ? rest_joints : std::vector<HingeState>(model.joints.size()),
                  none, c_m, c_d, c_k, A);
}

void assemble_system(const Model& model, const SystemLayout& L, const Points& x, const Points& v,
                     const std::vector<HingeState>& joints, const Controls& controls, double c_m, double c_d,
                     double c_k, Eigen::SparseMatrix<double>& A) {
  double* values = A.valuePtr();
  std::fill(values, values + A.nonZeros(), 0.0);
  const int n = model.num_nodes();
  if (c_m != 0.0)
    for (int i = 0; i < n; ++i) add_block(values, L, i, Mat3::Identity(), c_m * model.mass[i]);
  const ForcePlan& p = model.plan;
  const bool springs = model.terms & kSprings, dampers = model.terms & kDampers;
  if (springs || dampers)
    for (int e = 0; e < p.num_edges(); ++e) {
      const int a = p.edge_a[static_cast<size_t>(e)], b = p.edge_b[static_cast<size_t>(e)];
      const Vec3 l = x.col(b) - x.col(a);
      if (springs && c_k != 0.0) {
        const size_t k = static_cast<size_t>(e);
        add_edge_blocks(values, L, n, e, a, b,
                        p.edge_law_m.empty()
                            ? edge_spring_jacobian(l, p.edge_rest[k], p.edge_k_s[k])
                            : spring_law_jacobian(l, p.edge_rest[k], p.edge_k_s[k], p.edge_law_m[k], p.edge_law_n[k]),
                        c_k);
      }
      if (dampers) {
        Mat3 dl, dw;
        edge_damper_jacobians(l, Vec3(v.col(b) - v.col(a)), p.edge_k_d[static_cast<size_t>(e)], dl, dw);
        if (c_k != 0.0) add_edge_blocks(values, L, n, e, a, b, dl, c_k);
        if (c_d != 0.0) add_edge_blocks(values, L, n, e, a, b, dw, c_d);
      }
    }
  const bool nonlinear = model.terms & (kRepulsion | kVolume), continuum = model.terms & kNeoHookean;
  const bool bulk = model.terms & kBulk;
  const VolumeGroups& groups = model.volume_groups;
  thread_local std::vector<double> pressure;
  if (c_k != 0.0 && (continuum || bulk)) {
    pressure.resize(static_cast<size_t>(groups.size()));
    for (int g = 0; g < groups.size(); ++g) pressure[static_cast<size_t>(g)] = volume_group_pressure(model, g, x);
  }
  if (c_k != 0.0 && (nonlinear || continuum || bulk)) {
    Mat12 K, Kc;
    for (size_t t = 0; t < model.elements.size(); ++t) {
      const Element& el = model.elements[t];
      Vec3 xe[4];
      for (int i = 0; i < 4; ++i) xe[i] = x.col(el.nodes[static_cast<size_t>(i)]);
      const bool active = nonlinear && nonlinear_element_jacobian(model, el, xe, K);
      if (continuum) {
        if (groups.empty())
          snh_force_jacobian(xe, model.continuum.dm_inv[t], el.rest_volume, model.continuum.constants[t], Kc);
        else
          snh_force_jacobian_at_pressure(xe, model.continuum.dm_inv[t], el.rest_volume, model.continuum.constants[t],
                                         pressure[static_cast<size_t>(groups.of_tet[t])], Kc);
        if (active)
          K += Kc;
        else
          K = Kc;
      } else if (bulk) {
        if (!active) K.setZero();
        add_bulk_pressure_jacobian(xe, pressure[static_cast<size_t>(groups.of_tet[t])], K);
      } else if (!active) {
        continue;
      }
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
          add_block(values, L, L.tet_block[16 * t + 4 * static_cast<size_t>(i) + static_cast<size_t>(j)],
                    K.block<3, 3>(3 * i, 3 * j), c_k);
    }
  }
  if (c_k != 0.0 && (continuum || bulk)) assemble_volume_groups(model, L, x, c_k, values);
  if (c_k != 0.0 || c_d != 0.0) assemble_parts(model, L, x, v, joints, controls, c_d, c_k, values);
}

// A node an obstacle holds for one solve (hold_contacts).
struct HeldContact {
  int node = -1;
  Vec3 x, v;       // its position and velocity at the step's end (all of them, or along `normal` if it slides)
  Vec3 normal;     // the obstacle's outward normal at the step's start
  int obstacle = -1;
  bool slides = false;  // frictionless: only its normal motion is held
  Vec3 row;        // its row of G before it is zeroed (residual): h times the force holding it
};

// Eigen's simplicial LDL^T, factorised from a matrix already in its fill-reducing
// order. SimplicialLDLT::factorize(S) permutes S into a temporary sparse matrix
// on every call (Eigen 3.4, SimplicialCholesky.h: `CholMatrixType tmp(size,
// size)` and the twisted copy's count vector), and solve() permutes in place
// through a heap mask. factorize_preordered - Eigen's own numeric factorisation,
// the one factorize() calls - takes the permuted upper triangle C = P S P^T
// directly; the caller keeps C's pattern and fills its values. Then a step's
// factorisation and solves allocate nothing (below Eigen's stack limit of
// 128 KiB of scratch per factorisation, 16,384 unknowns).
class PreorderedLdlt : public Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> {
 public:
  // Factorises C = P S P^T, P = permutationP() of the analysed pattern (upper triangle read).
  void factorize_permuted(const Eigen::SparseMatrix<double>& c) { this->template factorize_preordered<true>(c); }
  // x = S^-1 b through the factors, with `work` (size n) holding P b; x must not alias b.
  void solve_into(const Eigen::VectorXd& b, Eigen::VectorXd& work, Eigen::VectorXd& x) const {
    if (this->m_P.size() > 0)
      work = this->m_P * b;
    else
      work = b;
    this->matrixL().solveInPlace(work);
    work = this->m_diag.asDiagonal().inverse() * work;  // as Eigen's solve: the same bits
    this->matrixU().solveInPlace(work);
    if (this->m_P.size() > 0)
      x = this->m_Pinv * work;
    else
      x = work;
  }
};

// The workspace of the implicit steps: layout, matrix, factorisation, vectors.
struct ImplicitWorkspace {
  const Model* model = nullptr;  // the model the layout was made for
  int nodes = -1, edges = -1;
  size_t strands = 0, muscles = 0, skin = 0;  // the parts the layout's extra blocks were made for
  int volume_groups = 0;
  SystemLayout layout;
  Eigen::SparseMatrix<double> A;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;  // sparse_lu
  // symmetric_ldlt: the symmetric part (A + A^T) / 2 is factorised as
  // C = P S P^T (its upper triangle), whose entries are gathered straight
  // from A's values through c_from / c_from_t (analyse_symmetric_part), so that no
  // sparse expression is evaluated - and nothing allocated - per factorisation.
  PreorderedLdlt ldlt;
  Eigen::SparseMatrix<double> C;
  std::vector<int> c_from, c_from_t;  // per entry of C: A's entries (i, j) and (j, i) it averages
  Eigen::VectorXd permuted;           // the solve's right-hand side in C's order
  bool ldlt_analysed = false;
  Points x1, v1, v_trial, r, load;
  // The step's base: x+ = x_base + h v+ and M (v+ - v_base) = h F (backward
  // Euler: the state and h = dt; BDF2: its combination of two states).
  Points x_base, v_base;
  Eigen::VectorXd rhs, delta;
  State at;  // the iterate handed to evaluate_forces
  Points r_keep;  // the residual at the iterate while a chord step is tried
  bool factored = false;  // lu or ldlt holds a factorisation (of an earlier iterate's Jacobian)
  bool refresh = false;   // the last chord step contracted weakly: factorise afresh
  double factor_h = 0.0;  // the h it was made for (M - h D - h^2 K)
  bool factor_statics = false;  // and whether for a quasi-static solve (-h^2 K)
  std::vector<HingeState> joints_end;  // the joints at the step's end
  // A cut step's halfway controls and joint states, one per depth of cut (advance).
  std::vector<Controls> cut_controls;
  std::vector<std::vector<HingeState>> cut_joints;
  double force_floor = 0.0;  // N: residual forces below it are round-off (round_off_force)
  // Anderson acceleration of the chord steps (anderson_step): the differences
  // of the last iterates (dv), their chord updates (dd) and residuals (dg), a
  // ring of anderson_depth columns, `kept` of them valid (-1: none, and no
  // last iterate either); the last iterate, update and residual.
  Eigen::MatrixXd dv, dd, dg;
  Eigen::VectorXd last_v, last_d, last_g;
  int kept = -1, ring = 0;
  // Held contacts (hold_contacts): nodes on a stick obstacle's surface at the
  // step's start move with it over the step and drop out of the solve.
  std::vector<HeldContact> held;
  std::vector<int> held_before;    // the held nodes of the last factorisation
  std::vector<int> sliding_index;  // per node: its index in `held` if held sliding, else -1
  std::vector<char> fixed;  // per degree of freedom: layout.fixed or held (stick)
  // Quasi-static (step_quasi_static): G = -h (f(x1, 0) + load), no inertia,
  // the forces at zero velocity (no dampers); `still` holds those zeros.
  bool statics = false;
  Points still;
  // Quasi-static: the load scale the state is in equilibrium with (0 before
  // the first step), so a cut step's first half takes the load halfway.
  double load_from = 0.0;
};

namespace {

ImplicitWorkspace& workspace(const Model& model, Scratch& scratch) {
  if (!scratch.implicit) scratch.implicit = std::make_shared<ImplicitWorkspace>();
  ImplicitWorkspace& w = *scratch.implicit;
  if (w.model != &model || w.nodes != model.num_nodes() || w.edges != model.plan.num_edges() ||
      w.strands != model.strands.size() || w.muscles != model.muscles.size() ||
      w.skin != model.skin.triangles.size() ||
      w.volume_groups != model.volume_groups.size()) {
    w.layout = make_system_layout(model);
    w.A = w.layout.pattern;
    w.lu.analyzePattern(w.A);
    w.ldlt_analysed = false;
    w.factored = false;
    w.nodes = model.num_nodes();
    w.edges = model.plan.num_edges();
    w.strands = model.strands.size();
    w.muscles = model.muscles.size();
    w.skin = model.skin.triangles.size();
    w.volume_groups = model.volume_groups.size();
    w.load_from = 0.0;
    w.model = &model;
  }
  return w;
}

// x1 = x_base + h v1 on free components; prescribed ones at their values at
// t + dt (groups a joint drives at the joints' states `joints`).
void positions_from_velocities(const Model& model, const Controls& c, const std::vector<HingeState>& joints,
                               double h, ImplicitWorkspace& w) {
  w.x1 = w.x_base + h * w.v1;
  apply_group_constraints(model, c, joints, w.x1, w.v1);
  for (const HeldContact& hc : w.held) {
    if (hc.slides) {
      w.x1.col(hc.node) += (hc.x - Vec3(w.x1.col(hc.node))).dot(hc.normal) * hc.normal;
      w.v1.col(hc.node) += (hc.v - Vec3(w.v1.col(hc.node))).dot(hc.normal) * hc.normal;
    } else {
      w.x1.col(hc.node) = hc.x;
      w.v1.col(hc.node) = hc.v;
    }
  }
}

// The contacts the solve holds (thesis 5.6.2's responses, inside the
// implicit system): a node of an obstacle's node list that lies on its
// surface at the step's start - put there by the last step's projection -
// is held by it for this solve. On a stick obstacle it moves with it to
// x + dt u, v+ = u (u the obstacle's velocity): a prescribed node. On a
// frictionless one only its motion along the outward normal n is
// prescribed, (x+ - x - dt u) . n = 0 and (v+ - u) . n = 0; its tangential
// motion stays an unknown of the solve. Without the hold the solve lets such
// a node sink into the obstacle and the projection afterwards pushes it back
// along n, a displacement no force in the solve saw; at the implicit
// integrators' long steps that crushed the tets under the indenter (issue
// 16). The obstacle's placement at the step's start is its offset at the
// end minus dt u. A node is on the surface when its depth is within 1e-9 of
// the obstacle's size (the cylinder's radius, for a plane 1 m) of zero.
void hold_contacts(const Model& model, const State& s, const Controls& c, double dt, ImplicitWorkspace& w) {
  w.held.clear();
  w.fixed = w.layout.fixed;
  w.sliding_index.assign(static_cast<size_t>(model.num_nodes()), -1);
  for (size_t k = 0; k < model.obstacles.size(); ++k) {
    const RigidObstacle& ob = model.obstacles[k];
    const bool slides = ob.response == ContactResponse::Frictionless;
    const Vec3 u = k < c.obstacle_velocity.size() ? c.obstacle_velocity[k] : Vec3::Zero();
    const Vec3 end = k < c.obstacle_offset.size() ? c.obstacle_offset[k] : Vec3::Zero();
    const Vec3 start = end - dt * u;
    const double tol = 1e-9 * (ob.shape == ObstacleShape::Cylinder ? ob.cylinder.radius : 1.0);
    for (int n : ob.nodes) {
      // Held by an earlier obstacle (an obstacle's nodes are never a group's: fixed means held).
      if (w.fixed[3 * static_cast<size_t>(n)] || w.sliding_index[static_cast<size_t>(n)] >= 0) continue;
      const ContactGap g = obstacle_gap(ob, start, s.x.col(n));
      if (g.depth < -tol) continue;
      if (slides)
        w.sliding_index[static_cast<size_t>(n)] = static_cast<int>(w.held.size());
      else
        for (size_t a = 0; a < 3; ++a) w.fixed[3 * static_cast<size_t>(n) + a] = 1;
      w.held.push_back({n, Vec3(s.x.col(n)) + dt * u, u, g.normal, static_cast<int>(k), slides, Vec3::Zero()});
    }
  }
}

// The sliding held nodes' rows and columns of the Newton matrix in the basis
// that keeps their normal update zero: with P = I - n n^T, a sliding node's
// block row becomes P A_ij, its block column A_ji P, and its diagonal block
// P A_ii P + n n^T (an identity's row along n). Its update is then
// tangential, as its residual row P G_i is.
void hold_sliding_in_matrix(const SystemLayout& L, const ImplicitWorkspace& w, Eigen::SparseMatrix<double>& A) {
  if (std::none_of(w.held.begin(), w.held.end(), [](const HeldContact& hc) { return hc.slides; })) return;
  double* values = A.valuePtr();
  for (size_t b = 0; b < L.block_nodes.size(); ++b) {
    const auto [r, c] = L.block_nodes[b];
    const int hr = w.sliding_index[static_cast<size_t>(r)], hc = w.sliding_index[static_cast<size_t>(c)];
    if (hr < 0 && hc < 0) continue;
    Mat3 B;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) B(i, j) = values[L.column_start[3 * b + static_cast<size_t>(j)] + i];
    if (hr >= 0) {
      const Vec3& nr = w.held[static_cast<size_t>(hr)].normal;
      B -= nr * (nr.transpose() * B);
    }
    if (hc >= 0) {
      const Vec3& nc = w.held[static_cast<size_t>(hc)].normal;
      B -= (B * nc) * nc.transpose();
    }
    if (r == c) B += w.held[static_cast<size_t>(hr)].normal * w.held[static_cast<size_t>(hr)].normal.transpose();
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) values[L.column_start[3 * b + static_cast<size_t>(j)] + i] = B(i, j);
  }
}

// A sliding node keeps the normal component of its start on the surface;
// its tangential slide of s moves it off a curved surface by about
// s^2 / 2R. Each is put back on the surface at the step's end (the closest
// point), so that it is found on it - and held - at the next step's start.
void settle_sliding(const Model& model, const Controls& c, ImplicitWorkspace& w) {
  for (const HeldContact& hc : w.held) {
    if (!hc.slides) continue;
    const size_t o = static_cast<size_t>(hc.obstacle);
    const Vec3 end = o < c.obstacle_offset.size() ? c.obstacle_offset[o] : Vec3::Zero();
    const ContactGap g = obstacle_gap(model.obstacles[o], end, w.x1.col(hc.node));
    w.x1.col(hc.node) += g.depth * g.normal;
  }
}

// Lets go of the held nodes the obstacle would have to pull: the force that
// holds node i is G_i / h (G's row before it is zeroed, HeldContact::row); a
// contact can only push, along the obstacle's outward normal. Returns
// whether any was let go.
bool release_pulling_contacts(ImplicitWorkspace& w) {
  size_t kept = 0;
  for (const HeldContact& hc : w.held) {
    const size_t n = static_cast<size_t>(hc.node);
    if (hc.row.dot(hc.normal) < 0.0) {
      for (size_t a = 0; a < 3; ++a) w.fixed[3 * n + a] = w.layout.fixed[3 * n + a];
      w.sliding_index[n] = -1;
      continue;
    }
    if (hc.slides) w.sliding_index[n] = static_cast<int>(kept);
    w.held[kept++] = hc;
  }
  const bool any = kept < w.held.size();
  w.held.resize(kept);
  return any;
}

// G = M (v1 - v_base) - h (f(x1, v1) + load) into w.r (prescribed
// components zero); returns max |G_i|, sets `l2` to |G| and `scale` to the
// largest term in the balance.
double residual(const Model& model, const State& s, const Controls& c, const std::vector<HingeState>& joints,
                double time, double h, ImplicitWorkspace& w, Scratch& scratch, double& scale, double& l2) {
  State& at = w.at;  // evaluate_forces reads x, v and the joints
  at.x.swap(w.x1);
  if (w.statics)
    at.v.setZero(3, at.x.cols());
  else
    at.v.swap(w.v1);
  at.joints = joints;
  at.t = time;
  at.step = s.step + 1;
  bool finite = true;
  try {
    evaluate_forces(model, at, c, scratch);
  } catch (const SimulationFailure&) {
    finite = false;  // an iterate that degenerates an element: no residual
  }
  w.x1.swap(at.x);
  if (!w.statics) w.v1.swap(at.v);
  if (!finite) {
    scale = l2 = std::numeric_limits<double>::infinity();
    return scale;
  }
  const Points& f = scratch.f;
  // The balance's largest term: momenta (their round-off bounds how small G
  // can get), the momentum change, and the forces times dt. Quasi-static:
  // the forces and loads alone.
  if (w.statics) {
    scale = 0.0;
    w.r.setZero(3, f.cols());
  } else {
    scale = std::max((w.v1 * model.mass.asDiagonal()).cwiseAbs().maxCoeff(),
                     (w.v_base * model.mass.asDiagonal()).cwiseAbs().maxCoeff());
    w.r = (w.v1 - w.v_base) * model.mass.asDiagonal();
  }
  scale = std::max({scale, w.r.cwiseAbs().maxCoeff(), h * f.cwiseAbs().maxCoeff(), h * w.load.cwiseAbs().maxCoeff()});
  w.r -= h * (f + w.load);
  // The held nodes' rows: h times the force that holds them; a sliding
  // node's normal part leaves G (its fixed components go below).
  for (HeldContact& hc : w.held) {
    hc.row = w.r.col(hc.node);
    if (hc.slides) w.r.col(hc.node) -= hc.row.dot(hc.normal) * hc.normal;
  }
  double worst = 0.0, sum = 0.0;
  for (Eigen::Index i = 0; i < w.r.size(); ++i) {
    if (w.fixed[static_cast<size_t>(i)]) w.r.data()[i] = 0.0;
    worst = std::max(worst, std::abs(w.r.data()[i]));
    sum += w.r.data()[i] * w.r.data()[i];
  }
  l2 = std::isfinite(sum) ? std::sqrt(sum) : std::numeric_limits<double>::infinity();
  if (!std::isfinite(sum)) worst = l2;
  return worst;
}

// Prescribed rows and columns (`fixed`) become identity rows (their update is zero).
void fix_prescribed(const std::vector<char>& fixed, Eigen::SparseMatrix<double>& A) {
  double* values = A.valuePtr();
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (int col = 0; col < A.cols(); ++col)
    for (int k = outer[col]; k < outer[col + 1]; ++k) {
      const int row = inner[k];
      if (fixed[static_cast<size_t>(col)] || fixed[static_cast<size_t>(row)]) values[k] = row == col ? 1.0 : 0.0;
    }
}

// The force that round-off leaves in a spring sum (or the continuum
// element's): a few hundred machine epsilons of the largest force a spring
// exerts at unit strain, k_s L0. At
// rest, with no load, the balance's largest term is itself round-off, and a
// tolerance relative to it alone would ask for less than round-off can give.
double round_off_force(const Model& model) {
  double f = 0.0;
  const ForcePlan& p = model.plan;
  for (int e = 0; e < p.num_edges(); ++e)  // k_s times the edge's length at rest (zero-length springs: not their rest length)
    f = std::max(f, p.edge_k_s[static_cast<size_t>(e)] *
                        (model.rest_positions.col(p.edge_b[static_cast<size_t>(e)]) -
                         model.rest_positions.col(p.edge_a[static_cast<size_t>(e)])).norm());
  // The continuum element's: its moduli times a face area, (mu + lambda) V0^(2/3).
  if (model.terms & kNeoHookean)
    for (size_t t = 0; t < model.elements.size(); ++t) {
      const SnhConstants& c = model.continuum.constants[t];
      f = std::max(f, (c.mu + c.lambda) * std::cbrt(model.elements[t].rest_volume * model.elements[t].rest_volume));
    }
  // The bulk term's: its moduli times a group's face area.
  if (model.terms & kBulk)
    for (int g = 0; g < model.volume_groups.size(); ++g) {
      const double v0 = model.volume_groups.rest_volume[static_cast<size_t>(g)];
      const BulkLaw& law = model.volume_groups.bulk_law[static_cast<size_t>(g)];
      f = std::max(f, (law.modulus + law.rest_modulus) * std::cbrt(v0 * v0));
    }
  return 1e3 * std::numeric_limits<double>::epsilon() * f;
}

// Whether the solve holds the nodes the kept factorisation was made for.
bool same_held_nodes(const ImplicitWorkspace& w) {
  return std::equal(w.held.begin(), w.held.end(), w.held_before.begin(), w.held_before.end(),
                    [](const HeldContact& hc, int node) { return hc.node == node; });
}

// The symmetric part's ordering and its permuted pattern, once per layout:
// AMD on the layout's pattern (structurally symmetric: every block (a, b) has
// its (b, a)), C = P S P^T's upper triangle as Eigen's factorize() would form
// it, and for each entry of C the positions in A's values of the entries
// (i, j) and (j, i) of S it holds - found by permuting a copy of the pattern
// whose values are their own positions.
void analyse_symmetric_part(ImplicitWorkspace& w) {
  const Eigen::SparseMatrix<double>& pattern = w.layout.pattern;
  w.ldlt.analyzePattern(pattern);
  Eigen::SparseMatrix<double> ids = pattern;
  for (Eigen::Index k = 0; k < ids.nonZeros(); ++k) ids.valuePtr()[k] = static_cast<double>(k);
  w.C.resize(pattern.rows(), pattern.cols());
  w.C.selfadjointView<Eigen::Upper>() = ids.selfadjointView<Eigen::Lower>().twistedBy(w.ldlt.permutationP());
  w.C.makeCompressed();
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  // Position of (row, col) in the pattern's values.
  const auto at = [&](int row, int col) {
    const int* p = std::lower_bound(inner + outer[col], inner + outer[col + 1], row);
    if (p == inner + outer[col + 1] || *p != row) throw Error("implicit step: the system's pattern is not symmetric");
    return static_cast<int>(p - inner);
  };
  w.c_from.resize(static_cast<size_t>(w.C.nonZeros()));
  w.c_from_t.resize(w.c_from.size());
  for (size_t k = 0; k < w.c_from.size(); ++k) {
    const int from = static_cast<int>(w.C.valuePtr()[k]);
    const int col = static_cast<int>(std::upper_bound(outer, outer + pattern.cols() + 1, from) - outer) - 1;
    const int row = inner[from];
    w.c_from[k] = from;
    w.c_from_t[k] = at(col, row);
  }
  w.permuted.resize(pattern.rows());
  w.ldlt_analysed = true;
}

// Factorises w.A by the model's linear solver (NewtonOptions): A itself, or
// its symmetric part (A + A^T)/2 - whose pattern is the layout's for every
// factorisation, so its ordering is analysed once. Returns whether it worked.
bool factorize(const Model& model, ImplicitWorkspace& w) {
  if (model.newton.linear_solver == LinearSolver::sparse_lu) {
    w.lu.factorize(w.A);
    return w.lu.info() == Eigen::Success;
  }
  if (!w.ldlt_analysed) analyse_symmetric_part(w);
  double* c = w.C.valuePtr();
  const double* a = w.A.valuePtr();
  for (size_t k = 0; k < w.c_from.size(); ++k)
    c[k] = 0.5 * (a[w.c_from[k]] + a[w.c_from_t[k]]);
  w.ldlt.factorize_permuted(w.C);
  return w.ldlt.info() == Eigen::Success;
}

// w.delta = (the factorised matrix)^-1 w.rhs.
void solve(const Model& model, ImplicitWorkspace& w) {
  if (model.newton.linear_solver == LinearSolver::sparse_lu)
    w.delta = w.lu.solve(w.rhs);
  else
    w.ldlt.solve_into(w.rhs, w.permuted, w.delta);
}

// Newton's stopping bound on max |G_i|: the tolerance relative to the
// balance's largest term, and never below the round-off force times h.
double tolerance(const Model& model, double scale, double h, const ImplicitWorkspace& w) {
  return std::max(model.newton.tolerance * scale, h * w.force_floor);
}

// Whether the quasi-static balance is the gradient of conservative_energy
// minus the loads' work: every force term has an energy (not the thesis'
// volume term) and there are no moving parts, obstacles or contacts.
bool has_potential(const Model& model) {
  return !(model.terms & kVolume) && model.strands.empty() && model.muscles.empty() && model.joints.empty() &&
         model.skin.triangles.empty() && model.obstacles.empty() && !model.self_contact;
}

// The potential energy at the iterate w.x1: stored energy minus the dead loads' work.
double potential_energy(const Model& model, const ImplicitWorkspace& w) {
  return conservative_energy(model, w.x1) - (w.load.array() * w.x1.array()).sum();
}

// Whether every tet of the iterate w.x1 keeps its orientation (signed
// volume > 0); always true without NewtonOptions::keep_orientation.
bool orientation_kept(const Model& model, const ImplicitWorkspace& w) {
  if (!model.newton.keep_orientation) return true;
  for (const Element& el : model.elements) {
    const auto& n = el.nodes;
    if (!(tet_signed_volume(w.x1.col(n[0]), w.x1.col(n[1]), w.x1.col(n[2]), w.x1.col(n[3])) > 0.0)) return false;
  }
  return true;
}

// Sizes the history for the model (at each Newton solve's start: it
// allocates only when the model's size or depth changed) and clears it.
void clear_anderson(const Model& model, ImplicitWorkspace& w) {
  const int m = model.newton.anderson_depth;
  const Eigen::Index n = 3 * static_cast<Eigen::Index>(model.num_nodes());
  if (m > 0 && (w.dv.rows() != n || w.dv.cols() != m)) {
    w.dv.resize(n, m);
    w.dd.resize(n, m);
    w.dg.resize(n, m);
    w.last_v.resize(n);
    w.last_d.resize(n);
    w.last_g.resize(n);
  }
  w.kept = -1;
}

// Anderson acceleration (Anderson 1965, J. ACM 12:547; Walker & Ni 2011,
// SIAM J. Numer. Anal. 49:1715) of the chord iteration v <- v + d(v),
// d = J0^-1 (-G(v)), J0 the kept factorisation's matrix. With the last m
// iterates' differences dV, their updates' dD and their residuals' dG:
//   gamma = argmin |G - dG gamma|,   update = d - (dV + dD) gamma.
// For a linear G the combination's residual is G - dG gamma, so gamma
// minimises the residual Newton's test reads (a GMRES-like minimal residual
// over the history). The least squares is in G's norm, not d's (Walker & Ni's
// form): measured on the physiological leg, the chord steps' d shrinks about
// three-fold per iteration while |G| - dominated by the stiff tendons, where a
// tiny velocity error is a large force - shrinks by only 0.69, and a fit of d
// left that mode alone. Normal equations, m <= 8, a 1e-12 relative Tikhonov
// term for nearly parallel columns. w.delta holds d on entry and the update
// on return; w.r holds G at w.v1. Allocates nothing (clear_anderson sizes
// the history).
void anderson_step(const Model& model, ImplicitWorkspace& w) {
  const int m = model.newton.anderson_depth;
  const Eigen::Index n = w.delta.size();
  const Eigen::Map<const Eigen::VectorXd> v(w.v1.data(), n);
  const Eigen::Map<const Eigen::VectorXd> g_now(w.r.data(), n);
  if (w.kept < 0) {  // the first chord step since the history was cleared
    w.kept = 0;
    w.ring = 0;
  } else {
    w.dv.col(w.ring) = v - w.last_v;
    w.dd.col(w.ring) = w.delta - w.last_d;
    w.dg.col(w.ring) = g_now - w.last_g;
    w.ring = (w.ring + 1) % m;
    w.kept = std::min(w.kept + 1, m);
  }
  w.last_v = v;
  w.last_d = w.delta;
  w.last_g = g_now;
  if (w.kept == 0) return;
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 8, 8>;
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 8, 1>;
  const int k = w.kept;
  Small g(k, k);
  SmallVec b(k);
  for (int i = 0; i < k; ++i) {
    b(i) = w.dg.col(i).dot(g_now);
    for (int j = 0; j <= i; ++j) g(i, j) = g(j, i) = w.dg.col(i).dot(w.dg.col(j));
  }
  // A little Tikhonov regularisation keeps nearly parallel columns harmless.
  g.diagonal().array() += 1e-12 * g.trace() + std::numeric_limits<double>::min();
  const SmallVec gamma = g.ldlt().solve(b);
  for (int i = 0; i < k; ++i) w.delta -= gamma(i) * (w.dv.col(i) + w.dd.col(i));
}

// What the last Newton solve reached.
struct NewtonResult {
  bool converged = false;
  int iterations = 0;
  double residual = 0.0, scale = 0.0;  // max |G_i| and the balance's largest term
  const char* why = "";  // why it stopped (a literal: a failed solve that a cut step retries allocates nothing)
};

// Newton's method on G(v+) = 0 for one step from `s` to time `time`, with
// the base (w.x_base, w.v_base) and coefficient h set; starts from w.v1 (the
// caller's guess) and leaves the iterate in w.x1, w.v1.
NewtonResult newton(const Model& model, const State& s, const Controls& c, const std::vector<HingeState>& joints,
                    double time, double h, ImplicitWorkspace& w, Scratch& scratch) {
  NewtonResult out;
  clear_anderson(model, w);  // no Anderson history: a new solve
  positions_from_velocities(model, c, joints, h, w);
  if (!orientation_kept(model, w)) {  // the guess inverts a tet: start from the step's start positions instead
    w.v1 = (s.x - w.x_base) / h;
    positions_from_velocities(model, c, joints, h, w);
  }
  double l2 = 0.0;
  out.residual = residual(model, s, c, joints, time, h, w, scratch, out.scale, l2);
  while (!(out.residual <= tolerance(model, out.scale, h, w))) {
    if (!std::isfinite(out.residual)) {
      out.why = "met non-finite forces";
      return out;
    }
    if (out.iterations == model.newton.max_iterations) {
      out.why = "did not converge";
      return out;
    }
    ++out.iterations;
    w.rhs = -Eigen::Map<const Eigen::VectorXd>(w.r.data(), w.r.size());
    // Modified Newton: a factorisation kept from an earlier iterate or step
    // (same h) gives a chord step, kept when it at least halves |G|;
    // otherwise (or without one) the Jacobian is made afresh here.
    if (model.newton.reuse_factorization && w.factored && w.factor_h == h && w.factor_statics == w.statics && !w.refresh &&
        same_held_nodes(w)) {
      solve(model, w);
      if (model.newton.anderson_depth > 0) anderson_step(model, w);
      w.v_trial = w.v1;
      w.r_keep = w.r;
      w.v1 = w.v_trial + Eigen::Map<const Points>(w.delta.data(), 3, model.num_nodes());
      positions_from_velocities(model, c, joints, h, w);
      double scale = 0.0, trial_l2 = std::numeric_limits<double>::infinity();
      const double trial =
          orientation_kept(model, w) ? residual(model, s, c, joints, time, h, w, scratch, scale, trial_l2) : trial_l2;
      if (trial_l2 <= 0.5 * l2) {
        // With LU a weak contraction (worse than 1/10) would spend the
        // iteration budget: the next iteration factorises afresh. The
        // symmetric part's fresh factorisation contracts no faster than a
        // kept one (its rate is A's asymmetry), so with LDLT only a chord
        // step that stops halving |G| (below) makes a fresh one.
        w.refresh = trial_l2 > (model.newton.linear_solver == LinearSolver::sparse_lu ? 0.1 : 0.5) * l2;
        out.residual = trial;
        out.scale = scale;
        l2 = trial_l2;
        continue;
      }
      w.v1 = w.v_trial;  // back to the iterate, for a fresh Jacobian there
      w.r = w.r_keep;
      positions_from_velocities(model, c, joints, h, w);
    }
    if (w.statics)  // G = -h (f(x1, 0) + load): only the stiffness, at zero velocity
      assemble_system(model, w.layout, w.x1, w.still, joints, c, 0.0, 0.0, -h * h, w.A);
    else
      assemble_system(model, w.layout, w.x1, w.v1, joints, c, 1.0, -h, -h * h, w.A);
    fix_prescribed(w.fixed, w.A);
    hold_sliding_in_matrix(w.layout, w, w.A);
    w.factored = factorize(model, w);
    ++scratch.factorizations;
    clear_anderson(model, w);  // a new chord map: the Anderson history is of the old one
    w.held_before.clear();
    for (const HeldContact& hc : w.held) w.held_before.push_back(hc.node);
    w.factor_h = h;
    w.factor_statics = w.statics;
    w.refresh = false;
    if (!w.factored) {
      out.why = "met a singular matrix";
      return out;
    }
    solve(model, w);
    // Backtracking on |G| (the exact Newton direction descends it; the
    // symmetric part's, near it, as a rule): halve the update until |G|
    // decreases, at most 10 times. Quasi-static with a potential energy: an
    // update that lowers the energy is accepted too - near incompressibility
    // the linearised step's rotations change volumes to second order, so |G|
    // grows at the full step, which is still the way to the equilibrium (the
    // FEM reference's line search is on its energy for the same reason).
    w.v_trial = w.v1;
    const bool by_energy = w.statics && has_potential(model);
    const double e0 = by_energy ? potential_energy(model, w) : 0.0;
    double alpha = 1.0;
    bool kept = true;
    for (int ls = 0;; ++ls) {
      w.v1 = w.v_trial + alpha * Eigen::Map<const Points>(w.delta.data(), 3, model.num_nodes());
      positions_from_velocities(model, c, joints, h, w);
      double scale = 0.0, trial_l2 = std::numeric_limits<double>::infinity();
      // An update that inverts a tet (keep_orientation) counts as no decrease.
      kept = orientation_kept(model, w);
      const double trial = kept ? residual(model, s, c, joints, time, h, w, scratch, scale, trial_l2) : trial_l2;
      if (trial_l2 < l2 || ls == 10 || (by_energy && std::isfinite(trial_l2) && potential_energy(model, w) < e0)) {
        out.residual = trial;
        out.scale = scale;
        l2 = trial_l2;
        break;
      }
      alpha *= 0.5;
    }
    if (!kept) {
      out.why = "inverted a tet at every halving of its update (keep_orientation)";
      return out;
    }
  }
  out.converged = true;
  return out;
}

// The prescribed offset of group g now (from its first node's prescribed axes).
Vec3 group_offset_now(const Model& model, const State& s, size_t g, const Vec3& target) {
  const KinematicGroup& grp = model.groups[g];
  Vec3 off = target;
  if (grp.nodes.empty()) return off;
  const int n = grp.nodes.front();
  for (int a = 0; a < 3; ++a)
    if (grp.axes[a]) off[a] = s.x(a, n) - model.rest_positions(a, n);
  return off;
}

// Sets the step's base and returns h. Backward Euler: the state, h = dt.
// BDF2 with a history one step back of length dt- (omega = dt / dt-), the
// variable-step form (Hairer, Norsett & Wanner, Solving ODEs I, III.5):
//   y+ - (1+omega)^2/(1+2 omega) y + omega^2/(1+2 omega) y- = (1+omega)/(1+2 omega) dt F(y+),
// for omega = 1 the familiar y+ = 4/3 y - 1/3 y- + 2/3 dt F(y+). Without a
// history, or when the step grew more than twice (omega > 2: near the edge of
// its zero-stability, omega < 1 + sqrt 2), a backward-Euler step restarts it.
double set_base(const State& s, double dt, bool bdf2, ImplicitWorkspace& w) {
  if (bdf2 && s.dt_prev > 0.0 && dt <= 2.0 * s.dt_prev && s.x_prev.cols() == s.x.cols() &&
      s.v_prev.cols() == s.v.cols()) {
    const double omega = dt / s.dt_prev, d = 1.0 + 2.0 * omega;
    const double alpha = (1.0 + omega) * (1.0 + omega) / d, beta = omega * omega / d;
    w.x_base = alpha * s.x - beta * s.x_prev;
    w.v_base = alpha * s.v - beta * s.v_prev;
    return (1.0 + omega) / d * dt;
  }
  w.x_base = s.x;
  w.v_base = s.v;
  return dt;
}

// The dead loads at load scale `scale`: scale (f_ext + M g).
void set_load(const Model& model, double scale, ImplicitWorkspace& w) {
  w.load.setZero(3, model.num_nodes());
  if (model.external_force.cols() == model.num_nodes()) w.load = scale * model.external_force;
  if (model.terms & kGravity) w.load.noalias() += (scale * model.gravity) * model.mass.transpose();  // (an outer product: without noalias a temporary)
}

// Advances s by dt to `time`: one Newton solve, or - when it fails - two
// half steps (prescribed offsets and joint states halfway), up to
// max_step_cuts times. The joints go from `from` to `to` over the step.
// With `bdf2` each solved step is a BDF2 step where s has a history, and
// leaves s's history for the next one.
void advance(const Model& model, State& s, const Controls& c, const std::vector<HingeState>& from,
             const std::vector<HingeState>& to, double time, double dt, int cuts, bool bdf2,
             ImplicitWorkspace& w, Scratch& scratch) {
  const double h = set_base(s, dt, bdf2, w);
  set_load(model, c.load_scale, w);
  hold_contacts(model, s, c, dt, w);
  // The first iterate: the velocity now (backward Euler), or with BDF2's
  // history the velocity extrapolated linearly to the step's end.
  if (bdf2 && h != dt)
    w.v1 = s.v + (dt / s.dt_prev) * (s.v - s.v_prev);
  else
    w.v1 = s.v;
  NewtonResult r = newton(model, s, c, to, time, h, w, scratch);
  scratch.last_newton_iterations += r.iterations;
  // A held node the obstacle would have to pull goes free and the solve is
  // repeated from its solution (at most 8 times; what is still held then
  // stays held for this step).
  for (int pass = 0; r.converged && pass < 8 && release_pulling_contacts(w); ++pass) {
    r = newton(model, s, c, to, time, h, w, scratch);
    scratch.last_newton_iterations += r.iterations;
  }
  if (r.converged) {
    settle_sliding(model, c, w);
    w.load_from = c.load_scale;
    if (bdf2) {
      s.x_prev.swap(s.x);
      s.v_prev.swap(s.v);
      s.dt_prev = dt;
    }
    s.x = w.x1;
    s.v = w.v1;
    return;
  }
  if (cuts == model.newton.max_step_cuts) {
    Eigen::Index axis = 0, node = 0;
    w.r.cwiseAbs().maxCoeff(&axis, &node);
    std::ostringstream m;
    m << (w.statics ? "quasi-static" : bdf2 ? "BDF2" : "backward Euler") << ": Newton " << r.why << " after " << r.iterations << " iterations with the step cut "
      << cuts << " times to " << dt << " s (residual " << r.residual / h << " N, tolerance "
      << tolerance(model, r.scale, h, w) / h << " N)";
    throw SimulationFailure(m.str(), time, s.step + 1, -1, static_cast<int>(node));
  }
  // The halfway controls and joints, in buffers per cut depth (sized in
  // step_implicit, never here: the deeper calls hold references into them;
  // reused, so a cut step allocates nothing once its depth has been reached).
  Controls& mid = w.cut_controls[static_cast<size_t>(cuts)];
  mid = c;
  // Quasi-static: the load halfway too (the equilibria between are a
  // continuation path to the step's end). Dynamic steps keep the end's load.
  if (w.statics) mid.load_scale = 0.5 * (w.load_from + c.load_scale);
  for (size_t g = 0; g < model.groups.size(); ++g)
    mid.group_offset[g] = 0.5 * (group_offset_now(model, s, g, c.group_offset[g]) + c.group_offset[g]);
  // A rigid motion halfway: its second-order Taylor estimate half a step back.
  for (auto& m : mid.group_motion)
    if (m) m = rigid_motion_before(*m, 0.5 * dt);
  std::vector<HingeState>& half = w.cut_joints[static_cast<size_t>(cuts)];
  half.resize(to.size());
  for (size_t j = 0; j < to.size(); ++j)
    half[j] = {0.5 * (from[j].angle + to[j].angle), 0.5 * (from[j].velocity + to[j].velocity)};
  ++scratch.last_step_cuts;
  advance(model, s, mid, from, half, time - 0.5 * dt, 0.5 * dt, cuts + 1, bdf2, w, scratch);
  advance(model, s, c, half, to, time, 0.5 * dt, cuts + 1, bdf2, w, scratch);
}

}  // namespace

namespace {

void step_implicit(const Model& model, State& state, const Controls& controls, double dt, bool bdf2,
                   Scratch& scratch, bool statics = false) {
  ImplicitWorkspace& w = workspace(model, scratch);
  w.statics = statics;
  if (statics) w.still.setZero(3, model.num_nodes());
  if (controls.group_offset.size() < model.groups.size() || controls.group_velocity.size() < model.groups.size())
    throw Error(std::string(statics ? "quasi-static" : bdf2 ? "BDF2" : "backward Euler") + ": controls for " + std::to_string(model.groups.size()) + " kinematic groups needed");
  scratch.last_newton_iterations = 0;
  scratch.last_step_cuts = 0;
  w.force_floor = round_off_force(model);
  const size_t depths = static_cast<size_t>(std::max(model.newton.max_step_cuts, 0));
  if (w.cut_controls.size() < depths) {
    w.cut_controls.resize(depths);
    w.cut_joints.resize(depths);
  }
  // The joints were stepped already (step_joints): the solve holds their
  // groups at the new states, halfway ones when the step is cut.
  w.joints_end = state.joints;
  // (Called without step_joints - directly - the joints have no start: no halfway states.)
  const std::vector<HingeState>& from =
      scratch.joints_before.size() == w.joints_end.size() ? scratch.joints_before : w.joints_end;
  advance(model, state, controls, from, w.joints_end, state.t + dt, dt, 0, bdf2, w, scratch);
  scratch.newton_iterations += scratch.last_newton_iterations;
  scratch.step_cuts += scratch.last_step_cuts;
}

}  // namespace

void step_backward_euler(const Model& model, State& state, const Controls& controls, double dt, Scratch& scratch) {
  step_implicit(model, state, controls, dt, false, scratch);
}

void step_bdf2(const Model& model, State& state, const Controls& controls, double dt, Scratch& scratch) {
  step_implicit(model, state, controls, dt, true, scratch);
}

void step_quasi_static(const Model& model, State& state, const Controls& controls, double dt, Scratch& scratch) {
  if (!model.joints.empty())
    throw Error("quasi-static: the model has " + std::to_string(model.joints.size()) +
                " joints, whose motion is dynamic; use backward_euler or bdf2");
  // Contact with a rigid obstacle is held through velocities over the step
  // (hold_contacts), which a quasi-static step does not have: measured on the
  // indentation benchmark, the force came out 135 % off (8.5 % dynamically).
  if (!model.obstacles.empty())
    throw Error("quasi-static: the model has " + std::to_string(model.obstacles.size()) +
                " rigid obstacles, whose contact the quasi-static step does not hold yet; use backward_euler or bdf2");
  if (model.self_contact)
    throw Error("quasi-static: the model has self-contact, which is resolved on positions and velocities after "
                "each step; use backward_euler or bdf2");
  step_implicit(model, state, controls, dt, false, scratch, true);
}

}  // namespace msd
