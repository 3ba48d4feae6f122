#include "msd/experiments/blowup.hpp"

#include "msd/integrate/step.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace msd {

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

}  // namespace

double lattice_wave_speed(const Model& model) {
  const ForcePlan& p = model.plan;
  double c = 0.0;
  for (int e = 0; e < p.num_edges(); ++e) {
    const double m = std::min(model.mass[p.edge_a[static_cast<size_t>(e)]], model.mass[p.edge_b[static_cast<size_t>(e)]]);
    const double k = p.edge_k_s[static_cast<size_t>(e)];
    // The edge's length at rest (not the spring's rest length, 0 for zero-length springs).
    const double length = (model.rest_positions.col(p.edge_b[static_cast<size_t>(e)]) -
                           model.rest_positions.col(p.edge_a[static_cast<size_t>(e)])).norm();
    if (m > 0.0 && k > 0.0) c = std::max(c, length * std::sqrt(k / m));
  }
  return c;
}

BlowUpLimits::BlowUpLimits(const Model& model, double size, double blowup_factor)
    : max_displacement(blowup_factor * size),
      wave_speed(lattice_wave_speed(model)),
      free_fall_speed(std::sqrt(2.0 * model.gravity.norm() * size)),
      total_mass(model.mass.sum()) {}

double load_speed(const Controls& controls) {
  double v = 0.0;
  for (const Vec3& g : controls.group_velocity) v = std::max(v, g.norm());
  for (const Vec3& o : controls.obstacle_velocity) v = std::max(v, o.norm());
  return v;
}

void BlowUpLimits::check(const Model& model, const State& state, const RigidMotion* carried) const {
  Eigen::Index far = 0;
  double d = 0.0;
  if (carried) {
    for (Eigen::Index i = 0; i < state.x.cols(); ++i) {
      const double di = (Vec3(state.x.col(i)) - carried->place(model.rest_positions.col(i))).norm();
      if (di > d) {
        d = di;
        far = i;
      }
    }
  } else {
    d = (state.x - model.rest_positions).colwise().norm().maxCoeff(&far);
  }
  if (d > max_displacement)
    throw SimulationFailure("blow-up: node " + std::to_string(far) + " moved " + num(d) + " m from " +
                                (carried ? "its carried rest place" : "rest") + ", more than the limit " +
                                num(max_displacement) + " m (" + num(d / max_displacement) + " times the limit)",
                            state.t, state.step, -1, static_cast<int>(far));
  if (state.v.cols() == 0) return;
  Eigen::Index fast = 0;
  const double v = state.v.colwise().norm().maxCoeff(&fast);
  const double v_ref = reference_speed();
  if (v > 10.0 * v_ref)
    throw SimulationFailure("blow-up: node " + std::to_string(fast) + " moves at " + num(v) +
                                " m/s, more than ten times the scene's reference speed " + num(v_ref) +
                                " m/s (lattice wave " + num(wave_speed) + " + loading " + num(load_speed) +
                                " + free fall " + num(free_fall_speed) + ")",
                            state.t, state.step, -1, static_cast<int>(fast));
  const double ke = 0.5 * (state.v.colwise().squaredNorm().transpose().array() * model.mass.array()).sum();
  const double ke_limit = 0.5 * total_mass * v_ref * v_ref;
  if (ke > ke_limit)
    throw SimulationFailure("blow-up: kinetic energy " + num(ke) + " J, more than the whole body (" + num(total_mass) +
                                " kg) moving at the reference speed " + num(v_ref) + " m/s (" + num(ke_limit) + " J)",
                            state.t, state.step, -1, static_cast<int>(fast));
}

}  // namespace msd
