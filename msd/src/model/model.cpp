#include "msd/model/model.hpp"

#include "msd/forces/force_engine.hpp"
#include "msd/forces/zero_length_springs.hpp"
#include "msd/forces/tet_frame.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace msd {

ForceTerm parse_force_term(const std::string& name) {
  if (name == "springs") return kSprings;
  if (name == "dampers") return kDampers;
  if (name == "repulsion") return kRepulsion;
  if (name == "volume") return kVolume;
  if (name == "gravity") return kGravity;
  if (name == "neo_hookean") return kNeoHookean;
  if (name == "bulk") return kBulk;
  throw Error("unknown force term '" + name +
              "' (expected springs, dampers, repulsion, volume, gravity, neo_hookean or bulk)");
}

std::string force_terms_to_string(unsigned terms) {
  std::string s;
  const char* names[] = {"springs", "dampers", "repulsion", "volume", "gravity", "neo_hookean", "bulk"};
  for (int b = 0; b < 7; ++b)
    if (terms & (1u << b)) s += (s.empty() ? "" : ",") + std::string(names[b]);
  return s;
}

const char* to_string(LinearSolver s) { return s == LinearSolver::sparse_lu ? "sparse_lu" : "symmetric_ldlt"; }

LinearSolver parse_linear_solver(const std::string& name) {
  if (name == "sparse_lu") return LinearSolver::sparse_lu;
  if (name == "symmetric_ldlt") return LinearSolver::symmetric_ldlt;
  throw Error("unknown linear solver '" + name + "' (expected sparse_lu or symmetric_ldlt)");
}

namespace {

// The groups of ModelOptions::volume_group, numbered in order of first appearance.
VolumeGroups make_volume_groups(const Model& model, const std::vector<long>& label) {
  if (!(model.terms & (kNeoHookean | kBulk)))
    throw Error("volume groups are given but the model has neither the neo_hookean nor the bulk term");
  const size_t nt = model.elements.size();
  if (label.size() != nt)
    throw Error("volume groups: " + std::to_string(label.size()) + " labels for " + std::to_string(nt) + " tets");
  std::map<long, int> index;
  std::vector<int> of_tet(nt);
  for (size_t t = 0; t < nt; ++t) of_tet[t] = index.emplace(label[t], static_cast<int>(index.size())).first->second;
  const size_t ng = index.size();
  VolumeGroups g;
  g.of_tet = of_tet;
  g.tet_offset.assign(ng + 1, 0);
  for (int k : of_tet) ++g.tet_offset[static_cast<size_t>(k) + 1];
  for (size_t k = 0; k < ng; ++k) g.tet_offset[k + 1] += g.tet_offset[k];
  g.tets.resize(nt);
  std::vector<int> next(g.tet_offset.begin(), g.tet_offset.end() - 1);
  for (size_t t = 0; t < nt; ++t) g.tets[static_cast<size_t>(next[static_cast<size_t>(of_tet[t])]++)] = static_cast<int>(t);
  g.rest_volume.assign(ng, 0.0);
  g.corner_slot.assign(4 * nt, -1);
  g.node_offset.assign(1, 0);
  for (size_t k = 0; k < ng; ++k) {
    const int first = g.tets[static_cast<size_t>(g.tet_offset[k])];
    const size_t start = g.nodes.size();
    for (int q = g.tet_offset[k]; q < g.tet_offset[k + 1]; ++q) {
      const size_t t = static_cast<size_t>(g.tets[static_cast<size_t>(q)]);
      const Element& el = model.elements[t];
      if (el.region != model.elements[static_cast<size_t>(first)].region)
        throw Error("volume group " + std::to_string(k) + " has tets of regions " +
                    std::to_string(model.elements[static_cast<size_t>(first)].region) + " and " + std::to_string(el.region) +
                    " (tet " + std::to_string(t) + "): a group shares one material");
      g.rest_volume[k] += el.rest_volume;
      for (int i = 0; i < 4; ++i) {
        const auto at = std::find(g.nodes.begin() + static_cast<long>(start), g.nodes.end(), el.nodes[static_cast<size_t>(i)]);
        g.corner_slot[4 * t + static_cast<size_t>(i)] = static_cast<int>(at - (g.nodes.begin() + static_cast<long>(start)));
        if (at == g.nodes.end()) g.nodes.push_back(el.nodes[static_cast<size_t>(i)]);
      }
    }
    g.node_offset.push_back(static_cast<int>(g.nodes.size()));
    if (model.terms & kBulk) {
      const int r = model.elements[static_cast<size_t>(first)].region;
      g.bulk_law.push_back(
          lattice_bulk_law(model.region_materials[static_cast<size_t>(r)], "material of region " + std::to_string(r)));
    }
  }
  return g;
}

// Zero-length springs (msd/forces/zero_length_springs.hpp): the same for
// every region, with the springs and the bulk term.
void check_zero_length_springs(const ModelOptions& options) {
  for (size_t r = 0; r < options.region_materials.size(); ++r) {
    const std::string where = "material of region " + std::to_string(r) + ": zero_length_springs";
    if (options.region_materials[r].zero_length_springs != options.region_materials[0].zero_length_springs)
      throw Error(where + " differs from region 0's: give every region the same springs");
    if (!options.region_materials[r].zero_length_springs) continue;
    // (Beside the neo_hookean term the bulk term is refused already: one volume term per model.)
    if (!(options.terms & kSprings) || !(options.terms & kBulk))
      throw Error(where + " need the springs and the bulk term (its rest pressure holds the springs' pull)");
  }
}

// A tet's zero-length springs: k = mu w (the cotangent weights of its rest
// corners x), rest length 0. The dampers keep element_constants' k_d =
// damping_time k_s of the physical rule (tissue_material.hpp; why:
// zero_length_springs.hpp).
void set_zero_length_springs(const TissueMaterial& mat, int region, const Vec3 x[4], Element& el) {
  const double mu = scaled_shear_modulus(mat, "material of region " + std::to_string(region), "zero_length_springs");
  double w[6];
  cotangent_weights(x, w);
  for (int k = 0; k < 6; ++k) {
    el.k.k_s[k] = mu * w[k];
    el.rest_length[k] = 0.0;
  }
}

}  // namespace

