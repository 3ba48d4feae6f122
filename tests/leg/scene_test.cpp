// The leg scene runner (leg/scene.hpp, leg/run.hpp): the scene file's
// checks, and what a short run writes - HDF5 series and fields, XDMF that
// points at datasets which exist, OBJ frames, the summary - and what a blown-up
// run leaves behind.
#include "leg/outputs.hpp"
#include "leg/run.hpp"
#include "leg/scene.hpp"
#include "msd/geometry/leg_generator.hpp"
#include "tbio/results_file.hpp"
#include "test_support.hpp"

#include <yaml-cpp/yaml.h>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace {

namespace fs = std::filesystem;

std::string scenes() { return std::string(TISSUEBENCH_DATA_DIR) + "/scenes/"; }

using testing_support::read_text;

// A scene file written next to the shipped scenes' folder layout (so its
// relative paths resolve) from a shipped one with `edit` applied.
std::string variant_of(const std::string& name, const std::string& from, const std::string& to,
                       const std::string& out) {
  std::string text = read_text(scenes() + name + ".yaml");
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  fs::create_directories(fs::path(out).parent_path());
  // Relative paths (scripts) are resolved against the scene's folder.
  text = std::regex_replace(text, std::regex("\\.\\./scripts/"), std::string(TISSUEBENCH_DATA_DIR) + "/scripts/");
  std::ofstream(out) << text;
  return out;
}

