// The calibration loop end to end on small samples: the FEM references are
// computed (and reused on a second call), the optimiser lowers the objective,
// and the file it writes reads back.
#include "bench/calibration.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

namespace {

const char* kUniaxial = R"(name: cal_uniaxial
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {library: non_muscular_tissue}
msd: {constants: physical, repulsion_factor: 0.1, volume_factor: 1.0, dt: 2.0e-4}
fem: {formulation: three_field, degree: 1, cells: [2, 2, 4], vtu: false}
loading: {type: uniaxial, platens: bonded, path: [[0, 0], [0.5, -0.3], [1.5, 0.3], [2, 0]]}
output: {interval: 0.1}
)";

const char* kShear = R"(name: cal_shear
geometry: {shape: box, size: [0.04, 0.04, 0.02]}
mesh: {spacing: 0.01}
material: {library: non_muscular_tissue}
msd: {constants: physical, repulsion_factor: 0.1, volume_factor: 1.0, dt: 2.0e-4}
fem: {formulation: three_field, degree: 1, cells: [4, 4, 2], vtu: false}
loading: {type: simple_shear, path: [[0, 0], [0.5, 0.3], [1.5, -0.3], [2, 0]]}
output: {interval: 0.1}
)";

// A ring-down (stage 2): the block above stretched ~3 % by a dead load on its
// top, released at 0.6 s, ringing near 11 Hz for 0.4 s.
const char* kRingDown = R"(name: cal_ringdown
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {library: non_muscular_tissue}
msd: {constants: physical, repulsion_factor: 0.1, volume_factor: 1.0, dt: 2.0e-4}
fem: {formulation: three_field, degree: 1, cells: [2, 2, 4], vtu: false}
loading: {type: vibration, initial: preload, traction: {face: top, force: [0, 0, 0.04]}, release: 0.6, duration: 0.4}
output: {interval: 0.001}
)";

}  // namespace

