// The suite's pieces: tier files (strict, errors named) and the MSD variants.
#include "bench/suite.hpp"
#include "bench/calibration.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace {

std::string error_of(const std::string& file) {
  try {
    bench::load_tier(file);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Suite, ShippedTiersLoadAndNameTheirSpecs) {
  for (const char* tier : {"quick", "full"}) {
    const bench::SuiteTier t = bench::load_tier(std::string(TISSUEBENCH_SUITES_DIR) + "/" + tier + ".yaml");
    EXPECT_EQ(t.name, tier);
    // The quick tier (CI's) runs the neo-Hookean lattice as its lattice rung;
    // the full one runs every lattice rung (the calibrated, the physical and
    // the neo-Hookean) for the whole ladder.
    const bool full = std::string(tier) == "full";
    std::vector<std::string> expected{"thesis", "physical", "calibrated"};
    if (full) expected.push_back("lattice");
    expected.push_back("continuum");
    if (full) expected.push_back("physical_lattice");
    expected.push_back("neo_lattice");
    EXPECT_EQ(t.variants, expected);
    EXPECT_GE(t.benchmarks.size(), 5u);
    ASSERT_FALSE(t.sweeps.empty());
    // The sweep holds both families' rungs, with the quasi-static points.
    EXPECT_TRUE(t.sweeps.front().quasi_static) << tier;
    EXPECT_NE(std::find(t.sweeps.front().terms.begin(), t.sweeps.front().terms.end(), "neo_lattice"),
              t.sweeps.front().terms.end()) << tier;
    EXPECT_FALSE(t.stability.empty());
    EXPECT_FALSE(t.verification.empty());
    bool indentation = false;
    for (const auto& b : t.benchmarks) {
      indentation = indentation || b.spec == "indentation.yaml";
      EXPECT_NO_THROW(bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/" + b.spec)) << b.spec;
    }
    EXPECT_TRUE(indentation) << tier;
  }
}

TEST(Suite, ASweepMayLeaveOutItsCvodePoints) {
  testing_support::TempDir d("suite");
  std::ofstream(d.file("t.yaml")) << "tier: x\nbenchmarks: [{spec: s.yaml}]\n"
                                     "sweeps: [{spec: s.yaml}, {spec: s.yaml, cvode: false, quasi_static: true}]\n";
  const bench::SuiteTier t = bench::load_tier(d.file("t.yaml"));
  ASSERT_EQ(t.sweeps.size(), 2u);
  EXPECT_TRUE(t.sweeps[0].cvode);  // the default: time errors need the CVODE point
  EXPECT_FALSE(t.sweeps[0].quasi_static);
  EXPECT_FALSE(t.sweeps[1].cvode);
  EXPECT_TRUE(t.sweeps[1].quasi_static);
}

TEST(Suite, BadTierFilesAreNamed) {
  testing_support::TempDir d("suite");
  std::ofstream(d.file("a.yaml")) << "tier: x\nbenchmarks: [{spec: s.yaml, spce: 2}]\n";
  EXPECT_NE(error_of(d.file("a.yaml")).find("benchmarks[0].spce: unknown field"), std::string::npos)
      << error_of(d.file("a.yaml"));
  std::ofstream(d.file("b.yaml")) << "tier: x\nvariants: [thesis, fancy]\nbenchmarks: [{spec: s.yaml}]\n";
  EXPECT_NE(error_of(d.file("b.yaml")).find("unknown variant 'fancy'"), std::string::npos);
  std::ofstream(d.file("c.yaml")) << "tier: x\n";
  EXPECT_NE(error_of(d.file("c.yaml")).find("lists no benchmarks"), std::string::npos);
  std::ofstream(d.file("d.yaml")) << "tier: x\nbenchmarks: [{spec: s.yaml}]\nsweeps: [{spec: s.yaml, cvode: maybe}]\n";
  EXPECT_NE(error_of(d.file("d.yaml")).find("sweeps[0].cvode: is true or false (got 'maybe')"), std::string::npos)
      << error_of(d.file("d.yaml"));
  EXPECT_NE(error_of(d.file("none.yaml")).find("cannot read"), std::string::npos);
}

TEST(Suite, VariantsSetTheThesisConstantsOrTheMaterialsCalibration) {
  const bench::Spec spec = bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/bending.yaml");
  const std::string cal = std::string(TISSUEBENCH_SUITES_DIR) + "/../calibration";
  const bench::Spec thesis = bench::suite_variant(spec, "thesis", cal);
  EXPECT_EQ(thesis.msd->constants, "raw");
  EXPECT_DOUBLE_EQ(thesis.msd->k_s, 10.75);
  EXPECT_DOUBLE_EQ(thesis.msd->k_d, 0.2);
  EXPECT_EQ(thesis.msd->integrator, "explicit_euler");
  EXPECT_EQ(thesis.msd->mass_lumping, "equal");
  // bending.yaml takes BDF2 steps of 50 ms, far beyond any explicit limit:
  // the thesis' explicit Euler runs at 1/100 of the output interval; a spec
  // with an explicit integrator lends it its own step.
  ASSERT_EQ(spec.msd->integrator, "bdf2");
  EXPECT_DOUBLE_EQ(thesis.msd->dt, spec.output.interval / 100.0);
  const bench::Spec cylinder = bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/stability_uniaxial.yaml");
  ASSERT_EQ(cylinder.msd->integrator, "symplectic_euler");
  EXPECT_DOUBLE_EQ(bench::suite_variant(cylinder, "thesis", cal).msd->dt, cylinder.msd->dt);
  // cvode has no step of its own (msd.dt is not read).
  std::string text = cylinder.text;
  text.replace(text.find("integrator: symplectic_euler"), 28, "integrator: cvode");
  text.erase(text.find("  dt: 2.0e-4\n"), 13);
  const bench::Spec cvode = bench::parse_spec(text, "cvode.yaml");
  EXPECT_DOUBLE_EQ(bench::suite_variant(cvode, "thesis", cal).msd->dt, cvode.output.interval / 100.0);
  const bench::Spec calibrated = bench::suite_variant(spec, "calibrated", cal);
  EXPECT_NE(calibrated.msd->calibration.find("passive_muscle.yaml"), std::string::npos);
  EXPECT_NE(calibrated.msd->stiffness_scale, spec.msd->stiffness_scale);
  // The FEM side of a variant is the spec's: same geometry, mesh and material.
  EXPECT_EQ(calibrated.mesh->spacing, spec.mesh->spacing);
  EXPECT_EQ(bench::suite_variant(spec, "physical", cal).text, spec.text);
  EXPECT_THROW(bench::suite_variant(spec, "tuned", cal), msd::Error);
  // The calibrated lattice: the fit with the edge classes, from MATERIAL_lattice.yaml
  // (shipped for both materials; here one written as calibrate --edge-classes writes it).
  const bench::Spec shipped_lattice = bench::suite_variant(spec, "lattice", cal);
  EXPECT_NE(shipped_lattice.msd->calibration.find("passive_muscle_lattice.yaml"), std::string::npos);
  ASSERT_FALSE(shipped_lattice.msd->edge_laws.empty());
  testing_support::TempDir empty_dir("no_lattice");
  EXPECT_THROW(bench::suite_variant(spec, "lattice", empty_dir.path().string()), msd::Error);  // none there: named
  testing_support::TempDir lattice_dir("lattice");
  bench::CalibrationResult fitted;
  fitted.material = "passive_muscle";
  fitted.before = {1.0, 0.1, 1.0, 4.2e-3, 0.5, 1.0};
  fitted.after = {1.08, 0.03, 10.0, 5.1e-3, 0.26, 1.96};
  bench::write_calibration(fitted, lattice_dir.file("passive_muscle_lattice.yaml"));
  const bench::Spec lattice = bench::suite_variant(spec, "lattice", lattice_dir.path().string());
  EXPECT_NE(lattice.msd->calibration.find("passive_muscle_lattice.yaml"), std::string::npos);
  EXPECT_DOUBLE_EQ(lattice.msd->edge_laws[0].stiffness, 0.26);
  EXPECT_DOUBLE_EQ(lattice.msd->edge_laws[0].compression_exponent, 1.96);
  EXPECT_DOUBLE_EQ(lattice.msd->edge_laws[1].compression_exponent, 1.96);
  EXPECT_DOUBLE_EQ(lattice.msd->volume_factor, 10.0);
  EXPECT_EQ(lattice.mesh->spacing, spec.mesh->spacing);
  EXPECT_EQ(lattice.msd->newton_linear_solver, "sparse_lu");  // exact Newton: the fitted volume term is stiff
  // The continuum rung: the neo-Hookean tets with cube volumes on the same mesh and steps.
  const bench::Spec continuum = bench::suite_variant(spec, "continuum", cal);
  EXPECT_EQ(continuum.msd->terms, (std::vector<std::string>{"neo_hookean", "dampers"}));
  EXPECT_EQ(continuum.msd->continuum_volume, "per_cube");
  EXPECT_EQ(continuum.msd->integrator, spec.msd->integrator);
  EXPECT_DOUBLE_EQ(continuum.msd->dt, spec.msd->dt);
  EXPECT_EQ(continuum.mesh->spacing, spec.mesh->spacing);
  // It needs the material's Poisson's ratio.
  std::string no_nu = cylinder.text;
  const std::string library = "material: {library: non_muscular_tissue}";
  no_nu.replace(no_nu.find(library), library.size(), "material: {density: 920, youngs_modulus: 2990}");
  const bench::Spec without = bench::parse_spec(no_nu, "no_nu.yaml");  // a valid spec: only the variant refuses it
  ASSERT_FALSE(without.material.poisson_ratio);
  EXPECT_THROW(bench::suite_variant(without, "continuum", cal), msd::Error);
  EXPECT_NO_THROW(bench::suite_variant(without, "physical", cal));
  // The physical lattice: isotropic springs with the material's shear modulus
  // and the bulk term, every constant from E and nu (passive muscle: 0.495),
  // solved quasi-statically where the FEM is; it too needs nu.
  const bench::Spec rung = bench::suite_variant(spec, "physical_lattice", cal);
  EXPECT_EQ(rung.msd->terms, (std::vector<std::string>{"springs", "bulk"}));  // quasi-static: no dampers
  EXPECT_NEAR(rung.msd->edge_laws[1].stiffness, 1.8 / 1.495, 1e-12);
  EXPECT_NEAR(rung.msd->edge_laws[0].stiffness, 0.9 / 1.495, 1e-12);
  EXPECT_TRUE(rung.msd->edge_laws[0].linear() && rung.msd->edge_laws[1].linear());
  EXPECT_DOUBLE_EQ(rung.msd->volume_factor, 0.0);
  EXPECT_DOUBLE_EQ(rung.msd->bulk_factor, 1.0);
  EXPECT_EQ(rung.msd->integrator, "quasi_static");
  EXPECT_DOUBLE_EQ(rung.msd->dt, spec.output.interval);
  EXPECT_EQ(rung.mesh->spacing, spec.mesh->spacing);
  const bench::Spec ringing =
      bench::suite_variant(bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/vibration.yaml"), "physical_lattice", cal);
  EXPECT_EQ(ringing.msd->integrator, "bdf2");  // a vibration keeps its integrator
  EXPECT_EQ(ringing.msd->terms, (std::vector<std::string>{"springs", "dampers", "bulk"}));
  EXPECT_THROW(bench::suite_variant(without, "physical_lattice", cal), msd::Error);
  // The neo-Hookean lattice: zero-length springs and the bulk term's
  // neo-Hookean law, no class factors, quasi-static where the FEM is.
  const bench::Spec neo = bench::suite_variant(spec, "neo_lattice", cal);
  EXPECT_TRUE(neo.msd->zero_length_springs);
  EXPECT_EQ(neo.msd->terms, (std::vector<std::string>{"springs", "bulk"}));
  EXPECT_TRUE(neo.msd->edge_laws[0].stiffness == 1.0 && neo.msd->edge_laws[1].stiffness == 1.0);
  EXPECT_EQ(neo.msd->integrator, "quasi_static");
  EXPECT_DOUBLE_EQ(neo.msd->dt, spec.output.interval);
  const bench::Spec neo_ringing =
      bench::suite_variant(bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/vibration.yaml"), "neo_lattice", cal);
  EXPECT_EQ(neo_ringing.msd->integrator, "bdf2");
  EXPECT_EQ(neo_ringing.msd->terms, (std::vector<std::string>{"springs", "dampers", "bulk"}));
  EXPECT_TRUE(neo_ringing.msd->zero_length_springs);
  EXPECT_THROW(bench::suite_variant(without, "neo_lattice", cal), msd::Error);
}