std::string error_of(const std::string& file) {
  try {
    leg::read_leg_scene(file);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

std::vector<hsize_t> dims(hid_t file, const std::string& name) {
  const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (d < 0) return {};
  const hid_t s = H5Dget_space(d);
  std::vector<hsize_t> out(static_cast<size_t>(H5Sget_simple_extent_ndims(s)));
  H5Sget_simple_extent_dims(s, out.data(), nullptr);
  H5Sclose(s);
  H5Dclose(d);
  return out;
}

}  // namespace

TEST(LegScene, TheNineShippedScenesRead) {
  for (const char* name : {"gravity", "pretension", "external_object", "hamstrings", "quadriceps", "co_contraction",
                           "obstacle", "drop", "wobble"}) {
    SCOPED_TRACE(name);
    const leg::LegScene s = leg::read_leg_scene(scenes() + name + ".yaml");
    EXPECT_EQ(s.name, name);
    EXPECT_GT(s.duration, 0.0);
    EXPECT_NEAR(s.output_interval, 0.04, 0.037);  // the thesis' 1/25 s (wobble: 250 Hz)
  }
  const leg::LegScene h = leg::read_leg_scene(scenes() + "hamstrings.yaml");
  ASSERT_TRUE(h.script.has_value());
  EXPECT_DOUBLE_EQ(h.script->activation("BACK_MUSCLE", 3.0), 0.85);  // the thesis' script
  const leg::LegScene e = leg::read_leg_scene(scenes() + "external_object.yaml");
  ASSERT_EQ(e.model.obstacles.size(), 1u);
  EXPECT_EQ(e.model.obstacles[0].object.shape, msd::ObstacleShape::Cylinder);
  EXPECT_TRUE(e.model.knee_contact_box.has_value());
  const leg::LegScene w = leg::read_leg_scene(scenes() + "wobble.yaml");
  EXPECT_EQ(w.variants.size(), 2u);
}

// --set KEY=VALUE (tissuebench leg --set): a field replaced or added as if
// the file said so, kept in the scene's overrides and text (a checkpoint's
// identity), and checked by the same rules as the file's own fields.
TEST(LegScene, SetReplacesOrAddsAFieldAsIfTheFileSaidSo) {
  const std::string file = scenes() + "gravity.yaml";
  const leg::LegScene plain = leg::read_leg_scene(file);
  const leg::LegScene s = leg::read_leg_scene(
      file, {"knee.damping=0.3", "materials.passive.youngs_modulus=5000", "outputs.obj_every=7"});
  EXPECT_NE(plain.model.joint_damping, 0.3);
  EXPECT_DOUBLE_EQ(s.model.joint_damping, 0.3);
  EXPECT_NE(plain.model.passive.youngs_modulus, 5000.0);
  EXPECT_DOUBLE_EQ(s.model.passive.youngs_modulus, 5000.0);
  EXPECT_EQ(s.obj_every, 7);
  EXPECT_DOUBLE_EQ(s.model.passive.density, plain.model.passive.density);  // the rest as the file says
  EXPECT_EQ(s.overrides.size(), 3u);
  EXPECT_TRUE(plain.overrides.empty());
  // What was set heads the text, once each, before the changed scene.
  EXPECT_EQ(s.text.rfind("# " + file + " as changed by:\n# --set knee.damping=0.3\n", 0), 0u) << s.text;
  EXPECT_EQ(s.text.find("knee.damping=0.3"), s.text.rfind("knee.damping=0.3")) << s.text;
  EXPECT_EQ(plain.text.find("--set"), std::string::npos);
  // The text is the scene as run: a reader of the results' /meta sees the
  // values set, and the rest as the file has them.
  const YAML::Node run = YAML::Load(s.text);
  EXPECT_DOUBLE_EQ(run["knee"]["damping"].as<double>(), 0.3);
  EXPECT_DOUBLE_EQ(run["materials"]["passive"]["youngs_modulus"].as<double>(), 5000.0);
  EXPECT_EQ(run["name"].as<std::string>(), "gravity");
  EXPECT_DOUBLE_EQ(run["duration"].as<double>(), YAML::Load(plain.text)["duration"].as<double>());
  // The summary says the file was not run as shipped.
  const tbio::Json j = leg::summary_json(leg::LegRunSummary{}, s);
  ASSERT_TRUE(j.contains("scene_overrides"));
  EXPECT_EQ(j["scene_overrides"][0], "knee.damping=0.3");
  EXPECT_FALSE(leg::summary_json(leg::LegRunSummary{}, plain).contains("scene_overrides"));
  // The last of two settings of one field holds.
  EXPECT_DOUBLE_EQ(leg::read_leg_scene(file, {"knee.damping=0.3", "knee.damping=0.5"}).model.joint_damping, 0.5);
}

TEST(LegScene, SetRefusesWhatTheFileWouldNotHoldNamingTheSetting) {
  const std::string file = scenes() + "gravity.yaml";
  const auto error = [&](const std::string& o) {
    try {
      leg::read_leg_scene(file, {o});
    } catch (const msd::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  for (const char* o : {"knee.damping", "=1", "knee..damping=1", "knee.damping=[1,", "knee.damping=", "name.x=1"}) {
    const std::string e = error(o);
    EXPECT_NE(e.find(std::string("--set ") + o), std::string::npos) << o << ": " << e;
  }
  // Out of range and unknown: the file's own messages, naming the field and the setting.
  std::string e = error("knee.damping=-1");
  EXPECT_NE(e.find("gravity.yaml: knee.damping: must lie in"), std::string::npos) << e;  // no line: not the file's
  EXPECT_NE(e.find("--set knee.damping=-1"), std::string::npos) << e;
  e = error("knee.dampingg=1");
  EXPECT_NE(e.find("knee.dampingg: unknown field"), std::string::npos) << e;
}

TEST(LegScene, BadScenesAreRefusedNamingTheFileTheLineAndTheField) {
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  // An unknown field.
  std::string f = variant_of("gravity", "duration: 4.0", "duration: 4.0\nspeed: fast", dir + "/unknown.yaml");
  std::string e = error_of(f);
  EXPECT_NE(e.find("unknown.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("speed"), std::string::npos) << e;
  // An output interval that is no whole number of steps.
  f = variant_of("gravity", "output_interval: 0.04", "output_interval: 0.0401", dir + "/interval.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("output_interval"), std::string::npos) << e;
  // An unknown obstacle shape.
  f = variant_of("external_object", "shape: cylinder", "shape: cone", dir + "/shape.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("'cone' is not one of: cylinder, plane"), std::string::npos) << e;
  // An activation out of range in a variant.
  f = variant_of("wobble", "activation: {front: 0.5", "activation: {front: 1.5", dir + "/activation.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("variants[1]"), std::string::npos) << e;
  // A scripted knee angle outside the flexion range.
  f = variant_of("drop", "angle_deg: [[0, 0]]", "angle_deg: [[0, 170]]", dir + "/range.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("knee.angle_deg"), std::string::npos) << e;
  // A script with an error: its own file and line.
  const std::string script = dir + "/bad_script.txt";
  std::ofstream(script) << "% a comment\n0.0 BACK_MUSCLE 0.2 0.0\n1.0 CALF 0.5 1.0\n";
  f = variant_of("hamstrings", "../scripts/hamstrings.txt", script,
                 dir + "/script.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("bad_script.txt:3"), std::string::npos) << e;
  // A missing file.
  EXPECT_NE(error_of(dir + "/none.yaml").find("none.yaml"), std::string::npos);
  // A time step that leaves fewer than ten steps over the run.
  f = variant_of("drop", "dt: 2.0e-4", "dt: 0.9", dir + "/dt.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("dt.yaml:10:"), std::string::npos) << e;
  EXPECT_NE(e.find("dt: dt = 0.9 s leaves fewer than ten steps over the duration (8 s): use at most 0.8 s"),
            std::string::npos) << e;
  // A key given twice: refused, not the first one read.
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\ndt: -1", dir + "/twice.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("twice.yaml:11:1: duplicate key 'dt' (first given at line 10)"), std::string::npos) << e;
}

TEST(LegScene, AShortRunWritesSeriesFieldsXdmfObjFramesAndTheSummary) {
  // Pre-tension's first 0.2 s: 6 frames at 1/25 s (0, 0.04, ... 0.2).
  leg::LegScene s = leg::read_leg_scene(scenes() + "pretension.yaml");
  s.duration = 0.2;
  s.obj_every = 1;
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test" / "short").string();
  fs::remove_all(dir);
  const auto runs = leg::run_leg_scene(s, dir);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].status, "complete");
  EXPECT_EQ(runs[0].frames, 6);
  EXPECT_EQ(runs[0].steps, 1000);
  // HDF5: complete, every series one row per frame.
  const tbio::Results r = tbio::read_results(dir + "/leg.h5");
  EXPECT_EQ(r.status(), "complete");
  for (const char* name : {"time", "knee_angle", "knee_velocity", "joint_reaction_z", "tension_back_lower",
                           "volume_ratio_back_muscle", "knee_contact_area", "kinetic_energy", "elastic_energy"}) {
    ASSERT_TRUE(r.series.count(name)) << name;
    EXPECT_EQ(r.series.at(name).size(), 6u) << name;
  }
  EXPECT_NEAR(r.series.at("time").back(), 0.2, 1e-12);
  EXPECT_EQ(r.units.at("knee_angle"), "deg");
  // The pre-tension ramp (0.1-0.6 s) has begun: tension, and elastic energy in the strands.
  EXPECT_GT(r.series.at("tension_front_lower").back(), 0.0);
  EXPECT_GT(r.series.at("elastic_energy").back(), r.series.at("elastic_energy").front());
  // Fields: the nodes, the embedded skin and the bone surfaces, one frame each time.
  ASSERT_TRUE(r.point_sets.count("nodes"));
  ASSERT_TRUE(r.point_sets.count("skin"));
  EXPECT_EQ(r.point_sets.at("skin").second, 6);
  ASSERT_TRUE(r.point_sets.count("bones"));
  EXPECT_EQ(r.point_sets.at("bones").second, 6);
  {  // the femur's surface comes first and stays put (the femur is fixed); the lower bone turns with the knee
    const tbio::PointSetData bones = tbio::read_point_set(dir + "/leg.h5", "bones");
    EXPECT_FALSE(bones.triangles.empty());
    for (const auto& frame : bones.displacement) EXPECT_EQ(frame.front(), (std::array<double, 3>{0.0, 0.0, 0.0}));
  }
  // XDMF: every dataset it names exists in leg.h5 with the dimensions it declares.
  const std::string xdmf = read_text(dir + "/leg.xdmf");
  const hid_t file = H5Fopen((dir + "/leg.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const std::regex item("<DataItem Dimensions=\"([0-9 ]+)\"[^>]*Format=\"HDF\">leg\\.h5:([^<]+)</DataItem>");
  int items = 0;
  for (auto it = std::sregex_iterator(xdmf.begin(), xdmf.end(), item); it != std::sregex_iterator(); ++it) {
    std::vector<hsize_t> declared;
    std::istringstream in((*it)[1].str());
    for (hsize_t d; in >> d;) declared.push_back(d);
    EXPECT_EQ(dims(file, (*it)[2].str()), declared) << (*it)[2].str();
    ++items;
  }
  H5Fclose(file);
  EXPECT_EQ(items, 3 * 6 * 3);  // three grids (tissue, skin, bones), six frames, three HDF items each
  EXPECT_NE(xdmf.find("<Time Value=\"0.2\"/>"), std::string::npos);
  // OBJ frames: six, each the whole skin.
  int objs = 0;
  for (const auto& e : fs::directory_iterator(dir + "/skin")) objs += e.path().extension() == ".obj";
  EXPECT_EQ(objs, 6);
  const std::string obj = read_text(dir + "/skin/frame_0005.obj");
  EXPECT_EQ(std::count(obj.begin(), obj.end(), 'f'), r.point_sets.at("skin").first > 0 ? 15744 : 0);
  // The summary, last.
  const std::string summary = read_text(dir + "/summary.json");
  EXPECT_NE(summary.find("\"status\": \"complete\""), std::string::npos);
  EXPECT_NE(summary.find("\"knee_angle_trajectory_deg\""), std::string::npos);
  EXPECT_NE(summary.find("\"wall_per_simulated_second\""), std::string::npos);
}

TEST(LegScene, ABlownUpRunSaysWhenWhereAndWhyAndKeepsItsFrames) {
  // The drop released with a time step far past stability.
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test" / "blowup").string();
  fs::remove_all(dir);
  const std::string f = variant_of("drop", "dt: 2.0e-4", "dt: 8.0e-3", dir + "/drop_big_step.yaml");
  leg::LegScene s = leg::read_leg_scene(f);
  s.obj_every = 0;
  const auto runs = leg::run_leg_scene(s, dir);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].status, "failed");
  EXPECT_NE(runs[0].failure.find(" s "), std::string::npos) << runs[0].failure;  // "at t = ... s"
  // Caught by the physical limits (msd/experiments/blowup.hpp) or, failing
  // those, by a non-finite value.
  EXPECT_TRUE(runs[0].failure.find("blow-up: ") != std::string::npos ||
              runs[0].failure.find("non-finite") != std::string::npos)
      << runs[0].failure;
  EXPECT_LT(runs[0].simulated, s.duration);
  const tbio::Results r = tbio::read_results(dir + "/leg.h5");
  EXPECT_EQ(r.status(), "failed");
  EXPECT_EQ(static_cast<long>(r.series.at("time").size()), runs[0].frames);
  EXPECT_GE(runs[0].frames, 1);
  const std::string summary = read_text(dir + "/summary.json");
  EXPECT_NE(summary.find("\"status\": \"failed\""), std::string::npos);
  EXPECT_NE(summary.find("\"failure\""), std::string::npos);
}

TEST(LegScene, TheIntegratorAndItsNewtonSettingsAreReadAndMisuseIsRefused) {
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  EXPECT_EQ(leg::read_leg_scene(scenes() + "drop.yaml").integrator, msd::Integrator::SymplecticEuler);  // the default
  std::string f = variant_of("drop", "dt: 2.0e-4",
                             "dt: 2.0e-4\nintegrator: backward_euler\nnewton: {tolerance: 1.0e-6, max_iterations: 12, "
                             "reuse_factorization: false, keep_orientation: true}",
                             dir + "/implicit.yaml");
  const leg::LegScene s = leg::read_leg_scene(f);
  EXPECT_EQ(s.integrator, msd::Integrator::BackwardEuler);
  EXPECT_DOUBLE_EQ(s.model.newton.tolerance, 1e-6);
  EXPECT_EQ(s.model.newton.max_iterations, 12);
  EXPECT_EQ(s.model.newton.max_step_cuts, msd::NewtonOptions{}.max_step_cuts);
  EXPECT_FALSE(s.model.newton.reuse_factorization);
  EXPECT_TRUE(msd::NewtonOptions{}.reuse_factorization);  // modified Newton by default
  EXPECT_TRUE(s.model.newton.keep_orientation);
  EXPECT_FALSE(msd::NewtonOptions{}.keep_orientation);  // off by default
  // Newton settings without the implicit integrator, an unknown integrator, a bad tolerance.
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nnewton: {tolerance: 1.0e-6}", dir + "/newton_explicit.yaml");
  std::string e = error_of(f);
  EXPECT_NE(e.find("newton_explicit.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("only meaningful with 'integrator: backward_euler' or 'bdf2'"), std::string::npos) << e;
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nintegrator: bdf2\nnewton: {max_iterations: 9}", dir + "/bdf2.yaml");
  EXPECT_EQ(leg::read_leg_scene(f).integrator, msd::Integrator::Bdf2);
  EXPECT_EQ(leg::read_leg_scene(f).model.newton.max_iterations, 9);
  EXPECT_EQ(leg::read_leg_scene(f).model.newton.linear_solver, msd::LinearSolver::sparse_lu);  // the default
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nintegrator: bdf2\nnewton: {linear_solver: symmetric_ldlt}",
                 dir + "/ldlt.yaml");
  EXPECT_EQ(leg::read_leg_scene(f).model.newton.linear_solver, msd::LinearSolver::symmetric_ldlt);
  EXPECT_EQ(leg::read_leg_scene(f).model.newton.anderson_depth, 0);  // plain chord steps by default
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nintegrator: bdf2\nnewton: {anderson_depth: 3}", dir + "/anderson.yaml");
  EXPECT_EQ(leg::read_leg_scene(f).model.newton.anderson_depth, 3);
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nintegrator: bdf2\nnewton: {anderson_depth: 9}", dir + "/anderson9.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("anderson9.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("anderson_depth"), std::string::npos) << e;
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nintegrator: bdf2\nnewton: {linear_solver: qr}", dir + "/qr.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("qr.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("linear_solver"), std::string::npos) << e;
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nintegrator: rk4", dir + "/rk4.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("integrator"), std::string::npos) << e;
  EXPECT_NE(e.find("rk4"), std::string::npos) << e;
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nintegrator: backward_euler\nnewton: {tolerance: 2}",
                 dir + "/tolerance.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("newton.tolerance"), std::string::npos) << e;
  // The continuum element needs a Poisson's ratio in both materials: refused, naming the file, `terms` and the
  // material that lacks it; read where both carry one; a ratio outside (-1, 0.5) is refused by its field.
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nterms: [neo_hookean, dampers, gravity]", dir + "/neo_hookean.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("neo_hookean.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("terms"), std::string::npos) << e;
  EXPECT_NE(e.find("materials.passive.poisson_ratio"), std::string::npos) << e;
  const std::string passive = "damping_time: 4.2e-3, repulsion_factor: 0.5, volume_factor: 1.6}";
  const std::string with_nu = read_text(f);
  std::string text = with_nu;
  text.replace(text.find(passive), passive.size(), "damping_time: 4.2e-3, poisson_ratio: 0.495}");
  std::ofstream(dir + "/neo_hookean_passive_only.yaml") << text;
  e = error_of(dir + "/neo_hookean_passive_only.yaml");
  EXPECT_NE(e.find("materials.muscle.poisson_ratio"), std::string::npos) << e;
  text.replace(text.find(passive), passive.size(), "damping_time: 4.2e-3, poisson_ratio: 0.495}");
  std::ofstream(dir + "/neo_hookean_both.yaml") << text;
  const leg::LegScene both = leg::read_leg_scene(dir + "/neo_hookean_both.yaml");
  EXPECT_TRUE(both.model.terms & msd::kNeoHookean);
  EXPECT_EQ(both.model.passive.poisson_ratio, 0.495);
  EXPECT_EQ(both.model.muscle.poisson_ratio, 0.495);
  // The lattice's bulk term is not a leg term: refused where it is named.
  f = variant_of("drop", "dt: 2.0e-4", "dt: 2.0e-4\nterms: [springs, dampers, bulk, gravity]", dir + "/bulk.yaml");
  e = error_of(f);
  EXPECT_NE(e.find("bulk.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("terms"), std::string::npos) << e;
  EXPECT_NE(e.find("bulk"), std::string::npos) << e;
  text.replace(text.find("poisson_ratio: 0.495"), 20, "poisson_ratio: 0.5");
  std::ofstream(dir + "/neo_hookean_half.yaml") << text;
  e = error_of(dir + "/neo_hookean_half.yaml");
  EXPECT_NE(e.find("neo_hookean_half.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("poisson_ratio"), std::string::npos) << e;
}

TEST(LegScene, TheHillLawRealTendonsAndActivationDynamicsAreReadAndMisuseIsRefused) {
  // hamstrings.yaml's muscles section: "muscles:\n  max_stress: 1.0e6\n  force_length_zero: 0.2\n".
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  const std::string thesis_muscles = "muscles:\n  max_stress: 1.0e6\n  force_length_zero: 0.2\n";
  auto hill = [&](const std::string& run, const std::string& muscles, const std::string& name) {
    const std::string with_run = variant_of("hamstrings", "dt: 2.0e-4", run, dir + "/" + name + "_run.yaml");
    const std::string text = read_text(with_run);
    std::string out = text;
    const size_t at = out.find(thesis_muscles);
    EXPECT_NE(at, std::string::npos);
    out.replace(at, thesis_muscles.size(), muscles);
    const std::string path = dir + "/" + name + ".yaml";
    std::ofstream(path) << out;
    return path;
  };
  const std::string bdf2 = "dt: 2.0e-4\nintegrator: bdf2";
  std::string f = hill(bdf2,
                       "muscles:\n  max_stress: 2.5e5\n  law: hill\n  hill: {rest_fibre_stretch: 0.95, max_velocity: 8}\n"
                       "  activation_time: 0.01\n  deactivation_time: 0.04\n",
                       "hill");
  leg::LegScene s = leg::read_leg_scene(f);
  EXPECT_TRUE(s.model.hill.enabled);
  EXPECT_DOUBLE_EQ(s.model.hill.rest_fibre_stretch, 0.95);
  EXPECT_DOUBLE_EQ(s.model.hill.max_velocity, 8.0);
  EXPECT_DOUBLE_EQ(s.model.hill.active_width, msd::HillMuscle{}.active_width);
  EXPECT_DOUBLE_EQ(s.model.activation_time, 0.01);
  EXPECT_DOUBLE_EQ(s.model.deactivation_time, 0.04);
  EXPECT_FALSE(leg::read_leg_scene(scenes() + "hamstrings.yaml").model.hill.enabled);  // the thesis law by default
  // Tendons: the toe and the failure strain.
  f = variant_of("hamstrings", "strand_area: 2.0e-5", "strand_area: 2.0e-5\n  toe_strain: 0.03\n  failure_strain: 0.08",
                 dir + "/toe.yaml");
  s = leg::read_leg_scene(f);
  EXPECT_DOUBLE_EQ(s.model.tendon_toe_strain, 0.03);
  EXPECT_DOUBLE_EQ(s.tendon_failure_strain, 0.08);
  // Refused, naming the file and field: the force-velocity relation with an
  // explicit integrator, Hill settings without the Hill law, a curve that is
  // not a curve, the thesis' limb with the Hill law, a toe past 20 %.
  auto refused = [&](const std::string& path, const std::string& field) {
    const std::string e = error_of(path);
    EXPECT_NE(e.find(fs::path(path).filename().string() + ":"), std::string::npos) << e;
    EXPECT_NE(e.find(field), std::string::npos) << e;
  };
  refused(hill("dt: 2.0e-4", "muscles:\n  max_stress: 2.5e5\n  law: hill\n", "hill_explicit"), "muscles.law");
  EXPECT_NE(error_of(dir + "/hill_explicit.yaml").find("integrator: backward_euler"), std::string::npos);
  EXPECT_NO_THROW(leg::read_leg_scene(
      hill("dt: 2.0e-4", "muscles:\n  max_stress: 2.5e5\n  law: hill\n  hill: {force_velocity: false}\n", "hill_no_fv")));
  refused(hill(bdf2, "muscles:\n  max_stress: 2.5e5\n  hill: {active_width: 0.4}\n", "hill_without_law"), "muscles.hill");
  refused(hill(bdf2, "muscles:\n  max_stress: 2.5e5\n  law: hill\n  hill: {active_width: 1.5}\n", "hill_width"),
          "active_width");
  refused(hill(bdf2, "muscles:\n  max_stress: 2.5e5\n  law: hill\n  hill: {rest_fibre_stretch: 0}\n", "hill_stretch"),
          "rest_fibre_stretch");
  refused(hill(bdf2, "muscles:\n  max_stress: 2.5e5\n  law: hill\n  force_length_zero: 0.5\n", "hill_thesis_limb"),
          "force_length_zero");
  refused(hill(bdf2, "muscles:\n  max_stress: 2.5e5\n  activation_time: -0.01\n", "negative_tau"), "activation_time");
  refused(variant_of("hamstrings", "strand_area: 2.0e-5", "strand_area: 2.0e-5\n  toe_strain: 0.3", dir + "/toe_big.yaml"),
          "toe_strain");
  // F_max from a published cross-section (either muscle, or both); not positive or unknown: refused.
  s = leg::read_leg_scene(hill(bdf2, "muscles:\n  max_stress: 2.7e5\n  pcsa: {front: 0.0225, back: 0.0088}\n", "pcsa"));
  ASSERT_TRUE(s.model.front_pcsa && s.model.back_pcsa);
  EXPECT_DOUBLE_EQ(*s.model.front_pcsa, 0.0225);
  EXPECT_DOUBLE_EQ(*s.model.back_pcsa, 0.0088);
  s = leg::read_leg_scene(hill(bdf2, "muscles:\n  max_stress: 2.7e5\n  pcsa: {back: 0.0088}\n", "pcsa_back"));
  EXPECT_FALSE(s.model.front_pcsa.has_value());
  EXPECT_FALSE(leg::read_leg_scene(scenes() + "hamstrings.yaml").model.back_pcsa.has_value());  // the mesh's section
  refused(hill(bdf2, "muscles:\n  max_stress: 2.7e5\n  pcsa: {front: 0}\n", "pcsa_zero"), "muscles.pcsa.front");
  refused(hill(bdf2, "muscles:\n  max_stress: 2.7e5\n  pcsa: {back: -0.01}\n", "pcsa_negative"), "muscles.pcsa.back");
  refused(hill(bdf2, "muscles:\n  max_stress: 2.7e5\n  pcsa: {quadriceps: 0.02}\n", "pcsa_name"), "quadriceps");
}

TEST(LegScene, AScriptedHipIsReadAndKeyframesOutOfOrderOrNotARotationAreRefused) {
  const leg::LegScene s = leg::read_leg_scene(scenes() + "swing.yaml");
  ASSERT_TRUE(s.hip.has_value());
  EXPECT_EQ(s.hip->size(), 7u);
  EXPECT_LT((s.hip->pivot() - msd::Vec3(0, 0, 0.93)).norm(), 1e-15);
  EXPECT_LT((s.hip->at(0.25).place(s.hip->pivot()) - msd::Vec3(0, 0, 0.93)).norm(), 1e-12);
  EXPECT_FALSE(leg::read_leg_scene(scenes() + "gravity.yaml").hip.has_value());  // no hip: the femur held
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  auto refused = [&](const std::string& from, const std::string& to, const std::string& name,
                     const std::string& what) {
    const std::string path = variant_of("swing", from, to, dir + "/" + name + ".yaml");
    const std::string e = error_of(path);
    EXPECT_NE(e.find(name + ".yaml:"), std::string::npos) << e;
    EXPECT_NE(e.find("hip.keyframes"), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  refused("- [0.75,", "- [0.20,", "hip_out_of_order", "way-point 3: its time");
  refused("- [0.25, 0, 0, 0.93, 0.9762960, 0, -0.2164396, 0]", "- [0.25, 0, 0, 0.93, 0.9762960, 0, -0.5, 0]",
          "hip_not_unit", "unit quaternion");
  refused("- [0.25, 0, 0, 0.93, 0.9762960, 0, -0.2164396, 0]", "- [0.25, 0, 0, 0.93, 1, 0, 0]", "hip_seven",
          "eight numbers");
  const std::string no_pivot = variant_of("swing", "  pivot: [0, 0, 0.93]", "", dir + "/hip_no_pivot.yaml");
  EXPECT_NE(error_of(no_pivot).find("pivot"), std::string::npos) << error_of(no_pivot);
}

TEST(LegScene, TheIsometricKneeExperimentsReadOnTheAnatomicalLegWithRealTendonsAndThePublishedPcsa) {
  // msd/data/experiments: the runs behind docs/leg-geometry.md's isometric torque table.
  const std::string dir = std::string(TISSUEBENCH_DATA_DIR) + "/experiments/";
  const leg::LegScene front = leg::read_leg_scene(dir + "isometric_knee_front.yaml");
  const leg::LegScene back = leg::read_leg_scene(dir + "isometric_knee_back.yaml");
  // The same experiments on the physiological leg's constants: only the tissue, skin, routes and attachments differ.
  const leg::LegScene front_p = leg::read_leg_scene(dir + "isometric_knee_front_physiological.yaml");
  const leg::LegScene back_p = leg::read_leg_scene(dir + "isometric_knee_back_physiological.yaml");
  for (const auto& [thesis, p] : {std::pair{&front, &front_p}, std::pair{&back, &back_p}}) {
    EXPECT_EQ(p->model.terms, msd::kNeoHookean | msd::kDampers | msd::kGravity);
    EXPECT_TRUE(p->model.tendons_direct);
    EXPECT_TRUE(p->model.tendons_at_fibre_ends);
    EXPECT_EQ(p->model.muscle.poisson_ratio, 0.499);  // as the physiological scenes (cited there)
    EXPECT_TRUE(p->model.skin.has_value());
    EXPECT_EQ(p->model.passive.youngs_modulus, 2990);
    EXPECT_EQ(p->model.muscle.youngs_modulus, 14950);
    EXPECT_EQ(p->geometry, thesis->geometry);
    EXPECT_EQ(p->script_path, thesis->script_path);
    EXPECT_EQ(p->model.front_pcsa, thesis->model.front_pcsa);
    EXPECT_EQ(p->model.back_pcsa, thesis->model.back_pcsa);
    EXPECT_EQ(p->knee_angle.values().back(), thesis->knee_angle.values().back());  // both held at 80 degrees
    // The physiological scenes' postures of the muscles' optima, not the test's 80 degrees.
    EXPECT_FALSE(p->tendons_engage_at.has_value());
    EXPECT_TRUE(thesis->tendons_engage_at.has_value());
  }
  // The quadriceps' experiment: the scenes' optima. The hamstrings': both at
  // the test angle, standing in for the seated hip the model lacks (the
  // file says why).
  EXPECT_NEAR(front_p.model.front_optimal_angle, 50.0 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(front_p.model.back_optimal_angle, 0.0);
  EXPECT_NEAR(back_p.model.front_optimal_angle, 80.0 * M_PI / 180.0, 1e-15);
  EXPECT_NEAR(back_p.model.back_optimal_angle, 80.0 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(back_p.knee_angle.values().back(), 80.0 * M_PI / 180.0);
  // ... and it starts there, not straight: the hamstrings' tendons would be stretched before the tissue could follow.
  EXPECT_EQ(back_p.initial_angle, back_p.knee_angle.values().back());
  EXPECT_EQ(front_p.knee_angle.values(), front.knee_angle.values());
  for (const leg::LegScene* s : {&front, &back, &front_p, &back_p}) {
    EXPECT_EQ(fs::path(s->geometry).parent_path().filename(), "leg_anatomical") << s->geometry;
    EXPECT_DOUBLE_EQ(s->model.tendon_modulus, 1.2e9);
    EXPECT_DOUBLE_EQ(s->model.max_muscle_stress, 2.7e5);
    EXPECT_TRUE(s->model.hill.enabled);
  }
  ASSERT_TRUE(front.model.front_pcsa.has_value());
  EXPECT_FALSE(front.model.back_pcsa.has_value());
  ASSERT_TRUE(back.model.back_pcsa.has_value());
  // The groups' PCSA for the leg's body, rounded to the docs' figures (225 and 88 cm^2).
  const msd::LegDimensions d;
  EXPECT_NEAR(*front.model.front_pcsa, msd::group_pcsa(d.quadriceps, 1.756, 85.5), 0.005 * *front.model.front_pcsa);
  EXPECT_NEAR(*back.model.back_pcsa, msd::group_pcsa(d.hamstrings, 1.756, 85.5), 0.01 * *back.model.back_pcsa);
}

TEST(LegScene, TheFullActivationHamstringsExperimentIsThePhysiologicalSceneWithOnlyItsScriptTakenToFull) {
  // msd/data/experiments/hamstrings_full_physiological.yaml: the issue's
  // "hamstrings flex a standing knee past 90 degrees" at full activation.
  const leg::LegScene scene = leg::read_leg_scene(std::string(TISSUEBENCH_DATA_DIR) + "/physiological/hamstrings.yaml");
  const leg::LegScene full =
      leg::read_leg_scene(std::string(TISSUEBENCH_DATA_DIR) + "/experiments/hamstrings_full_physiological.yaml");
  EXPECT_EQ(full.duration, scene.duration);
  EXPECT_EQ(full.dt, scene.dt);
  EXPECT_EQ(full.model.gravity, scene.model.gravity);
  EXPECT_EQ(full.model.terms, scene.model.terms);
  EXPECT_EQ(fs::weakly_canonical(full.geometry), fs::weakly_canonical(scene.geometry));
  EXPECT_EQ(full.model.muscle.youngs_modulus, scene.model.muscle.youngs_modulus);
  EXPECT_EQ(full.model.muscle.poisson_ratio, scene.model.muscle.poisson_ratio);
  EXPECT_EQ(full.model.passive.youngs_modulus, scene.model.passive.youngs_modulus);
  EXPECT_EQ(full.model.skin.has_value(), scene.model.skin.has_value());
  EXPECT_EQ(full.model.tendon_modulus, scene.model.tendon_modulus);
  EXPECT_EQ(full.model.tendons_at_fibre_ends, scene.model.tendons_at_fibre_ends);
  EXPECT_EQ(full.model.max_muscle_stress, scene.model.max_muscle_stress);
  EXPECT_EQ(full.model.back_pcsa, scene.model.back_pcsa);
  EXPECT_EQ(full.model.joint_damping, scene.model.joint_damping);
  EXPECT_EQ(full.model.front_optimal_angle, scene.model.front_optimal_angle);
  EXPECT_EQ(full.model.back_optimal_angle, scene.model.back_optimal_angle);
  EXPECT_EQ(full.knee_angle.values(), scene.knee_angle.values());
  EXPECT_EQ(fs::path(scene.script_path).filename(), "hamstrings.txt");
  EXPECT_EQ(fs::path(full.script_path).filename(), "hamstrings_full.txt");
  // The script is the thesis' one taken on to full activation at 3 s.
  std::ifstream in(full.script_path);
  std::string line, last;
  while (std::getline(in, line))
    if (line.rfind("3.0 BACK_MUSCLE", 0) == 0) last = line;
  EXPECT_EQ(last, "3.0 BACK_MUSCLE 1.0 1.0");
}

TEST(LegScene, TheSkinIsReadFromMaterialsAndANonPositiveOrPartialSkinIsRefused) {
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  const std::string mat = "  muscle: {density: 1040, youngs_modulus: 75000, damping_time: 4.2e-3, repulsion_factor: 0.5, volume_factor: 1.6}\n";
  auto with_skin = [&](const std::string& skin, const std::string& name) {
    return variant_of("gravity", mat, mat + skin, dir + "/" + name + ".yaml");
  };
  const leg::LegScene s = leg::read_leg_scene(with_skin("  skin: {youngs_modulus: 129e3, thickness: 1.55e-3}\n", "skin"));
  ASSERT_TRUE(s.model.skin.has_value());
  EXPECT_DOUBLE_EQ(s.model.skin->youngs_modulus, 129e3);
  EXPECT_DOUBLE_EQ(s.model.skin->thickness, 1.55e-3);
  EXPECT_FALSE(leg::read_leg_scene(scenes() + "gravity.yaml").model.skin.has_value());  // none: the thesis
  auto refused = [&](const std::string& skin, const std::string& name, const std::string& field) {
    const std::string e = error_of(with_skin(skin, name));
    EXPECT_NE(e.find(name + ".yaml:"), std::string::npos) << e;
    EXPECT_NE(e.find(field), std::string::npos) << e;
  };
  refused("  skin: {youngs_modulus: 0, thickness: 1.55e-3}\n", "skin_zero", "materials.skin.youngs_modulus");
  refused("  skin: {youngs_modulus: 129e3, thickness: -1e-3}\n", "skin_negative", "materials.skin.thickness");
  refused("  skin: {youngs_modulus: 129e3}\n", "skin_partial", "thickness");
  refused("  skin: {youngs_modulus: 129e3, thickness: 1.55e-3, density: 1100}\n", "skin_density", "density");
}

TEST(LegScene, TheTendonsRouteIsReadAndAnUnknownRouteIsRefused) {
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  EXPECT_FALSE(leg::read_leg_scene(scenes() + "hamstrings.yaml").model.tendons_direct);  // the thesis' default
  std::string f = variant_of("hamstrings", "  strand_area: 2.0e-5", "  strand_area: 2.0e-5\n  route: direct",
                             dir + "/route_direct.yaml");
  EXPECT_TRUE(leg::read_leg_scene(f).model.tendons_direct);
  f = variant_of("hamstrings", "  strand_area: 2.0e-5", "  strand_area: 2.0e-5\n  route: sheath", dir + "/route_bad.yaml");
  const std::string e = error_of(f);
  EXPECT_NE(e.find("route_bad.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("tendons.route"), std::string::npos) << e;
}

TEST(LegScene, TheTendonsAttachmentIsReadAndFibreEndsWithoutTheDirectRouteAreRefused) {
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  EXPECT_FALSE(leg::read_leg_scene(scenes() + "hamstrings.yaml").model.tendons_at_fibre_ends);  // the thesis' patch
  std::string f = variant_of("hamstrings", "  strand_area: 2.0e-5",
                             "  strand_area: 2.0e-5\n  route: direct\n  attach: fibre_ends", dir + "/attach_ends.yaml");
  EXPECT_TRUE(leg::read_leg_scene(f).model.tendons_at_fibre_ends);
  auto refused = [&](const std::string& lines, const std::string& name, const std::string& says) {
    const std::string e = error_of(variant_of("hamstrings", "  strand_area: 2.0e-5", "  strand_area: 2.0e-5\n" + lines,
                                              dir + "/" + name + ".yaml"));
    EXPECT_NE(e.find(name + ".yaml:"), std::string::npos) << e;
    EXPECT_NE(e.find("attach"), std::string::npos) << e;
    EXPECT_NE(e.find(says), std::string::npos) << e;
  };
  refused("  attach: fibre_ends", "attach_routed", "route: direct");  // route: tissue, the default
  refused("  route: direct\n  attach: aponeurosis", "attach_bad", "aponeurosis");
}

TEST(LegScene, TheMusclesOptimalAnglesAreReadAndRefusedOutsideTheKneesRangeBesideEngageAtOrOffTheDirectRoute) {
  const std::string dir = (fs::path(TB_TEST_OUTPUT_DIR) / "leg_scene_test").string();
  const leg::LegScene thesis = leg::read_leg_scene(scenes() + "hamstrings.yaml");
  EXPECT_EQ(thesis.model.front_optimal_angle, 0.0);  // the mesh's straight knee
  EXPECT_EQ(thesis.model.back_optimal_angle, 0.0);
  // The shipped scenes' tendons section ends just before muscles: the edits
  // add the direct route there (insertions: path is the default).
  const std::string set = "muscles:\n  max_stress: 1.0e6";
  const auto with = [](const std::string& route, const std::string& angles) {
    return route + "muscles:\n  optimal_at_deg: " + angles + "\n  max_stress: 1.0e6";
  };
  const std::string direct = "  route: direct\n";
  const leg::LegScene s =
      leg::read_leg_scene(variant_of("hamstrings", set, with(direct, "{front: 50, back: 10}"), dir + "/optimal.yaml"));
  EXPECT_NEAR(s.model.front_optimal_angle, 50.0 * M_PI / 180.0, 1e-15);
  EXPECT_NEAR(s.model.back_optimal_angle, 10.0 * M_PI / 180.0, 1e-15);
  auto refused = [&](const std::string& name, const std::string& scene, const std::string& to,
                     const std::string& says) {
    const std::string e = error_of(variant_of(scene, set, to, dir + "/" + name + ".yaml"));
    EXPECT_NE(e.find(name + ".yaml:"), std::string::npos) << e;
    EXPECT_NE(e.find("optimal_at_deg"), std::string::npos) << e;
    EXPECT_NE(e.find(says), std::string::npos) << e;
  };
  // range_deg is [-10, 150] in the shipped scenes.
  refused("optimal_above", "hamstrings", with(direct, "{front: 160}"), "outside knee.range_deg");
  refused("optimal_below", "hamstrings", with(direct, "{back: -20}"), "outside knee.range_deg");
  refused("optimal_side", "hamstrings", with(direct, "{middle: 20}"), "middle");
  // The quadriceps scene engages its tendons at 2 s: two rules for one length.
  refused("optimal_engaged", "quadriceps", with(direct, "{front: 50}"), "engage_at");
  // Through the flesh nodes (the thesis' route) a strand's length would not turn with the knee.
  refused("optimal_routed", "hamstrings", with("", "{front: 50}"), "route: direct");
}

TEST(LegScene, ThePhysiologicalScenesAreTheTunedOnesOnTheMaterialsFilesConstants) {
  // msd/data/physiological: the same ten scenes as msd/data/scenes (set-up,
  // scripts, obstacles, variants), every constant the materials file's or a
  // cited published one (docs/leg-motion.md, "The physiological leg").
  const YAML::Node materials = YAML::LoadFile(std::string(TISSUEBENCH_DATA_DIR) + "/../../benchmarks/materials.yaml");
  const auto constant = [&](const char* material, const char* key) { return materials[material][key].as<double>(); };
  std::vector<std::string> tuned_names, names;
  for (const auto& e : fs::directory_iterator(scenes())) tuned_names.push_back(e.path().stem().string());
  for (const auto& e : fs::directory_iterator(std::string(TISSUEBENCH_DATA_DIR) + "/physiological"))
    names.push_back(e.path().stem().string());
  std::sort(tuned_names.begin(), tuned_names.end());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, tuned_names);
  EXPECT_EQ(names.size(), 10u);
  const msd::LegDimensions d;
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const leg::LegScene tuned = leg::read_leg_scene(scenes() + name + ".yaml");
    const leg::LegScene s = leg::read_leg_scene(std::string(TISSUEBENCH_DATA_DIR) + "/physiological/" + name + ".yaml");
    // The same experiment.
    EXPECT_EQ(s.name, tuned.name);
    EXPECT_EQ(s.duration, tuned.duration);
    EXPECT_EQ(s.model.gravity, tuned.model.gravity);
    EXPECT_EQ(s.knee_angle.times(), tuned.knee_angle.times());
    EXPECT_EQ(s.knee_angle.values(), tuned.knee_angle.values());
    if (name == "quadriceps") {
      // Held at 90 degrees until the activation starts (4 s): the issue's
      // outcome starts from a knee bent at 90 (the file says why).
      ASSERT_TRUE(s.knee_release && tuned.knee_release);
      EXPECT_EQ(*s.knee_release, 4.0);
      EXPECT_GT(*s.knee_release, *tuned.knee_release);
    } else {
      EXPECT_EQ(s.knee_release, tuned.knee_release);
    }
    EXPECT_EQ(fs::path(s.script_path).filename(), fs::path(tuned.script_path).filename());
    EXPECT_EQ(s.variants.size(), tuned.variants.size());
    EXPECT_EQ(s.model.obstacles.size(), tuned.model.obstacles.size());
    EXPECT_EQ(s.hip.has_value(), tuned.hip.has_value());
    // The model choices kept from the tuned scene (each file's header lists them).
    EXPECT_EQ(s.model.strand_area, tuned.model.strand_area);
    // The knee's damping is not kept: the healthy knee's, measured in the
    // swing phase of walking (0.02-0.14 N m s/rad, van der Kooij et al.
    // 2022), its middle, where the tuned scenes' 0.25 was fitted to a pendulum.
    EXPECT_EQ(s.model.joint_damping, 0.08);
    EXPECT_EQ(tuned.model.joint_damping, 0.25);
    EXPECT_EQ(s.model.limit_stiffness, tuned.model.limit_stiffness);
    EXPECT_EQ(s.model.passive_lo, tuned.model.passive_lo);
    EXPECT_EQ(s.model.passive_hi, tuned.model.passive_hi);
    EXPECT_EQ(s.model.min_flexion, tuned.model.min_flexion);
    EXPECT_EQ(s.model.max_flexion, tuned.model.max_flexion);
    EXPECT_EQ(s.model.joint_space_radius, tuned.model.joint_space_radius);
    EXPECT_EQ(s.model.knee_contact_box, tuned.model.knee_contact_box);
    // On the anatomical leg, in the continuum element at the materials file's constants.
    EXPECT_EQ(fs::path(s.geometry).parent_path().filename(), "leg_anatomical") << s.geometry;
    EXPECT_EQ(s.model.terms, msd::kNeoHookean | msd::kDampers | msd::kGravity);
    const std::pair<const msd::TissueMaterial*, const char*> pairs[] = {{&s.model.passive, "non_muscular_tissue"},
                                                                        {&s.model.muscle, "passive_muscle"}};
    for (const auto& [m, key] : pairs) {
      EXPECT_EQ(m->density, constant(key, "density")) << key;
      EXPECT_EQ(m->youngs_modulus, constant(key, "youngs_modulus")) << key;
      if (m == &s.model.passive) {
        EXPECT_EQ(m->poisson_ratio, constant(key, "poisson_ratio")) << key;
      }
      EXPECT_EQ(m->damping_time, constant(key, "damping_time")) << key;
      EXPECT_EQ(m->stiffness_scale, 1.0) << key;
    }
    // The muscle's Poisson's ratio, the one override (cited in each file):
    // nearer the incompressible 0.5 than the file's numerical 0.495.
    EXPECT_EQ(s.model.muscle.poisson_ratio, 0.499);
    EXPECT_GT(s.model.muscle.poisson_ratio, constant("passive_muscle", "poisson_ratio"));
    ASSERT_TRUE(s.model.skin.has_value());
    EXPECT_EQ(s.model.skin->youngs_modulus, constant("skin", "youngs_modulus"));
    EXPECT_EQ(s.model.skin->thickness, constant("skin", "thickness"));
    // Real tendons, none softened, routed straight; Hill muscles at a published specific tension and PCSA.
    EXPECT_EQ(s.model.tendon_modulus, constant("tendon", "youngs_modulus"));
    EXPECT_TRUE(s.model.tendon_moduli.empty());
    EXPECT_EQ(s.model.tendon_toe_strain, 0.02);
    EXPECT_TRUE(s.model.tendons_direct);
    EXPECT_TRUE(s.model.tendons_at_fibre_ends);  // an aponeurosis
    // One posture of each muscle's optimum in every scene, not the scene's own start (tendons.engage_at).
    EXPECT_FALSE(s.tendons_engage_at.has_value());
    EXPECT_NEAR(s.model.front_optimal_angle, 50.0 * M_PI / 180.0, 1e-15);  // Chen et al. 2016
    EXPECT_EQ(s.model.back_optimal_angle, 0.0);
    EXPECT_TRUE(s.model.hill.enabled);
    EXPECT_EQ(s.model.max_muscle_stress, 2.7e5);
    ASSERT_TRUE(s.model.front_pcsa && s.model.back_pcsa);
    EXPECT_NEAR(*s.model.front_pcsa, msd::group_pcsa(d.quadriceps, 1.756, 85.5), 0.005 * *s.model.front_pcsa);
    EXPECT_NEAR(*s.model.back_pcsa, msd::group_pcsa(d.hamstrings, 1.756, 85.5), 0.01 * *s.model.back_pcsa);
    EXPECT_EQ(s.model.activation_time, 0.01);  // Zajac 1989
    EXPECT_EQ(s.model.deactivation_time, 0.04);
    EXPECT_EQ(s.integrator, msd::Integrator::Bdf2);
  }
}