Model build_model(const TetMesh& mesh, const ModelOptions& options) {
  check_tet_mesh(mesh, "model mesh");
  Model model;
  model.rest_positions = mesh.nodes;
  model.terms = options.terms;
  model.nonlinear_threshold = options.nonlinear_threshold;
  model.gravity = options.gravity;
  model.region_materials = options.region_materials;
  if (!(options.nonlinear_threshold >= 0.0 && options.nonlinear_threshold <= 1.0))
    throw Error("nonlinear_threshold must be in [0, 1] (0 = terms always on)");
  if (!options.gravity.allFinite()) throw Error("gravity is not finite");
  if (options.threads < 1)
    throw Error("threads must be at least 1, got " + std::to_string(options.threads));
  model.threads = options.threads;
  if (!(options.newton.tolerance > 0.0 && options.newton.tolerance < 1.0))
    throw Error("newton tolerance must be in (0, 1), got " + std::to_string(options.newton.tolerance));
  if (options.newton.max_iterations < 1)
    throw Error("newton max_iterations must be at least 1, got " + std::to_string(options.newton.max_iterations));
  if (options.newton.max_step_cuts < 0)
    throw Error("newton max_step_cuts must be at least 0, got " + std::to_string(options.newton.max_step_cuts));
  if (options.newton.anderson_depth < 0 || options.newton.anderson_depth > 8)
    throw Error("newton anderson_depth must be in [0, 8], got " + std::to_string(options.newton.anderson_depth));
  model.newton = options.newton;
  model.reference_forces = options.reference_forces;
  for (size_t r = 0; r < options.region_materials.size(); ++r)
    check_material(options.region_materials[r], "material of region " + std::to_string(r));

  const int n = mesh.num_nodes();
  model.mass = Eigen::VectorXd::Zero(n);
  // Equal-per-node lumping needs each region's total mass and node count first.
  std::vector<double> region_mass(options.region_materials.size(), 0.0);
  std::vector<std::vector<char>> region_nodes(options.region_materials.size());

  model.elements.reserve(mesh.tets.size());
  for (size_t e = 0; e < mesh.tets.size(); ++e) {
    const int r = mesh.region[e];
    if (r < 0 || r >= static_cast<int>(options.region_materials.size()))
      throw Error("tet " + std::to_string(e) + " has region " + std::to_string(r) +
                  " but no material is given for it");
    const TissueMaterial& mat = options.region_materials[static_cast<size_t>(r)];
    Element el;
    el.nodes = mesh.tets[e];
    el.region = r;
    Vec3 x[4];
    for (int i = 0; i < 4; ++i) x[i] = mesh.nodes.col(el.nodes[i]);
    const TetFrame g = tet_frame(x);
    el.rest_volume = g.volume;
    for (int i = 0; i < 4; ++i) el.rest_height[i] = g.height[i];
    for (int k = 0; k < 6; ++k) {
      const Vec3 d = x[kTetEdges[k][1]] - x[kTetEdges[k][0]];
      el.rest_length[k] = d.norm();
      el.edge_class[k] = classify_edge(d);
    }
    el.floor = mat.repulsion_floor;
    el.k = element_constants(mat, el.rest_volume, el.rest_length, el.rest_height, el.edge_class);
    if (mat.zero_length_springs) set_zero_length_springs(mat, r, x, el);
    if (options.terms & kNeoHookean) {
      if (mat.mode != ConstantsMode::Physical || !mat.poisson_ratio)
        throw Error("material of region " + std::to_string(r) +
                    ": the neo_hookean term needs physical constants with a Poisson's ratio (youngs_modulus, poisson_ratio)");
      model.continuum.dm_inv.push_back(rest_shape_inverse(x));
      model.continuum.constants.push_back(snh_constants(mat.youngs_modulus, *mat.poisson_ratio, mat.stiffness_scale));
    }
    const double m = mat.density * el.rest_volume;
    if (mat.lumping == MassLumping::PerTet) {
      for (int i = 0; i < 4; ++i) model.mass[el.nodes[i]] += 0.25 * m;
    } else {
      region_mass[static_cast<size_t>(r)] += m;
      auto& flags = region_nodes[static_cast<size_t>(r)];
      if (flags.empty()) flags.assign(static_cast<size_t>(n), 0);
      for (int i = 0; i < 4; ++i) flags[static_cast<size_t>(el.nodes[i])] = 1;
    }
    model.elements.push_back(el);
  }
  for (size_t r = 0; r < region_nodes.size(); ++r) {
    if (region_nodes[r].empty()) continue;
    const long count = std::count(region_nodes[r].begin(), region_nodes[r].end(), 1);
    for (int i = 0; i < n; ++i)
      if (region_nodes[r][static_cast<size_t>(i)]) model.mass[i] += region_mass[r] / static_cast<double>(count);
  }
  for (int i = 0; i < n; ++i)
    if (!(model.mass[i] > 0.0)) throw Error("node " + std::to_string(i) + " belongs to no tet (zero mass)");
  model.inv_mass = model.mass.cwiseInverse();
  if ((options.terms & kBulk) && (options.terms & kNeoHookean))
    throw Error("the bulk term and the neo_hookean term are two volume terms for one model: choose one");
  check_zero_length_springs(options);
  if ((options.terms & kBulk) && options.volume_group.empty())
    throw Error("the bulk term needs volume groups (ModelOptions::volume_group: the lattice's cubes)");
  if (!options.volume_group.empty()) model.volume_groups = make_volume_groups(model, options.volume_group);
  model.plan = make_force_plan(model.elements, model.region_materials, n);

  std::vector<int> owner(static_cast<size_t>(n), -1);
  for (size_t g = 0; g < options.groups.size(); ++g) {
    for (int node : options.groups[g].nodes) {
      if (node < 0 || node >= n)
        throw Error("kinematic group '" + options.groups[g].name + "' refers to node " +
                    std::to_string(node) + " of " + std::to_string(n));
      if (owner[static_cast<size_t>(node)] >= 0)
        throw Error("node " + std::to_string(node) + " is in kinematic groups '" +
                    options.groups[static_cast<size_t>(owner[static_cast<size_t>(node)])].name +
                    "' and '" + options.groups[g].name + "'");
      owner[static_cast<size_t>(node)] = static_cast<int>(g);
    }
  }
  model.groups = options.groups;
  for (size_t k = 0; k < options.obstacles.size(); ++k) {
    RigidObstacle ob = options.obstacles[k];
    const std::string where = "obstacle '" + ob.name + "'";
    check_obstacle(ob, where);
    if (ob.nodes.empty())
      for (const Tri& f : boundary_faces(mesh.tets))
        for (int v : f) ob.nodes.push_back(v);
    std::sort(ob.nodes.begin(), ob.nodes.end());
    ob.nodes.erase(std::unique(ob.nodes.begin(), ob.nodes.end()), ob.nodes.end());
    for (int node : ob.nodes)
      if (node < 0 || node >= n)
        throw Error(where + " refers to node " + std::to_string(node) + " of " + std::to_string(n));
    // Prescribed nodes follow their group, not the obstacle.
    ob.nodes.erase(std::remove_if(ob.nodes.begin(), ob.nodes.end(),
                                  [&](int node) { return owner[static_cast<size_t>(node)] >= 0; }),
                   ob.nodes.end());
    model.obstacles.push_back(std::move(ob));
  }
  if (options.external_force.size() > 0) {
    if (options.external_force.cols() != n)
      throw Error("external forces given for " + std::to_string(options.external_force.cols()) + " nodes, the mesh has " +
                  std::to_string(n));
    if (!options.external_force.allFinite()) throw Error("external forces are not finite");
    model.external_force = options.external_force;
  }
  check_model_parts(model);
  return model;
}

