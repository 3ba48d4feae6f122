#include "msd/experiments/rig.hpp"

#include "msd/experiments/blowup.hpp"
#include "msd/forces/element_forces.hpp"
#include "msd/io/interrupt.hpp"

#include <cmath>
#include <set>

namespace msd {

Face parse_face(const std::string& name) {
  const char* names[] = {"left", "right", "front", "back", "bottom", "top"};
  for (int i = 0; i < 6; ++i)
    if (name == names[i]) return static_cast<Face>(i);
  throw Error("unknown face '" + name + "' (expected left, right, front, back, bottom or top)");
}

std::string to_string(Face face) {
  const char* names[] = {"left", "right", "front", "back", "bottom", "top"};
  return names[static_cast<int>(face)];
}

std::vector<int> face_nodes(const TetMesh& mesh, Face face) {
  const int axis = static_cast<int>(face) / 2;
  const bool max_side = static_cast<int>(face) % 2 == 1;
  const Vec3 lo = mesh.nodes.rowwise().minCoeff(), hi = mesh.nodes.rowwise().maxCoeff();
  const double tol = 1e-9 * (hi - lo).maxCoeff();
  const double plane = max_side ? hi[axis] : lo[axis];
  std::vector<int> nodes;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (std::abs(mesh.nodes(axis, n) - plane) <= tol) nodes.push_back(n);
  return nodes;
}

namespace {

template <typename F>
void for_face_triangles(const TetMesh& mesh, const std::vector<int>& nodes, F&& f) {
  std::vector<char> in(static_cast<size_t>(mesh.num_nodes()), 0);
  for (int n : nodes) in[static_cast<size_t>(n)] = 1;
  for (const Tri& t : boundary_faces(mesh.tets))
    if (in[static_cast<size_t>(t[0])] && in[static_cast<size_t>(t[1])] && in[static_cast<size_t>(t[2])]) {
      const Vec3 a = mesh.nodes.col(t[0]), b = mesh.nodes.col(t[1]), c = mesh.nodes.col(t[2]);
      f(t, 0.5 * (b - a).cross(c - a).norm());
    }
}

}  // namespace

double face_area(const TetMesh& mesh, const std::vector<int>& nodes) {
  double area = 0.0;
  for_face_triangles(mesh, nodes, [&](const Tri&, double a) { area += a; });
  return area;
}

Points face_load(const TetMesh& mesh, const std::vector<int>& nodes, const Vec3& total_force) {
  const double area = face_area(mesh, nodes);
  if (!(area > 0.0)) throw Error("face_load: the face has no boundary triangles");
  Points f = Points::Zero(3, mesh.num_nodes());
  for_face_triangles(mesh, nodes, [&](const Tri& t, double a) {
    for (int k = 0; k < 3; ++k) f.col(t[k]) += (a / area / 3.0) * total_force;
  });
  return f;
}

int nearest_node(const Points& x, const Vec3& p) {
  Eigen::Index best = 0;
  (x.colwise() - p).colwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

ElementVolumes element_volumes(const Model& model, const Points& x) {
  ElementVolumes r;
  for (const Element& el : model.elements) {
    const double ve = tet_signed_volume(x, el.nodes);
    r.volume += ve;
    r.inverted += ve <= 0.0;
  }
  return r;
}

BulkSample measure_bulk(const Model& model, const State& state, double rest_volume) {
  const ElementVolumes ev = element_volumes(model, state.x);
  BulkSample b;
  b.volume_ratio = ev.volume / rest_volume;
  b.inverted_elements = ev.inverted;
  b.kinetic_energy = kinetic_energy(model, state.v);
  return b;
}

Vec3 applied_force(const Model& model, const Scratch& scratch, double load_scale, int node) {
  Vec3 f = scratch.f.col(node);
  if (model.external_force.cols() == model.num_nodes()) f += load_scale * model.external_force.col(node);
  if (model.terms & kGravity) f += load_scale * model.mass[node] * model.gravity;
  return f;
}

RunStats run_experiment(const Model& model, State state, double end_time, double size,
                        const TimeSteppingOptions& opt, const ExperimentHooks& hooks, const LoopPosition* resume) {
  if (!(opt.dt > 0.0) || !std::isfinite(opt.dt)) throw Error("time step dt must be positive");
  if (!(opt.output_interval > 0.0)) throw Error("output interval must be positive");
  Scratch scratch;
  if (!resume) apply_constraints(model, hooks.controls(0.0), state);
  RunStats stats;
  const long total_steps = static_cast<long>(std::ceil(end_time / opt.dt - 1e-9));
  BlowUpLimits limits(model, size, opt.blowup_factor);
  long output_index = resume ? resume->outputs : 0;
  double next_output = output_index * opt.output_interval;
  const long first = resume ? resume->step : 0;
  if (resume) stats.steps = first;
  for (long k = first;; ++k) {
    const double t = k * opt.dt;
    state.t = t;  // avoid drift from repeated addition
    throw_if_interrupted(t, state.step);
    if ((t >= next_output - 1e-12 * opt.dt || k == total_steps) && !(resume && k == first)) {
      limits.see_load_speed(load_speed(hooks.controls(t)));
      limits.check(model, state);
      if (!hooks.sample(state, scratch)) break;
      ++output_index;
      next_output = output_index * opt.output_interval;
      if (hooks.after_sample) hooks.after_sample(state, k, output_index);
    }
    if (k == total_steps) break;
    step(model, state, hooks.controls((k + 1) * opt.dt), opt.dt, opt.integrator, scratch);
    ++stats.steps;
    stats.newton_iterations = scratch.newton_iterations;
    stats.step_cuts = scratch.step_cuts;
    stats.factorizations = scratch.factorizations;
  }
  stats.simulated_seconds = state.t;
  return stats;
}

}  // namespace msd
