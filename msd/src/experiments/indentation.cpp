#include "msd/experiments/indentation.hpp"

#include "msd/forces/element_forces.hpp"
#include "msd/integrate/step.hpp"

#include <cmath>

namespace msd {

IndentationSetup add_indenter(const TetMesh& mesh, const IndenterOptions& indenter, ModelOptions& options) {
  if (indenter.axis != 0 && indenter.axis != 1)
    throw Error("indenter: the cylinder's axis must be horizontal (x or y)");
  if (!(indenter.radius > 0.0)) throw Error("indenter: radius must be positive");
  if (!(indenter.max_depth > 0.0)) throw Error("indenter: depth must be positive");
  IndentationSetup s;
  const Vec3 lo = mesh.nodes.rowwise().minCoeff(), hi = mesh.nodes.rowwise().maxCoeff();
  s.height = hi.z() - lo.z();
  if (indenter.max_depth >= s.height) throw Error("indenter: depth must be less than the block's height");
  s.max_depth = indenter.max_depth;
  s.volume = total_volume(mesh.nodes, mesh.tets);
  KinematicGroup base{"clamp (bottom)", face_nodes(mesh, Face::Bottom), {true, true, true}};
  if (base.nodes.empty()) throw Error("indenter: no nodes on the bottom face");
  s.clamp_group = static_cast<int>(options.groups.size());
  options.groups.push_back(base);
  RigidObstacle ob;
  ob.name = "indenter";
  ob.response = indenter.response;
  ob.cylinder.radius = indenter.radius;
  ob.cylinder.axis = indenter.axis == 0 ? Vec3::UnitX() : Vec3::UnitY();
  ob.cylinder.point = 0.5 * (lo + hi);
  ob.cylinder.point.z() = hi.z() + indenter.radius;
  ob.nodes = face_nodes(mesh, Face::Top);
  s.obstacle = static_cast<int>(options.obstacles.size());
  options.obstacles.push_back(ob);
  return s;
}

Controls indentation_controls(const Model& model, const IndentationSetup& setup, const LoadingPath& path, double t) {
  Controls c;
  c.group_offset.assign(model.groups.size(), Vec3::Zero());
  c.group_velocity.assign(model.groups.size(), Vec3::Zero());
  c.obstacle_offset.assign(model.obstacles.size(), Vec3::Zero());
  c.obstacle_velocity.assign(model.obstacles.size(), Vec3::Zero());
  c.obstacle_offset[static_cast<size_t>(setup.obstacle)] = Vec3(0, 0, -setup.max_depth * path.value(t));
  c.obstacle_velocity[static_cast<size_t>(setup.obstacle)] = Vec3(0, 0, -setup.max_depth * path.rate(t));
  return c;
}

IndentationSample measure_indentation(const Model& model, const IndentationSetup& setup, const LoadingPath& path,
                                      const State& state, Scratch& scratch) {
  evaluate_forces(model, state, scratch);
  IndentationSample s;
  s.time = state.t;
  s.depth = setup.max_depth * path.value(state.t);
  const RigidObstacle& ob = model.obstacles.at(static_cast<size_t>(setup.obstacle));
  const Vec3 offset(0, 0, -s.depth), e(0, 0, -1);
  // Gravity and dead loads, if a scene adds them, stay at full scale: the
  // path drives the indenter, not the loads.
  auto applied = [&](int n) { return applied_force(model, scratch, 1.0, n); };
  for (int n : ob.nodes) {
    const CylinderGap g = cylinder_gap(ob.cylinder, offset, state.x.col(n));
    if (g.depth < -1e-9 * ob.cylinder.radius) continue;
    const double lambda = std::max(0.0, -applied(n).dot(g.normal));
    if (lambda > 0.0) ++s.contact_nodes;
    s.force += lambda * g.normal.dot(e);
  }
  for (int n : model.groups.at(static_cast<size_t>(setup.clamp_group)).nodes) s.base_reaction -= applied(n).z();
  const BulkSample bulk = measure_bulk(model, state, setup.volume);
  s.volume_ratio = bulk.volume_ratio;
  s.inverted_elements = bulk.inverted_elements;
  s.kinetic_energy = bulk.kinetic_energy;
  return s;
}

}  // namespace msd
