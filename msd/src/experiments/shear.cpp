#include "msd/experiments/shear.hpp"

#include "msd/forces/element_forces.hpp"

namespace msd {

Controls shear_controls(const Model& model, const UniaxialSetup& setup, const LoadingPath& gamma, double t) {
  Controls c;
  c.group_offset.assign(model.groups.size(), Vec3::Zero());
  c.group_velocity.assign(model.groups.size(), Vec3::Zero());
  c.group_offset[static_cast<size_t>(setup.top_group)] = Vec3(gamma.value(t) * setup.length, 0, 0);
  c.group_velocity[static_cast<size_t>(setup.top_group)] = Vec3(gamma.rate(t) * setup.length, 0, 0);
  return c;
}

ShearSample measure_shear(const Model& model, const UniaxialSetup& setup, const State& state, Scratch& scratch) {
  evaluate_forces(model, state, scratch);
  const KinematicGroup& top = model.groups.at(static_cast<size_t>(setup.top_group));
  Vec3 f = Vec3::Zero();
  double offset = 0.0;
  for (int n : top.nodes) {
    f += scratch.f.col(n);
    offset += state.x(0, n) - model.rest_positions(0, n);
  }
  ShearSample s;
  s.time = state.t;
  s.shear_strain = offset / static_cast<double>(top.nodes.size()) / setup.length;
  s.shear_stress = -f.x() / setup.area;
  s.normal_stress = -f.z() / setup.area;
  const BulkSample bulk = measure_bulk(model, state, setup.volume);
  s.volume_ratio = bulk.volume_ratio;
  s.inverted_elements = bulk.inverted_elements;
  s.kinetic_energy = bulk.kinetic_energy;
  return s;
}

}  // namespace msd
