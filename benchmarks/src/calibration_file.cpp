// Reading a calibration file (the YAML `tissuebench calibrate` writes) and
// applying it to a spec's msd section. Apart from the fit (calibration.cpp)
// because spec reading needs it and builds without the FEM (the sanitizer and
// fuzz builds: docs/fuzzing.md).
#include "bench/calibration.hpp"

#include "msd/core/types.hpp"

#include <yaml-cpp/yaml.h>

namespace bench {

CalibrationParameters read_calibration(const std::string& path, std::string* material) {
  YAML::Node n;
  try {
    n = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw msd::Error(path + ": cannot read the calibration file: " + e.msg);
  }
  // A file that is not a mapping, or a field of the wrong shape, is refused
  // like a missing field (never a yaml-cpp exception: tests/fuzz/regressions/calibration/).
  if (!n.IsMap()) throw msd::Error(path + ": the calibration file must be a YAML mapping");
  if (material) {
    const YAML::Node m = n["material"];
    if (m && !m.IsScalar()) throw msd::Error(path + ": 'material' must be a name");
    *material = m ? m.Scalar() : "";
  }
  const YAML::Node p = n["parameters"];
  if (!p) throw msd::Error(path + ": no 'parameters' in the calibration file");
  if (!p.IsMap()) throw msd::Error(path + ": 'parameters' must be a mapping");
  CalibrationParameters c;
  try {
    c.stiffness_scale = p["stiffness_scale"].as<double>();
    c.repulsion_factor = p["repulsion_factor"].as<double>();
    c.volume_factor = p["volume_factor"].as<double>();
    if (p["damping_time"]) c.damping_time = p["damping_time"].as<double>();
  } catch (const YAML::Exception& e) {
    throw msd::Error(path + ": parameters.stiffness_scale, repulsion_factor and volume_factor are required: " +
                     e.msg);
  }
  if (!(c.stiffness_scale > 0.0) || c.repulsion_factor < 0.0 || c.volume_factor < 0.0 ||
      (c.damping_time && !(*c.damping_time >= 0.0)))
    throw msd::Error(path + ": calibrated parameters out of range");
  return c;
}

void apply_calibration(Spec& spec, const std::string& file, const std::string& where) {
  if (!spec.msd || spec.msd->constants != "physical")
    throw msd::Error(where + file + ": a calibration applies to 'msd.constants: physical'");
  std::string material;
  CalibrationParameters c;
  try {
    c = read_calibration(file, &material);
  } catch (const msd::Error& e) {
    throw msd::Error(where + e.what());
  }
  if (!material.empty() && material != spec.material.name)
    throw msd::Error(where + file + ": calibrated for material '" + material + "', but the spec's material is '" +
                     (spec.material.name.empty() ? std::string("(unnamed)") : spec.material.name) + "'");
  spec.msd->stiffness_scale = c.stiffness_scale;
  spec.msd->repulsion_factor = c.repulsion_factor;
  spec.msd->volume_factor = c.volume_factor;
  spec.msd->damping_time = c.damping_time;
  spec.msd->calibration = file;
}

}  // namespace bench
