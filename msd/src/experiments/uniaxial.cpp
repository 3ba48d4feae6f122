#include "msd/experiments/uniaxial.hpp"

#include "msd/forces/element_forces.hpp"

#include <cmath>

namespace msd {

PlatenContact parse_platen_contact(const std::string& name) {
  if (name == "bonded") return PlatenContact::Bonded;
  if (name == "frictionless") return PlatenContact::Frictionless;
  throw Error("unknown platen contact '" + name + "' (expected bonded or frictionless)");
}

UniaxialSetup add_platens(const TetMesh& mesh, PlatenContact contact, ModelOptions& options) {
  const double zmin = mesh.nodes.row(2).minCoeff(), zmax = mesh.nodes.row(2).maxCoeff();
  const double tol = 1e-9 * (zmax - zmin);
  KinematicGroup bottom{"bottom platen", {}, {true, true, true}};
  KinematicGroup top{"top platen", {}, {true, true, true}};
  if (contact == PlatenContact::Frictionless) {
    bottom.axes[0] = bottom.axes[1] = false;
    top.axes[0] = top.axes[1] = false;
  }
  std::vector<char> on_top(static_cast<size_t>(mesh.num_nodes()), 0);
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (mesh.nodes(2, n) <= zmin + tol) bottom.nodes.push_back(n);
    if (mesh.nodes(2, n) >= zmax - tol) {
      top.nodes.push_back(n);
      on_top[static_cast<size_t>(n)] = 1;
    }
  }
  if (bottom.nodes.empty() || top.nodes.empty() || !(zmax > zmin))
    throw Error("uni-axial test: the sample has no distinct top and bottom faces");
  UniaxialSetup s;
  s.length = zmax - zmin;
  s.volume = total_volume(mesh.nodes, mesh.tets);
  for (const Tri& f : boundary_faces(mesh.tets))
    if (on_top[static_cast<size_t>(f[0])] && on_top[static_cast<size_t>(f[1])] &&
        on_top[static_cast<size_t>(f[2])]) {
      const Vec3 a = mesh.nodes.col(f[0]), b = mesh.nodes.col(f[1]), c = mesh.nodes.col(f[2]);
      s.area += 0.5 * (b - a).cross(c - a).norm();
    }
  s.bottom_group = static_cast<int>(options.groups.size());
  options.groups.push_back(bottom);
  s.top_group = static_cast<int>(options.groups.size());
  options.groups.push_back(top);
  return s;
}

Controls uniaxial_controls(const Model& model, const UniaxialSetup& setup, const LoadingPath& path,
                           double t) {
  Controls c;
  c.group_offset.assign(model.groups.size(), Vec3::Zero());
  c.group_velocity.assign(model.groups.size(), Vec3::Zero());
  c.group_offset[static_cast<size_t>(setup.top_group)] = Vec3(0, 0, path.value(t) * setup.length);
  c.group_velocity[static_cast<size_t>(setup.top_group)] = Vec3(0, 0, path.rate(t) * setup.length);
  return c;
}

UniaxialSample measure_uniaxial(const Model& model, const UniaxialSetup& setup, const State& state,
                                Scratch& scratch) {
  evaluate_forces(model, state, scratch);
  const KinematicGroup& top = model.groups.at(static_cast<size_t>(setup.top_group));
  const KinematicGroup& bottom = model.groups.at(static_cast<size_t>(setup.bottom_group));
  Vec3 f = Vec3::Zero();
  for (int n : top.nodes) f += scratch.f.col(n);
  double ztop = 0.0, zbot = 0.0;
  for (int n : top.nodes) ztop += state.x(2, n);
  for (int n : bottom.nodes) zbot += state.x(2, n);
  ztop /= static_cast<double>(top.nodes.size());
  zbot /= static_cast<double>(bottom.nodes.size());
  UniaxialSample s;
  s.time = state.t;
  s.strain = (ztop - zbot - setup.length) / setup.length;
  s.nominal_stress = -f.z() / setup.area;
  s.lateral_force = std::hypot(f.x(), f.y());
  const BulkSample bulk = measure_bulk(model, state, setup.volume);
  s.volume_ratio = bulk.volume_ratio;
  s.inverted_elements = bulk.inverted_elements;
  s.kinetic_energy = bulk.kinetic_energy;
  s.nonlinear_active = scratch.nonlinear_active;
  return s;
}

RunStats run_uniaxial(const Model& model, const UniaxialSetup& setup, const LoadingPath& path,
                      const TimeSteppingOptions& opt,
                      const std::function<bool(const UniaxialSample&, const State&)>& on_sample) {
  ExperimentHooks hooks;
  hooks.controls = [&](double t) { return uniaxial_controls(model, setup, path, t); };
  hooks.sample = [&](const State& state, Scratch& scratch) {
    return on_sample(measure_uniaxial(model, setup, state, scratch), state);
  };
  return run_experiment(model, rest_state(model), path.end_time(), setup.length, opt, hooks);
}

}  // namespace msd
