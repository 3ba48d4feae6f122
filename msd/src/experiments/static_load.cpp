#include "msd/experiments/static_load.hpp"

#include "msd/forces/element_forces.hpp"

#include <cmath>

namespace msd {

ClampSetup add_clamp(const TetMesh& mesh, Face face, ModelOptions& options) {
  ClampSetup s;
  KinematicGroup g{"clamp (" + to_string(face) + ")", face_nodes(mesh, face), {true, true, true}};
  if (g.nodes.empty()) throw Error("clamp: no nodes on the " + to_string(face) + " face");
  s.clamp_group = static_cast<int>(options.groups.size());
  options.groups.push_back(g);
  const Vec3 lo = mesh.nodes.rowwise().minCoeff(), hi = mesh.nodes.rowwise().maxCoeff();
  s.size = (hi - lo).maxCoeff();
  s.volume = total_volume(mesh.nodes, mesh.tets);
  Vec3 probe = 0.5 * (lo + hi);
  const int axis = static_cast<int>(face) / 2;
  probe[axis] = static_cast<int>(face) % 2 == 0 ? hi[axis] : lo[axis];
  s.probe_node = nearest_node(mesh.nodes, probe);
  return s;
}

Controls clamp_controls(const Model& model, const LoadingPath& load_factor, double t) {
  Controls c;
  c.group_offset.assign(model.groups.size(), Vec3::Zero());
  c.group_velocity.assign(model.groups.size(), Vec3::Zero());
  c.load_scale = load_factor.value(t);
  return c;
}

ClampSample measure_clamp(const Model& model, const ClampSetup& setup, const LoadingPath& load_factor,
                          const State& state, Scratch& scratch) {
  evaluate_forces(model, state, scratch);
  ClampSample s;
  s.time = state.t;
  s.load_factor = load_factor.value(state.t);
  s.probe_displacement = state.x.col(setup.probe_node) - model.rest_positions.col(setup.probe_node);
  for (int n : model.groups.at(static_cast<size_t>(setup.clamp_group)).nodes)
    s.reaction -= applied_force(model, scratch, s.load_factor, n);
  const BulkSample bulk = measure_bulk(model, state, setup.volume);
  s.volume_ratio = bulk.volume_ratio;
  s.inverted_elements = bulk.inverted_elements;
  s.kinetic_energy = bulk.kinetic_energy;
  return s;
}

State displaced_state(const Model& model, bool first_mode, double amplitude) {
  State s = rest_state(model);
  const double z0 = model.rest_positions.row(2).minCoeff(), z1 = model.rest_positions.row(2).maxCoeff();
  const double L = z1 - z0;
  for (int n = 0; n < model.num_nodes(); ++n) {
    const double Z = model.rest_positions(2, n) - z0;
    s.x(2, n) += first_mode ? amplitude * 2.0 * L / M_PI * std::sin(M_PI * Z / (2.0 * L)) : amplitude * Z;
  }
  return s;
}

}  // namespace msd
