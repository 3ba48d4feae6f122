// Accuracy that ctest asserts, not only the guard (issue 17, item 5): the
// model ladder's continuum rung (the neo_hookean term with one volume ratio
// per cube, the suite's `continuum` variant) run against the FEM reference on
// shipped benchmarks, each held to the target issue 17 sets for it - the
// project's accuracy requirement, not this model's own result:
//   shear <= 5 % and bending under gravity <= 5 % (relative RMS of the load
//   curve), the ring-down's frequency within 3 %, and the volume-ratio error
//   <= 0.03 over strain +-0.4 (the thesis cylinder's working range).
// The targets the rung misses today (uni-axial and held-out bending) are not
// asserted: benchmarks/results/2026-12-03-continuum-rung.md says by how much.
#include "accuracy_support.hpp"

#include <cmath>
#include <string>

namespace {

bench::Spec continuum(const std::string& name, const std::string& find = "", const std::string& replace = "") {
  return accuracy_support::variant_spec(name, "continuum", find, replace);
}

using accuracy_support::run_both;

}  // namespace

TEST(ContinuumAccuracy, TheShearBlocksLoadCurveIsWithinFivePercentOfTheFem) {
  // The quick tier's shear block (calibrate_shear.yaml, gamma +-0.4) at the shipped shear's BDF2 steps.
  testing_support::TempDir dir("continuum_shear");
  const bench::Comparison c =
      run_both(continuum("calibrate_shear.yaml", "integrator: symplectic_euler\n  dt: 1.0e-4",
                         "integrator: bdf2\n  newton_linear_solver: symmetric_ldlt\n  dt: 5.0e-2"),
               dir);
  EXPECT_LE(c.load_rel_rms, 0.05);
}

TEST(ContinuumAccuracy, TheCantileverUnderGravityIsWithinFivePercentOfTheFem) {
  testing_support::TempDir dir("continuum_gravity");
  const bench::Comparison c = run_both(continuum("bending_gravity.yaml"), dir);
  EXPECT_LE(c.load_rel_rms, 0.05);
}

TEST(ContinuumAccuracy, TheRingDownsFrequencyIsWithinThreePercentOfTheFem) {
  testing_support::TempDir dir("continuum_ringdown");
  const bench::Comparison c = run_both(continuum("vibration.yaml"), dir);
  ASSERT_TRUE(std::isfinite(c.frequency_rel_error));
  EXPECT_LE(std::abs(c.frequency_rel_error), 0.03);
}

TEST(ContinuumAccuracy, TheThesisCylindersVolumeRatioStaysWithinThreeHundredthsOfTheFemsOverStrainPlusMinusFourTenths) {
  testing_support::TempDir dir("continuum_cylinder");
  const bench::Comparison c = run_both(continuum("stability_uniaxial.yaml"), dir);
  EXPECT_LE(c.volume_ratio_max_error, 0.03);
}
