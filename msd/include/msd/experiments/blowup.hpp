// The blow-up detector shared by every run (the benchmarks' rig, CVODE and
// the leg): a state is a blow-up when it is physically impossible for the
// scene, not only when it is no longer finite. Three limits, each with the
// measured value in its message:
//
//   displacement  max_n |x_n - X_n|  >  blowup_factor * size
//   speed         max_n |v_n|        >  10 v_ref
//   energy        sum_n m_n |v_n|^2 / 2  >  M v_ref^2 / 2   (M: total mass)
//
// (A time step too large for the loading is refused before the run: a spec's
// msd.dt and a scene's dt must leave at least ten steps over the run.)
//
// with the reference speed v_ref = c + v_load + sqrt(2 g size):
//   c       the fastest wave the lattice carries, max over edges of
//           L0 sqrt(k_s / min(m_a, m_b)) (a spring chain's wave speed);
//   v_load  the fastest prescribed motion seen so far (platens, obstacles,
//           bones), m/s;
//   sqrt(2 g size)  the speed of a free fall across the sample.
// A strain wave moves material at most about strain x c, a platen at v_load
// and gravity at the free-fall speed, so a physical run stays well inside:
// the energy limit allows the whole body to move at v_ref, one node ten times
// that.
#pragma once

#include "msd/model/model.hpp"
#include "msd/skeleton/rigid_motion.hpp"

namespace msd {

/// c above (m/s): 0 for a model without springs.
double lattice_wave_speed(const Model& model);

struct BlowUpLimits {
  double max_displacement = 0.0;  ///< m
  double wave_speed = 0.0;        ///< c, m/s
  double free_fall_speed = 0.0;   ///< sqrt(2 g size), m/s
  double total_mass = 0.0;        ///< kg
  double load_speed = 0.0;        ///< v_load so far, m/s (raise with see_load_speed)

  /// Limits for `model`, a sample of extent `size` (m), displacement limit
  /// blowup_factor * size.
  BlowUpLimits(const Model& model, double size, double blowup_factor);
  BlowUpLimits() = default;

  void see_load_speed(double v) { load_speed = std::max(load_speed, v); }
  double reference_speed() const { return wave_speed + load_speed + free_fall_speed; }

  /// Throws SimulationFailure (time, step, node; the measured value against
  /// its limit) when `state` breaks a limit. With `carried` (a scripted bone
  /// carrying the body, e.g. the leg's femur): displacements from the rest
  /// pose carried by it, x - (R X + d), not from rest.
  void check(const Model& model, const State& state, const RigidMotion* carried = nullptr) const;
};

/// The fastest prescribed speed in `controls` (groups and obstacles), m/s.
double load_speed(const Controls& controls);

}  // namespace msd
