// Reading a calibration file (the YAML `tissuebench calibrate` writes) and
// applying it to a spec's msd section. Apart from the fit (calibration.cpp)
// because spec reading needs it and builds without the FEM (the sanitizer and
// fuzz builds: docs/fuzzing.md).
#include "bench/calibration.hpp"
#include "bench/shared_io.hpp"

#include "msd/core/types.hpp"

#include <yaml-cpp/yaml.h>

namespace bench {

CalibrationParameters read_calibration(const std::string& path, std::string* material) {
  // Every field is known (an unknown one is a typo or a file of another
  // program): the fitted parameters are checked for range, the provenance
  // sections only for their presence as written by write_calibration.
  const tbio::Fields f(load_yaml_file(path, "calibration file"), "", path);
  f.only({"material", "parameters", "material_damping_time", "starting_parameters", "volume_weight", "objective", "optimiser",
          "damping_stage", "specs", "checked_on", "reference", "created"});
  if (material) *material = f.text_or("material", "");
  const tbio::Fields p = f.section("parameters");
  p.only({"stiffness_scale", "repulsion_factor", "volume_factor", "damping_time", "axis_stiffness",
          "compression_exponent"});
  CalibrationParameters c;
  c.stiffness_scale = p.positive("stiffness_scale");
  auto non_negative = [&](const std::string& key) {
    const double v = p.number(key);  // required, finite
    if (v < 0.0) throw msd::Error(p.where(key) + "must be a number >= 0");
    return v;
  };
  c.repulsion_factor = non_negative("repulsion_factor");
  c.volume_factor = non_negative("volume_factor");
  if (p.has("damping_time")) c.damping_time = p.non_negative_or("damping_time", 0.0);
  if (p.has("axis_stiffness") != p.has("compression_exponent"))
    throw msd::Error(p.where(p.has("axis_stiffness") ? "axis_stiffness" : "compression_exponent") +
                     "the edge classes' axis_stiffness and compression_exponent come together");
  if (p.has("axis_stiffness")) {
    c.axis_stiffness = p.positive("axis_stiffness");
    c.compression_exponent = non_negative("compression_exponent");
  }
  if (auto s = f.optional_section("starting_parameters"))
    s->only({"stiffness_scale", "repulsion_factor", "volume_factor", "damping_time", "axis_stiffness",
             "compression_exponent"});
  return c;
}

void apply_edge_classes(MsdSpec& msd, const CalibrationParameters& p) {
  if (p.axis_stiffness) msd.edge_laws[static_cast<size_t>(msd::EdgeClass::axis)].stiffness = *p.axis_stiffness;
  if (p.compression_exponent)
    for (msd::EdgeClass c : {msd::EdgeClass::axis, msd::EdgeClass::face_diagonal}) {
      msd::SpringLaw& law = msd.edge_laws[static_cast<size_t>(c)];
      law.tension_exponent = 1.0;
      law.compression_exponent = *p.compression_exponent;
    }
}

void apply_calibration(Spec& spec, const std::string& file, const std::string& where) {
  if (!spec.msd || spec.msd->constants != "physical")
    throw msd::Error(where + file + ": a calibration applies to 'msd.constants: physical'");
  if (spec.msd->zero_length_springs)
    throw msd::Error(where + file + ": the calibrations fit the thesis' springs; msd.zero_length_springs takes every "
                     "constant from E and nu (no calibration for it is shipped)");
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
  apply_edge_classes(*spec.msd, c);
  spec.msd->calibration = file;
}

}  // namespace bench
