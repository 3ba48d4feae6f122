// Accuracy that ctest asserts (issue 17, item 5) for the neo-Hookean lattice
// - zero-length springs with cotangent weights and the bulk term's
// neo-Hookean law per cube, every constant from E and nu, the suite's
// `neo_lattice` variant, quasi-static where the FEM is - against the FEM
// reference on shipped benchmarks, each held to the target issue 17 sets for
// it (the project's requirement, not this model's own result):
//   uni-axial <= 5 % (relative RMS of the load curve over the working range),
//   shear <= 5 %, the held-out cantilever <= 8 %, the cantilever under
//   gravity <= 5 %, the ring-down's frequency within 3 %, the volume-ratio
//   error <= 0.03 over strain +-0.4.
// Not here: the indentation at its shipped 2.5 mm grid (1.36 %, measured in
// benchmarks/results/2026-12-04-neo-lattice.md) - its FEM reference alone
// takes two minutes; the quick tier's guard holds the 5 mm version. Missed,
// so not asserted: the uni-axial band on the thesis' own 2.5 cm grid (7.3 %;
// the shipped spec's 1.25 cm grid is asserted above). The results file says why.
#include "accuracy_support.hpp"

#include <cmath>

using accuracy_support::run_both;
using accuracy_support::variant_spec;

TEST(NeoLatticeAccuracy, TheThesisCycleIsWithinFivePercentOfTheFemOverTheWorkingRange) {
  testing_support::TempDir dir("neo_uniaxial");
  const bench::Comparison c = run_both(variant_spec("uniaxial.yaml", "neo_lattice"), dir);
  ASSERT_TRUE(std::isfinite(c.load_rel_rms_working));
  EXPECT_LE(c.load_rel_rms_working, 0.05);
}

TEST(NeoLatticeAccuracy, ShearIsWithinFivePercentOfTheFem) {
  testing_support::TempDir dir("neo_shear");
  const bench::Comparison c = run_both(variant_spec("calibrate_shear.yaml", "neo_lattice"), dir);
  EXPECT_LE(c.load_rel_rms, 0.05);
}

TEST(NeoLatticeAccuracy, TheHeldOutCantileverIsWithinEightPercentOfTheFem) {
  testing_support::TempDir dir("neo_bending");
  const bench::Comparison c = run_both(variant_spec("bending.yaml", "neo_lattice"), dir);
  EXPECT_LE(c.load_rel_rms, 0.08);
}

TEST(NeoLatticeAccuracy, TheCantileverUnderGravityIsWithinFivePercentOfTheFem) {
  testing_support::TempDir dir("neo_gravity");
  const bench::Comparison c = run_both(variant_spec("bending_gravity.yaml", "neo_lattice"), dir);
  EXPECT_LE(c.load_rel_rms, 0.05);
}

TEST(NeoLatticeAccuracy, TheRingDownsFrequencyIsWithinThreePercentOfTheFem) {
  testing_support::TempDir dir("neo_ringdown");
  const bench::Comparison c = run_both(variant_spec("vibration.yaml", "neo_lattice"), dir);
  ASSERT_TRUE(std::isfinite(c.frequency_rel_error));
  EXPECT_LE(std::abs(c.frequency_rel_error), 0.03);
}

TEST(NeoLatticeAccuracy, TheThesisCylindersVolumeRatioStaysWithinThreeHundredthsOfTheFemsOverStrainPlusMinusFourTenths) {
  testing_support::TempDir dir("neo_cylinder");
  const bench::Comparison c = run_both(variant_spec("stability_uniaxial.yaml", "neo_lattice"), dir);
  EXPECT_LE(c.volume_ratio_max_error, 0.03);
}
