#include "msd/forces/parts.hpp"

#include "msd/forces/muscle_units.hpp"
#include "msd/forces/skin_membrane.hpp"
#include "msd/forces/tendon.hpp"

#include <cmath>

namespace msd {

const RigidMotion* group_motion(const Controls& c, int group) {
  const size_t g = static_cast<size_t>(group);
  return group >= 0 && g < c.group_motion.size() && c.group_motion[g] ? &*c.group_motion[g] : nullptr;
}

const RigidMotion* joint_frame(const Model& model, const Controls& c, int joint) {
  return group_motion(c, model.joints[static_cast<size_t>(joint)].parent);
}

Vec3 group_point(const Model& model, int group, const Vec3& rest, const Points& x,
                 const std::vector<HingeState>& joints, const Controls& controls) {
  const KinematicGroup& g = model.groups[static_cast<size_t>(group)];
  if (g.joint >= 0) {
    const Hinge& h = model.joints[static_cast<size_t>(g.joint)].hinge;
    const Vec3 p = h.centre + hinge_rotation(h, joints[static_cast<size_t>(g.joint)].angle) * (rest - h.centre);
    const RigidMotion* frame = joint_frame(model, controls, g.joint);
    return frame ? frame->place(p) : p;
  }
  if (const RigidMotion* m = group_motion(controls, group)) return m->place(rest);
  if (g.nodes.empty()) return rest;
  const int first = g.nodes.front();
  return rest + (Vec3(x.col(first)) - Vec3(model.rest_positions.col(first)));
}

double strand_natural_length(const Model& model, size_t s, const Controls& c) {
  return s < c.strand_natural_length.size() ? c.strand_natural_length[s] : model.strands[s].natural_length;
}

namespace {
// (L - L0) / L0 when taut, else 0 (a slack strand of infinite L0 too).
double strain_of(double length, double l0) { return std::isfinite(l0) && length > l0 ? (length - l0) / l0 : 0.0; }
}  // namespace

void add_part_forces(const Model& model, const Points& x, const Points& v, const std::vector<HingeState>& joints,
                     const Controls& c, Scratch& scratch) {
  Points& f = scratch.f;
  const size_t ns = model.strands.size();
  if (scratch.strand_tension.size() != ns) scratch.strand_tension.resize(ns);
  if (scratch.strand_strain.size() != ns) scratch.strand_strain.resize(ns);
  if (scratch.anchor_force.size() != ns) scratch.anchor_force.resize(ns);
  for (size_t si = 0; si < ns; ++si) {
    const Strand& s = model.strands[si];
    const double l0 = strand_natural_length(model, si, c);
    scratch.anchor_force[si].setZero();
    if (s.anchor_group < 0) {
      scratch.strand_tension[si] = add_tendon_forces(x, s.nodes, l0, s.k_t, f, s.toe_strain);
      scratch.strand_strain[si] = strain_of(strand_length(x, s.nodes), l0);
      continue;
    }
    // With an anchor: the strand's points (nodes, then anchor) and their
    // forces in buffers, then onto the nodes.
    Points& p = scratch.strand_points;
    Points& fl = scratch.strand_forces;
    std::vector<int>& idx = scratch.strand_index;
    const Eigen::Index m = static_cast<Eigen::Index>(s.nodes.size()) + 1;
    // The buffers only grow (strands of different lengths share them).
    if (p.cols() < m) {
      p.resize(3, m);
      fl.resize(3, m);
    }
    for (size_t k = 0; k < s.nodes.size(); ++k) p.col(static_cast<Eigen::Index>(k)) = x.col(s.nodes[k]);
    p.col(m - 1) = group_point(model, s.anchor_group, s.anchor_rest, x, joints, c);
    if (idx.size() != static_cast<size_t>(m)) {
      idx.resize(static_cast<size_t>(m));
      for (size_t k = 0; k < idx.size(); ++k) idx[k] = static_cast<int>(k);
    }
    fl.leftCols(m).setZero();
    scratch.strand_tension[si] = add_tendon_forces(p, idx, l0, s.k_t, fl, s.toe_strain);
    scratch.strand_strain[si] = strain_of(strand_length(p, idx), l0);
    for (size_t k = 0; k < s.nodes.size(); ++k) f.col(s.nodes[k]) += fl.col(static_cast<Eigen::Index>(k));
    scratch.anchor_force[si] = fl.col(m - 1);
  }
  for (size_t mi = 0; mi < model.muscles.size(); ++mi) {
    const Muscle& mu = model.muscles[mi];
    const double a = mi < c.activation.size() ? c.activation[mi] : 0.0;
    if (mu.hill.enabled)
      add_hill_muscle_forces(x, v, mu.units, mu.unit_force, a, mu.hill, f);  // the passive element pulls at a = 0 too
    else if (a > 0.0)
      add_muscle_forces(x, mu.units, a * mu.unit_force, f, mu.force_length);
  }
  if (!model.skin.empty()) add_membrane_forces(model.skin, x, f, model.threads, scratch.skin_corner_force);
}

}  // namespace msd