TEST(CalibrationLoop, LowersTheObjectiveAndWritesAReadableFile) {
  testing_support::TempDir dir("calloop");
  std::ofstream(dir.file("u.yaml")) << kUniaxial;
  std::ofstream(dir.file("s.yaml")) << kShear;
  std::vector<std::string> lines;
  const bench::CalibrationResult r = bench::calibrate(
      "passive_muscle", {dir.file("u.yaml"), dir.file("s.yaml")}, dir.file("out"), {},
      [&](const std::string& l) { lines.push_back(l); }, 12);
  EXPECT_EQ(r.material, "passive_muscle");
  EXPECT_LT(r.objective_after, r.objective_before);
  EXPECT_LE(r.evaluations, 12);
  ASSERT_EQ(r.specs.size(), 2u);
  EXPECT_EQ(r.specs[0].sha256.size(), 64u);
  EXPECT_EQ(r.specs[0].load_series, "nominal_stress");
  EXPECT_EQ(r.specs[1].load_series, "shear_stress");
  EXPECT_LE(r.specs[0].rel_rms_after + r.specs[1].rel_rms_after,
            r.specs[0].rel_rms_before + r.specs[1].rel_rms_before + 1e-9);
  EXPECT_GE(r.after.stiffness_scale, 0.2);
  EXPECT_LE(r.after.stiffness_scale, 5.0);
  bench::write_calibration(r, dir.file("out/passive_muscle.yaml"));
  std::string material;
  const auto p = bench::read_calibration(dir.file("out/passive_muscle.yaml"), &material);
  EXPECT_EQ(material, "passive_muscle");
  EXPECT_DOUBLE_EQ(p.volume_factor, r.after.volume_factor);
  // A second call reuses the FEM references of the unchanged specs.
  lines.clear();
  bench::calibrate("passive_muscle", {dir.file("u.yaml"), dir.file("s.yaml")}, dir.file("out"), {},
                   [&](const std::string& l) { lines.push_back(l); }, 4);
  int reused = 0;
  for (const auto& l : lines) reused += l.find("reused") != std::string::npos;
  EXPECT_EQ(reused, 2);
  // A fit started from the written file begins where the first one ended:
  // its starting point is the file's set, and its first objective is the
  // first fit's last (the same constants on the same specs).
  const bench::CalibrationResult w =
      bench::calibrate("passive_muscle", {dir.file("u.yaml"), dir.file("s.yaml")}, dir.file("out"), {}, {}, 4, 2.0,
                       20, false, {}, bench::CalibrationStart{p, dir.file("out/passive_muscle.yaml"), material});
  EXPECT_DOUBLE_EQ(w.before.stiffness_scale, r.after.stiffness_scale);
  EXPECT_DOUBLE_EQ(w.before.volume_factor, r.after.volume_factor);
  EXPECT_NEAR(w.objective_before, r.objective_after, 1e-9 * r.objective_after);
  // The optimiser never ends above where it started (its last accepted
  // point may differ from its start in the last digits).
  EXPECT_LE(w.objective_after, w.objective_before * (1.0 + 1e-6));
  EXPECT_EQ(w.start_file, dir.file("out/passive_muscle.yaml"));
  bench::write_calibration(w, dir.file("warm.yaml"));
  std::ifstream in(dir.file("warm.yaml"));
  const std::string warm((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(warm.find("starting_parameters:   # from " + dir.file("out/passive_muscle.yaml")),
            std::string::npos) << warm;
}

TEST(CalibrationLoop, UnknownMaterialAndWrongLoadingAreErrors) {
  testing_support::TempDir dir("calloop");
  std::ofstream(dir.file("u.yaml")) << kUniaxial;
  EXPECT_THROW(bench::calibrate("unobtainium", {dir.file("u.yaml")}, dir.file("out")), msd::Error);
  std::string text = kUniaxial;
  text.replace(text.find("loading:"), std::string::npos,
               "loading: {type: static, fixed: bottom, traction: {face: top, force: [0, 0, 0.01]}, "
               "path: [[0, 0], [0.1, 1]]}\noutput: {interval: 0.05}\n");
  std::ofstream(dir.file("st.yaml")) << text;
  EXPECT_THROW(bench::calibrate("passive_muscle", {dir.file("st.yaml")}, dir.file("out")), msd::Error);
  // A ring-down must start from a preload; a ring-down alone leaves stage 1 nothing.
  std::string free = kRingDown;
  free.replace(free.find("initial: preload, traction: {face: top, force: [0, 0, 0.04]}, release: 0.6"),
               std::string("initial: preload, traction: {face: top, force: [0, 0, 0.04]}, release: 0.6").size(),
               "initial: axial_mode, amplitude: 0.01");
  std::ofstream(dir.file("free.yaml")) << free;
  try {
    bench::calibrate("passive_muscle", {dir.file("u.yaml"), dir.file("free.yaml")}, dir.file("out"));
    FAIL();
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("preload"), std::string::npos) << e.what();
  }
  std::ofstream(dir.file("r.yaml")) << kRingDown;
  try {
    bench::calibrate("passive_muscle", {dir.file("r.yaml")}, dir.file("out"));
    FAIL();
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("stage 1"), std::string::npos) << e.what();
  }
}

TEST(CalibrationLoop, StageTwoFitsTheDampersToTheRingDownsDampingRatio) {
  testing_support::TempDir dir("calloop");
  std::ofstream(dir.file("u.yaml")) << kUniaxial;
  std::ofstream(dir.file("r.yaml")) << kRingDown;
  const bench::CalibrationResult r =
      bench::calibrate("non_muscular_tissue", {dir.file("u.yaml"), dir.file("r.yaml")}, dir.file("out"), {}, {}, 8,
                       2.0, 12);
  ASSERT_TRUE(r.damping_fitted);
  ASSERT_EQ(r.specs.size(), 2u);
  const bench::SpecError& ring = r.specs[1];
  EXPECT_EQ(ring.load_series, "damping_ratio");
  EXPECT_GT(ring.damping_ratio_fem, 0.02);
  EXPECT_GT(ring.frequency_fem, 5.0);
  EXPECT_LE(r.damping_evaluations, 12);
  EXPECT_LT(r.damping_objective_after, r.damping_objective_before);
  // One parameter, one residual: the fitted dampers reproduce the FEM's damping ratio.
  EXPECT_LT(ring.rel_rms_after, 0.05) << "zeta FEM " << ring.damping_ratio_fem << ", MSD " << ring.damping_ratio_after;
  EXPECT_NEAR(ring.damping_ratio_after, ring.damping_ratio_fem, 0.05 * ring.damping_ratio_fem);
  ASSERT_TRUE(r.after.damping_time);
  EXPECT_GT(*r.after.damping_time, 0.0);
  EXPECT_LT(*r.after.damping_time, 0.03);
  EXPECT_NE(*r.after.damping_time, *r.before.damping_time);
  // The elastic stage saw only the quasi-static spec.
  EXPECT_EQ(r.specs[0].load_series, "nominal_stress");
  EXPECT_LT(r.objective_after, r.objective_before);
}
