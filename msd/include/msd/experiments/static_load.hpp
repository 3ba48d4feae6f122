// A sample clamped on one face and loaded by dead loads - a traction spread over
// another face and/or gravity - scaled by a load factor that follows a path
// (cantilever bending, a hanging bar). With dampers, a slow ramp and a hold the
// dynamics settle to the static response. Measured: the displacement of a probe
// node (nearest the centre of the face opposite the clamped one) and the
// reaction on the clamped face, -(internal + external forces on its nodes).
#pragma once

#include "msd/experiments/loading_path.hpp"
#include "msd/experiments/rig.hpp"

namespace msd {

struct ClampSetup {
  int clamp_group = -1;
  int probe_node = -1;
  double size = 0.0;    ///< largest side of the sample's bounding box, m
  double volume = 0.0;  ///< rest volume, m^3
};

/// Clamps the nodes of `face` (a kinematic group with zero motion, appended to
/// options.groups) and picks the probe node.
ClampSetup add_clamp(const TetMesh& mesh, Face face, ModelOptions& options);

/// No prescribed motion; load factor = path(t).
Controls clamp_controls(const Model& model, const LoadingPath& load_factor, double t);

struct ClampSample {
  double time = 0.0;
  double load_factor = 0.0;
  Vec3 probe_displacement{Vec3::Zero()};
  Vec3 reaction{Vec3::Zero()};
  double volume_ratio = 1.0;
  int inverted_elements = 0;
  double kinetic_energy = 0.0;
};

ClampSample measure_clamp(const Model& model, const ClampSetup& setup, const LoadingPath& load_factor,
                          const State& state, Scratch& scratch);

/// The rest state displaced by an axial field along z measured from the lowest
/// node plane, for free-vibration tests: u_z = a Z (stretch) or
/// u_z = a (2L/pi) sin(pi Z / 2L) (first mode of a fixed-free bar).
State displaced_state(const Model& model, bool first_mode, double amplitude);

}  // namespace msd
