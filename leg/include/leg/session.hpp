// A scene compiled once: its limb input read and checked, the limb meshed, the
// leg model built, and the instruments that observe it. `tissuebench leg`
// runs every variant of it (leg/run.hpp); `tissuebench serve` steps it live
// (leg/live.hpp).
#pragma once

#include "leg/limb_input.hpp"
#include "leg/scene.hpp"
#include "leg/sensors.hpp"

#include "msd/scene/leg_model.hpp"

namespace leg {

/// The meshed limb and the leg compiled from it, for every variant of a scene.
struct CompiledLeg {
  LimbInput input;
  MeshedLimb limb;
  msd::LegModel model;
};

/// Reads the scene's limb, meshes it and builds the leg. Throws msd::Error
/// naming the file for bad geometry or an unphysical constant.
CompiledLeg compile_leg(const LegScene& scene);

/// The leg at the scene's start: at rest, the knee at its initial angle and
/// velocity, the lower bone's nodes placed by the hinge.
msd::LegState start_state(const msd::LegModel& leg, const LegScene& scene);

/// The instruments of `c` (leg/sensors.hpp), with the limb's bone surfaces.
/// Refers to `c` and `scene`: both must outlive it.
Instruments make_leg_instruments(const CompiledLeg& c, const LegScene& scene);

}  // namespace leg
