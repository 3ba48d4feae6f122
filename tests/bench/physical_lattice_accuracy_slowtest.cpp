// Accuracy that ctest asserts (issue 17, item 5) for the physical lattice
// rung - isotropic springs with the material's shear modulus and the per-cube
// bulk term, every constant from E and nu, the suite's `physical_lattice`
// variant, quasi-static where the FEM is - against the FEM reference on
// shipped benchmarks, each held to the target issue 17 sets for it (the
// project's requirement, not this model's own result):
//   the held-out cantilever <= 8 % (relative RMS of the load curve), the
//   ring-down's frequency within 3 %, the volume-ratio error <= 0.03 over
//   strain +-0.4.
// The targets the rung misses (uni-axial 18.6-19.5 %, shear 5.55 %, the
// cantilever under gravity 7.1 % against 5 %, indentation 8.5 %) are not
// asserted: benchmarks/results/2026-12-04-bulk-term.md says by how much.
#include "accuracy_support.hpp"

#include <cmath>

using accuracy_support::run_both;
using accuracy_support::variant_spec;

TEST(PhysicalLatticeAccuracy, TheHeldOutCantileverIsWithinEightPercentOfTheFem) {
  testing_support::TempDir dir("lattice_bending");
  const bench::Comparison c = run_both(variant_spec("bending.yaml", "physical_lattice"), dir);
  EXPECT_LE(c.load_rel_rms, 0.08);
}

TEST(PhysicalLatticeAccuracy, TheRingDownsFrequencyIsWithinThreePercentOfTheFem) {
  testing_support::TempDir dir("lattice_ringdown");
  const bench::Comparison c = run_both(variant_spec("vibration.yaml", "physical_lattice"), dir);
  ASSERT_TRUE(std::isfinite(c.frequency_rel_error));
  EXPECT_LE(std::abs(c.frequency_rel_error), 0.03);
}

TEST(PhysicalLatticeAccuracy, TheThesisCylindersVolumeRatioStaysWithinThreeHundredthsOfTheFemsOverStrainPlusMinusFourTenths) {
  testing_support::TempDir dir("lattice_cylinder");
  const bench::Comparison c = run_both(variant_spec("stability_uniaxial.yaml", "physical_lattice"), dir);
  EXPECT_LE(c.volume_ratio_max_error, 0.03);
}
