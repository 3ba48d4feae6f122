// The virtual uni-axial test (thesis 5.2.1, figure 5.3): the sample's top and
// bottom faces move with rigid platens; the bottom one is fixed and the top one
// follows a nominal-strain path. Measured, as in the thesis:
//   F  = reaction force on the top platen: minus the z-sum of the internal forces
//        on its nodes (positive in tension),
//   sigma = F / A0 (nominal stress; A0 = the rest area of the sample's top face),
//   eps   = (d - l0) / l0 (nominal strain; d = platen separation),
//   volume ratio = current total tet volume / rest total, and the number of
//   inverted tets.
#pragma once

#include "msd/experiments/loading_path.hpp"
#include "msd/experiments/rig.hpp"
#include "msd/integrate/step.hpp"
#include "msd/model/model.hpp"

#include <functional>

namespace msd {

/// Bonded: platen nodes follow the platen in x, y and z (the thesis' test).
/// Frictionless: only z is prescribed; nodes slide freely on the platen.
enum class PlatenContact { Bonded, Frictionless };
PlatenContact parse_platen_contact(const std::string& name);

struct UniaxialSetup {
  double length = 0.0;   ///< l0, m
  double area = 0.0;     ///< A0, m^2
  double volume = 0.0;   ///< V0, m^3
  int bottom_group = -1, top_group = -1;
};

/// Makes the bottom (lowest z) and top (highest z) node planes of `mesh` into
/// platen groups, appended to options.groups. Throws if either face is empty.
UniaxialSetup add_platens(const TetMesh& mesh, PlatenContact contact, ModelOptions& options);

/// Platen motion at time t: bottom fixed, top at z offset strain(t) l0.
Controls uniaxial_controls(const Model& model, const UniaxialSetup& setup,
                           const LoadingPath& path, double t);

struct UniaxialSample {
  double time = 0.0;
  double strain = 0.0;
  double nominal_stress = 0.0;   ///< Pa
  double volume_ratio = 1.0;
  int inverted_elements = 0;
  double lateral_force = 0.0;    ///< |(Fx, Fy)| on the top platen, N
  double kinetic_energy = 0.0;   ///< J
  long nonlinear_active = 0;     ///< elements whose non-linear terms ran
};

/// Measures the sample at `state` (evaluates the forces into scratch).
UniaxialSample measure_uniaxial(const Model& model, const UniaxialSetup& setup,
                                const State& state, Scratch& scratch);

/// Runs the test from rest to the end of `path`, calling `on_sample` at t = 0
/// and every output interval (and at the end); a false return stops the run.
/// Throws SimulationFailure on a non-finite value or a blow-up.
RunStats run_uniaxial(const Model& model, const UniaxialSetup& setup, const LoadingPath& path,
                      const TimeSteppingOptions& options,
                      const std::function<bool(const UniaxialSample&, const State&)>& on_sample);

}  // namespace msd