void check_model_parts(Model& model) {
  const int n = model.num_nodes();
  const auto node_ok = [n](int i) { return i >= 0 && i < n; };
  model.kinematic.assign(static_cast<size_t>(n), 0);
  for (KinematicGroup& g : model.groups) {
    g.joint = -1;
    for (int node : g.nodes) {
      if (!node_ok(node))
        throw Error("kinematic group '" + g.name + "' refers to node " + std::to_string(node) + " of " + std::to_string(n));
      if (model.kinematic[static_cast<size_t>(node)])
        throw Error("node " + std::to_string(node) + " is in two kinematic groups (one is '" + g.name + "')");
      model.kinematic[static_cast<size_t>(node)] = 1;
    }
  }
  for (size_t k = 0; k < model.skin.triangles.size(); ++k) {
    const MembraneTriangle& t = model.skin.triangles[k];
    for (int node : t.nodes)
      if (!node_ok(node)) throw Error("skin triangle " + std::to_string(k) + " refers to node " + std::to_string(node) + " of " + std::to_string(n));
    if (!(t.rest_area > 0.0) || !t.rest_inverse.allFinite())
      throw Error("skin triangle " + std::to_string(k) + " has no rest area");
  }
  if (!model.skin.empty() && (!(model.skin.shear_modulus > 0.0) || !(model.skin.thickness > 0.0) ||
                              !(model.skin.area_floor > 0.0 && model.skin.area_floor <= 1.0)))
    throw Error("skin: shear modulus and thickness must be positive and the area floor in (0, 1]");
  for (size_t s = 0; s < model.strands.size(); ++s) {
    const Strand& st = model.strands[s];
    const std::string where = "strand " + std::to_string(s);
    if (st.nodes.size() + (st.anchor_group >= 0 ? 1 : 0) < 2) throw Error(where + " has fewer than two points");
    for (int node : st.nodes)
      if (!node_ok(node)) throw Error(where + " refers to node " + std::to_string(node) + " of " + std::to_string(n));
    if (st.anchor_group >= static_cast<int>(model.groups.size()))
      throw Error(where + " is anchored on group " + std::to_string(st.anchor_group) + " of " +
                  std::to_string(model.groups.size()));
    if (st.anchor_group >= 0) {
      const KinematicGroup& g = model.groups[static_cast<size_t>(st.anchor_group)];
      if (!(g.axes[0] && g.axes[1] && g.axes[2]))
        throw Error(where + " is anchored on group '" + g.name + "', which leaves an axis free: an anchor needs a rigid group");
    }
    if (!(st.natural_length > 0.0) || !std::isfinite(st.natural_length) || !(st.k_t > 0.0) || !std::isfinite(st.k_t))
      throw Error(where + ": natural length and stiffness must be positive and finite");
    if (!st.anchor_rest.allFinite()) throw Error(where + ": the anchor is not finite");
    if (!(st.toe_strain >= 0.0 && st.toe_strain < 0.2))
      throw Error(where + ": the toe strain must lie in [0, 0.2), got " + std::to_string(st.toe_strain));
  }
  for (const Muscle& m : model.muscles) {
    const std::string where = "muscle '" + m.name + "'";
    if (!(m.unit_force >= 0.0) || !std::isfinite(m.unit_force)) throw Error(where + ": unit force must be >= 0 and finite");
    if (m.force_length.enabled && !(m.force_length.zero_at >= 0.0 && m.force_length.zero_at < 1.0))
      throw Error(where + ": the force-length relation's zero stretch must lie in [0, 1)");
    if (m.hill.enabled) check_hill_muscle(m.hill, where + ": hill");
    for (const ContractileUnit& u : m.units)
      if (!node_ok(u.a) || !node_ok(u.b) || u.a == u.b || !(u.rest_length > 0.0))
        throw Error(where + " has a unit (" + std::to_string(u.a) + ", " + std::to_string(u.b) +
                    ") that does not join two distinct nodes of the model with a positive rest length");
  }
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& jt = model.joints[j];
    const std::string where = "joint '" + jt.name + "'";
    if (jt.group < 0 || jt.group >= static_cast<int>(model.groups.size()))
      throw Error(where + " drives group " + std::to_string(jt.group) + " of " + std::to_string(model.groups.size()));
    KinematicGroup& g = model.groups[static_cast<size_t>(jt.group)];
    if (g.joint >= 0) throw Error(where + ": group '" + g.name + "' is driven by another joint already");
    if (!(g.axes[0] && g.axes[1] && g.axes[2]))
      throw Error(where + ": group '" + g.name + "' must prescribe all three axes to turn rigidly");
    check_hinge(jt.hinge);
    if (std::abs(jt.hinge.axis.norm() - 1.0) > 1e-12) throw Error(where + ": the axis must be a unit vector");
    if (!(jt.damping >= 0.0) || !(jt.limit_stiffness >= 0.0) || !(jt.passive_lo <= jt.passive_hi) ||
        !(jt.body.mass >= 0.0))
      throw Error(where + ": damping, limit stiffness and body mass must be >= 0, passive_lo <= passive_hi");
    g.joint = static_cast<int>(j);
  }
  for (const Joint& jt : model.joints) {
    if (jt.parent < 0) continue;
    const std::string where = "joint '" + jt.name + "'";
    if (jt.parent >= static_cast<int>(model.groups.size()) || jt.parent == jt.group)
      throw Error(where + ": its parent must be another of the " + std::to_string(model.groups.size()) + " groups, got " +
                  std::to_string(jt.parent));
    const KinematicGroup& p = model.groups[static_cast<size_t>(jt.parent)];
    if (p.joint >= 0) throw Error(where + ": its parent '" + p.name + "' is turned by a joint itself (chains are not supported)");
    if (!(p.axes[0] && p.axes[1] && p.axes[2]))
      throw Error(where + ": its parent '" + p.name + "' must prescribe all three axes to carry a hinge");
  }
  for (const RigidObstacle& ob : model.obstacles)
    for (int node : ob.nodes)
      if (!node_ok(node) || model.kinematic[static_cast<size_t>(node)])
        throw Error("obstacle '" + ob.name + "' is tested against node " + std::to_string(node) +
                    ", which is out of range or in a kinematic group");
  if (model.self_contact && model.contact_tets.empty()) {
    model.contact_tets.reserve(model.elements.size());
    for (const Element& e : model.elements) model.contact_tets.push_back(e.nodes);
  }
}

State rest_state(const Model& model) {
  State s;
  s.x = model.rest_positions;
  s.v = Points::Zero(3, model.num_nodes());
  s.a = Points::Zero(3, model.num_nodes());
  s.joints.assign(model.joints.size(), HingeState{});
  return s;
}

}  // namespace msd
