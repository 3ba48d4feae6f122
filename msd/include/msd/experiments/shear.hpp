// Simple shear between bonded platens (the thesis names shear tests as future
// work, 7.6): the sample's bottom face is held, its top face moves along x by
// gamma(t) H with the platen, the sides are free. Measured: the shear stress
// tau = -(sum of x internal forces on the top nodes) / A0, the normal stress
// (z, positive in tension) and the volume ratio.
#pragma once

#include "msd/experiments/uniaxial.hpp"

namespace msd {

/// Platens as for the uni-axial test (bonded); the top one moves along x.
Controls shear_controls(const Model& model, const UniaxialSetup& setup, const LoadingPath& gamma, double t);

struct ShearSample {
  double time = 0.0;
  double shear_strain = 0.0;   ///< platen offset / height
  double shear_stress = 0.0;   ///< Pa
  double normal_stress = 0.0;  ///< Pa, positive in tension
  double volume_ratio = 1.0;
  int inverted_elements = 0;
  double kinetic_energy = 0.0;
};

ShearSample measure_shear(const Model& model, const UniaxialSetup& setup, const State& state, Scratch& scratch);

}  // namespace msd
