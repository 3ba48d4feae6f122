// The tissuebench program from the outside: help, exit codes, messages, and
// that bad input leaves nothing behind.
#include "bench/shared_io.hpp"
#include "msd/geometry/triangle_mesh.hpp"
#include "run_program.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace {

using Result = testing_support::ShellResult;
using testing_support::sh;

const char* kSpec = R"(name: cli
geometry: {shape: box, size: [0.02, 0.02, 0.04]}
mesh: {spacing: 0.01}
material: {density: 1000, youngs_modulus: 5000, damping_time: 0.002}
msd: {constants: physical, dt: 1.0e-4}
loading: {type: uniaxial, path: [[0, 0], [0.1, 0.05]]}
)";

}  // namespace

TEST(Cli, HelpListsSubcommands) {
  const Result r = sh("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* s : {"run", "suite", "inspect", "converge"}) EXPECT_NE(r.output.find(s), std::string::npos) << s;
  EXPECT_EQ(sh("run --help").code, 0);
  EXPECT_NE(sh("").code, 0);
  EXPECT_NE(sh("frobnicate").code, 0);
}

TEST(Cli, RunWritesResults) {
  testing_support::TempDir dir("cli");
  std::ofstream(dir.file("s.yaml")) << kSpec;
  const Result r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5") + " --solver msd");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("complete"), std::string::npos) << r.output;
  EXPECT_EQ(bench::read_results(dir.file("o.h5")).status(), "complete");
}

TEST(Cli, BadSpecGivesOneClearMessageExitTwoAndNoFile) {
  testing_support::TempDir dir("cli");
  std::string text = kSpec;
  text.replace(text.find("density: 1000"), 13, "densty: 1000");
  std::ofstream(dir.file("bad.yaml")) << text;
  const Result r = sh("run " + dir.file("bad.yaml") + " --out " + dir.file("o.h5"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("bad.yaml:4:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("material.densty: unknown field"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.h5")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.csv")));
}

TEST(Cli, UnknownSolverAndMissingSpecAreErrors) {
  testing_support::TempDir dir("cli");
  std::ofstream(dir.file("s.yaml")) << kSpec;
  EXPECT_EQ(sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5") + " --solver abaqus").code, 2);
  EXPECT_EQ(sh("run " + dir.file("missing.yaml") + " --out " + dir.file("o.h5")).code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.h5")));
}

TEST(Cli, BlowUpExitsOneAndKeepsTheFile) {
  testing_support::TempDir dir("cli");
  std::string text = kSpec;
  text.replace(text.find("dt: 1.0e-4"), 10, "dt: 2.0e-2");
  text.replace(text.find("[0.1, 0.05]"), 11, "[2.0, 0.05]");
  text += "output: {interval: 0.04}\n";
  std::ofstream(dir.file("s.yaml")) << text;
  const Result r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("failed"), std::string::npos) << r.output;
  EXPECT_EQ(bench::read_results(dir.file("o.h5")).status(), "failed");
}

TEST(Cli, FemRunWritesResultsAndBothSolversRun) {
  testing_support::TempDir dir("cli");
  const std::string spec = std::string(TISSUEBENCH_SPECS_DIR) + "/verify_simple_shear.yaml";
  const Result r = sh("run " + spec + " --solver fem --out " + dir.file("f.h5"));
  EXPECT_EQ(r.code, 0) << r.output;
  const bench::Results f = bench::read_results(dir.file("f.h5"));
  EXPECT_EQ(f.status(), "complete");
  EXPECT_EQ(f.meta.at("solver"), "fem");
  EXPECT_GT(f.timing.at("dofs"), 0.0);
  // --solver both needs a spec both solvers accept.
  std::string both = kSpec;
  both.replace(both.find("youngs_modulus: 5000"), 20, "youngs_modulus: 5000, poisson_ratio: 0.45");
  std::ofstream(dir.file("both.yaml")) << both << "fem: {cells: [2, 2, 4], vtu: false}\n";
  const Result b = sh("run " + dir.file("both.yaml") + " --solver both --out " + dir.file("both"));
  EXPECT_EQ(b.code, 0) << b.output;
  EXPECT_EQ(bench::read_results(dir.file("both/cli_msd.h5")).meta.at("solver"), "msd");
  EXPECT_EQ(bench::read_results(dir.file("both/cli_fem.h5")).meta.at("solver"), "fem");
}

TEST(Cli, FemUnderMpirunMatchesSerial) {
  // The same code on a distributed mesh over two processes: a traction-driven
  // case (Cook's membrane) and a displacement-driven one with pins (rollers),
  // where only some processes hold the moving boundary.
  testing_support::TempDir dir("cli");
  const std::string mpirun = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout 300 mpirun -np 2 "
                             "--oversubscribe ";
  for (const auto& [name, series] : {std::pair<std::string, std::string>{"verify_cooks_membrane_incompressible",
                                                                         "tip_displacement"},
                                     {"verify_uniaxial_roller", "nominal_stress"}}) {
    const std::string spec = std::string(TISSUEBENCH_SPECS_DIR) + "/" + name + ".yaml";
    ASSERT_EQ(sh("run " + spec + " --solver fem --out " + dir.file(name + "_serial.h5")).code, 0);
    const std::string cmd = mpirun + TISSUEBENCH_BINARY + " run " + spec + " --solver fem --quiet --out " +
                            dir.file(name + "_mpi.h5") + " 2>&1";
    std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
    std::string out;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, p.get())) out.append(buf, n);
    ASSERT_EQ(WEXITSTATUS(pclose(p.release())), 0) << name << ": " << out;
    const bench::Results s = bench::read_results(dir.file(name + "_serial.h5"));
    const bench::Results m = bench::read_results(dir.file(name + "_mpi.h5"));
    EXPECT_DOUBLE_EQ(m.timing.at("processes"), 2.0);
    const auto& a = s.series.at(series);
    const auto& b = m.series.at(series);
    ASSERT_EQ(a.size(), b.size());
    double scale = 0.0;
    for (double v : a) scale = std::max(scale, std::abs(v));
    for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-9 * scale) << name << " row " << i;
  }
}

TEST(Cli, FemBadInputAndFailedSolves) {
  testing_support::TempDir dir("cli");
  // An unsupported request: an OBJ surface for the fem solver.
  msd::write_obj(dir.file("c.obj"), msd::make_cylinder(0.02, 0.04, 16));
  std::string obj = kSpec;
  const std::string box = "{shape: box, size: [0.02, 0.02, 0.04]}";
  obj.replace(obj.find(box), box.size(), "{shape: obj, file: c.obj}");
  obj.replace(obj.find("youngs_modulus: 5000"), 20, "youngs_modulus: 5000, poisson_ratio: 0.45");
  std::ofstream(dir.file("obj.yaml")) << obj;
  Result r = sh("run " + dir.file("obj.yaml") + " --solver fem --out " + dir.file("obj.h5"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("not supported by the fem solver"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("obj.h5")));
  // An unphysical material: nu = 0.5.
  std::string nu = kSpec;
  nu.replace(nu.find("youngs_modulus: 5000"), 20, "youngs_modulus: 5000, poisson_ratio: 0.5");
  std::ofstream(dir.file("nu.yaml")) << nu;
  r = sh("run " + dir.file("nu.yaml") + " --solver fem --out " + dir.file("nu.h5"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("material.poisson_ratio"), std::string::npos) << r.output;
  // A material the fem cannot use (no Poisson ratio).
  std::ofstream(dir.file("e.yaml")) << kSpec;
  r = sh("run " + dir.file("e.yaml") + " --solver fem --out " + dir.file("e.h5"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("poisson_ratio"), std::string::npos) << r.output;
  // A Newton solve that cannot converge: 95 % compression in one increment with
  // no halving allowed. The run says when, exits 1 and keeps a failed file.
  std::ofstream(dir.file("hard.yaml"))
      << "name: hard\ngeometry: {shape: box, size: [0.02, 0.02, 0.04]}\n"
      << "material: {density: 1000, youngs_modulus: 5000, poisson_ratio: 0.45}\n"
      << "fem: {cells: [1, 1, 2], max_cuts: 0, max_iterations: 5, vtu: true}\n"
      << "loading: {type: uniaxial, platens: bonded, path: [[0, 0], [1, -0.95]]}\noutput: {interval: 1}\n";
  r = sh("run " + dir.file("hard.yaml") + " --solver fem --out " + dir.file("hard.h5"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("did not converge from load time 0"), std::string::npos) << r.output;
  const bench::Results h = bench::read_results(dir.file("hard.h5"));
  EXPECT_EQ(h.status(), "failed");
  EXPECT_EQ(h.series.at("time").size(), 1u);  // the reference state only
  EXPECT_TRUE(std::filesystem::exists(dir.file("hard_vtu/hard.pvd")));
  EXPECT_EQ(h.meta.at("vtu"), dir.file("hard_vtu/hard.pvd"));
  // The frames were written into a temporary folder moved into place at the
  // end; a second run replaces the first one's folder the same way. Neither
  // leaves a temporary behind.
  r = sh("run " + dir.file("hard.yaml") + " --solver fem --out " + dir.file("hard.h5"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir.file("hard_vtu/hard.pvd")));
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(e.path().filename().string().find(".old"), std::string::npos) << e.path();
}

TEST(Cli, InspectPrintsCounts) {
  const Result r = sh(std::string("inspect ") + TISSUEBENCH_SPECS_DIR + "/uniaxial_thesis_full.yaml");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("24 cubes, 120 tets, 63 nodes"), std::string::npos) << r.output;
}

namespace {

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  if (at == std::string::npos) throw std::runtime_error("test fixture: '" + from + "' not found");
  return s.replace(at, from.size(), to);
}

// kSpec with what the FEM needs, so sweeps have a reference.
std::string both_spec() {
  std::string s = replaced(kSpec, "youngs_modulus: 5000", "youngs_modulus: 5000, poisson_ratio: 0.45");
  s = replaced(s, "path: [[0, 0], [0.1, 0.05]]", "path: [[0, 0], [0.1, -0.1], [0.2, 0.1]]");
  return s + "fem: {cells: [2, 2, 4], vtu: false}\noutput: {interval: 0.01}\n";
}

std::string slurp(const std::string& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST(Cli, SweepRunsTheGridAndMergesOneTable) {
  testing_support::TempDir dir("cli");
  std::ofstream(dir.file("s.yaml")) << both_spec();
  const std::string grid = " --spacing 0.01 --dt 1e-4,5e-4 --integrators symplectic_euler --terms all "
                           "--thresholds off --quiet";
  const Result r = sh("sweep " + dir.file("s.yaml") + " --out " + dir.file("sw") + grid);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("FEM reference"), std::string::npos) << r.output;
  const std::string json = slurp(dir.file("sw/cli_sweep.json"));
  EXPECT_NE(json.find("\"integrator\": \"cvode\""), std::string::npos);
  EXPECT_NE(json.find("\"pareto\": true"), std::string::npos);
  EXPECT_EQ(json.find("\"status\": \"failed\""), std::string::npos) << json;
  // The fixed-step points have a time error against the CVODE point; it grows with dt.
  std::ifstream csv(dir.file("sw/cli_sweep.csv"));
  std::string line, header;
  std::getline(csv, header);
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  std::vector<std::string> names;
  {
    std::stringstream hs(header);
    for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
  }
  const size_t col = static_cast<size_t>(std::find(names.begin(), names.end(), "time_error") - names.begin());
  ASSERT_LT(col, names.size());
  ASSERT_EQ(rows.size(), 3u);  // dt 1e-4, dt 5e-4, cvode
  EXPECT_EQ(rows[2][3], "cvode");
  const double e1 = std::stod(rows[0][col]), e5 = std::stod(rows[1][col]);
  EXPECT_GT(e1, 0.0);
  EXPECT_GT(e5, e1);
  // A second sweep of the same grid keeps the points already run.
  const std::string loud = " --spacing 0.01 --dt 1e-4,5e-4 --integrators symplectic_euler --terms all --thresholds off";
  // With an FEM level beside the reference: its cost and its load-curve error
  // against the reference join the table.
  const Result again = sh("sweep " + dir.file("s.yaml") + " --out " + dir.file("sw") + loud + " --fem-levels 1:1");
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_NE(again.output.find("point 2: kept from an earlier run"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("FEM level Q1, refinement 1"), std::string::npos) << again.output;
  const std::string lj = slurp(dir.file("sw/cli_sweep.json"));
  const auto at = lj.find("\"fem_levels\": [");
  ASSERT_NE(at, std::string::npos) << lj;
  const auto err_at = lj.find("\"load_rel_rms\": ", at);
  ASSERT_NE(err_at, std::string::npos) << lj;
  const double level_error = std::stod(lj.substr(err_at + 16));
  EXPECT_GT(level_error, 0.0);   // a finer mesh differs from the reference ...
  EXPECT_LT(level_error, 0.2);   // ... by a discretisation error, not a different curve
  // A point over its time limit is stopped and marked, not counted on the front.
  const Result slow = sh("sweep " + dir.file("s.yaml") + " --out " + dir.file("slow") + " --reference " +
                         dir.file("sw/cli_fem.h5") + loud + " --no-cvode --point-timeout 0.001 --quiet");
  ASSERT_EQ(slow.code, 0) << slow.output;
  const std::string sj = slurp(dir.file("slow/cli_sweep.json"));
  EXPECT_NE(sj.find("\"status\": \"timeout\""), std::string::npos) << sj;
  EXPECT_EQ(sj.find("\"pareto\": true"), std::string::npos) << sj;
  // Under mpirun the same grid is spread over two processes and merged into one table.
  const std::string mpirun = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout 300 mpirun -np 2 "
                             "--oversubscribe ";
  const std::string cmd = mpirun + TISSUEBENCH_BINARY + " sweep " + dir.file("s.yaml") + " --out " +
                          dir.file("mpi") + grid + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p.get())) out.append(buf, n);
  ASSERT_EQ(WEXITSTATUS(pclose(p.release())), 0) << out;
  const std::string mj = slurp(dir.file("mpi/cli_sweep.json"));
  EXPECT_NE(mj.find("\"ranks\": 2"), std::string::npos) << mj;
  for (const char* id : {"\"id\": 0,", "\"id\": 1,", "\"id\": 2,"}) EXPECT_NE(mj.find(id), std::string::npos) << id;
  EXPECT_EQ(mj.find("\"status\": \"failed\""), std::string::npos) << mj;
}

TEST(Cli, SweepBadGridIsAnErrorBeforeAnythingRuns) {
  testing_support::TempDir dir("cli");
  std::ofstream(dir.file("s.yaml")) << both_spec();
  const Result r = sh("sweep " + dir.file("s.yaml") + " --out " + dir.file("sw") + " --terms everything");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("everything"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("sw/cli_sweep.json")));
  const Result level = sh("sweep " + dir.file("s.yaml") + " --out " + dir.file("sw") + " --fem-levels 4:0");
  EXPECT_EQ(level.code, 2);
  EXPECT_NE(level.output.find("--fem-levels: '4:0'"), std::string::npos) << level.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("sw/cli_sweep.json")));
}

TEST(Cli, StabilityPrintsBothTables) {
  testing_support::TempDir dir("cli");
  std::ofstream(dir.file("s.yaml")) << both_spec();
  const Result r = sh("stability " + dir.file("s.yaml") + " --out " + dir.file("st") +
                      " --integrators symplectic_euler --terms springs_dampers --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Largest stable time step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("tendon_1GPa"), std::string::npos) << r.output;
  EXPECT_NE(slurp(dir.file("st/cli_stability.json")).find("\"largest_stable_dt\""), std::string::npos);
}

TEST(Cli, CalibrationErrorsNameTheProblem) {
  testing_support::TempDir dir("cli");
  const Result a = sh("calibrate --material unobtainium --out " + dir.file("c") + " --quiet");
  EXPECT_EQ(a.code, 2);
  EXPECT_NE(a.output.find("unobtainium"), std::string::npos) << a.output;
  // A start of another material, and one outside the bounds: named, before any FEM run.
  std::ofstream(dir.file("start.yaml")) << "material: passive_muscle\nparameters: {stiffness_scale: 1, "
                                           "repulsion_factor: 0.1, volume_factor: 1}\n";
  const Result m = sh("calibrate --material non_muscular_tissue --start " + dir.file("start.yaml") + " --out " +
                      dir.file("c") + " --quiet");
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.output.find("start.yaml: material: 'passive_muscle' is not the fit's 'non_muscular_tissue'"),
            std::string::npos) << m.output;
  std::ofstream(dir.file("start.yaml")) << "material: passive_muscle\nparameters: {stiffness_scale: 1, "
                                           "repulsion_factor: 0.1, volume_factor: 25}\n";
  const Result o = sh("calibrate --material passive_muscle --start " + dir.file("start.yaml") + " --out " +
                      dir.file("c") + " --quiet");
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.output.find("start.yaml: parameters.volume_factor = 25 is not strictly inside"), std::string::npos)
      << o.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("c/passive_muscle.yaml")));
  std::ofstream(dir.file("c.yaml")) << "material: passive_muscle\nparameters: {stiffness_scale: 1, "
                                       "repulsion_factor: 0, volume_factor: 1}\n";
  const std::string spec = replaced(kSpec, "material: {density: 1000, youngs_modulus: 5000, damping_time: 0.002}",
                                    "material: {library: non_muscular_tissue}");
  std::ofstream(dir.file("s.yaml")) << spec;
  const Result b = sh("run " + dir.file("s.yaml") + " --calibration " + dir.file("c.yaml") + " --out " +
                      dir.file("o.h5"));
  EXPECT_EQ(b.code, 2);
  EXPECT_NE(b.output.find("passive_muscle"), std::string::npos) << b.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.h5")));
  std::ofstream(dir.file("c.yaml")) << "material: non_muscular_tissue\nparameters: {stiffness_scale: 0.5, "
                                       "repulsion_factor: 0, volume_factor: 2}\n";
  const Result c = sh("run " + dir.file("s.yaml") + " --calibration " + dir.file("c.yaml") + " --out " +
                      dir.file("o.h5"));
  EXPECT_EQ(c.code, 0) << c.output;
  EXPECT_EQ(bench::read_results(dir.file("o.h5")).meta.at("calibration"), dir.file("c.yaml"));
}

TEST(Cli, CheckPassesUnchangedAndFailsOnAPerturbedSpringConstant) {
  testing_support::TempDir dir("cli");
  std::ofstream(dir.file("s.yaml")) << both_spec();
  ASSERT_EQ(sh("run " + dir.file("s.yaml") + " --solver both --out " + dir.file("base") + " --quiet").code, 0);
  // A baseline from the run, then the same run checks clean against it.
  const Result up = sh("check " + dir.file("base") + " --baseline " + dir.file("b.yaml") + " --update --tier test");
  ASSERT_EQ(up.code, 0) << up.output;
  EXPECT_NE(up.output.find("cli.load_rel_rms: added"), std::string::npos) << up.output;
  const Result same = sh("check " + dir.file("base") + " --baseline " + dir.file("b.yaml"));
  EXPECT_EQ(same.code, 0) << same.output;
  EXPECT_NE(same.output.find("baseline metrics hold"), std::string::npos) << same.output;
  // The regression: springs 30 % stiffer. The guard names the metric, the
  // value, the baseline and its tolerance.
  std::ofstream(dir.file("r.yaml")) << replaced(both_spec(), "constants: physical", "constants: physical, stiffness_scale: 1.3");
  ASSERT_EQ(sh("run " + dir.file("r.yaml") + " --solver msd --out " + dir.file("reg/cli_msd.h5") + " --quiet").code, 0);
  ASSERT_EQ(sh("compare " + dir.file("reg/cli_msd.h5") + " " + dir.file("base/cli_fem.h5") + " --json " +
               dir.file("reg/cli_compare.json")).code,
            0);
  const Result bad = sh("check " + dir.file("reg") + " --baseline " + dir.file("b.yaml"));
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("cli.load_rel_rms: "), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("against baseline"), std::string::npos) << bad.output;
  // Bad input: a missing folder or baseline is an input error (2), not a regression.
  EXPECT_EQ(sh("check " + dir.file("nowhere") + " --baseline " + dir.file("b.yaml")).code, 2);
  EXPECT_EQ(sh("check " + dir.file("base") + " --baseline " + dir.file("none.yaml")).code, 2);
  // So is a baseline that would switch the guard off: an infinite, NaN, negative or
  // missing tolerance, or no metrics at all - named with its file, line and field.
  const std::string entry = "tier: t\nmetrics:\n  cli.load_rel_rms: ";
  for (const auto& [text, field] : std::vector<std::pair<std::string, std::string>>{
           {entry + "{value: 0.1, tolerance: .inf}\n", ":3:45: metrics.cli.load_rel_rms.tolerance: must be finite"},
           {entry + "{value: 0.1, tolerance: .nan}\n", ":3:45: metrics.cli.load_rel_rms.tolerance: must be finite"},
           {entry + "{value: 0.1, tolerance: -1}\n", ":3:45: metrics.cli.load_rel_rms.tolerance: must be >= 0"},
           {entry + "{value: 0.1}\n", ":3:21: metrics.cli.load_rel_rms.tolerance: required field is missing"},
           {"tier: t\nmetrics: {}\n", ":2:10: metrics: empty"}}) {
    std::ofstream(dir.file("bad.yaml")) << text;
    const Result r = sh("check " + dir.file("base") + " --baseline " + dir.file("bad.yaml"));
    EXPECT_EQ(r.code, 2) << text << r.output;
    EXPECT_NE(r.output.find(dir.file("bad.yaml") + field), std::string::npos) << text << r.output;
  }
}

TEST(Cli, SuiteBadTierOrSpecIsAnInputErrorBeforeAnythingRuns) {
  testing_support::TempDir dir("cli");
  const Result r = sh("suite --tier medium --out " + dir.file("out"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--tier: 'medium'"), std::string::npos) << r.output;
  // A tier naming a spec with a bad field stops before any run or folder.
  std::ofstream(dir.file("bad_spec.yaml")) << replaced(both_spec(), "spacing: 0.01", "spacing: 0.01, spasing: 1");
  std::ofstream(dir.file("t.yaml")) << "tier: t\nvariants: [physical]\nbenchmarks: [{spec: bad_spec.yaml}]\n";
  const Result b = sh("suite --tier " + dir.file("t.yaml") + " --out " + dir.file("out"));
  EXPECT_EQ(b.code, 2);
  EXPECT_NE(b.output.find("mesh.spasing: unknown field"), std::string::npos) << b.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
}

TEST(Cli, MeshWritesTheLimbForParaViewAndRefusesBadScenesByName) {
  testing_support::TempDir dir("cli_mesh");
  // A cylindrical limb: skin, a femur, a tibia reaching the skin's end, and a
  // muscle in front of and behind the femur.
  auto moved = [](msd::TriangleMesh m, const msd::Vec3& by) {
    m.vertices.colwise() += by;
    return m;
  };
  msd::write_obj(dir.file("skin.obj"), msd::make_cylinder(0.05, 0.30, 48));
  msd::write_obj(dir.file("femur.obj"), moved(msd::make_cylinder(0.012, 0.12, 16), {0, 0, 0.165}));
  msd::write_obj(dir.file("tibia.obj"), moved(msd::make_cylinder(0.012, 0.13, 16), {0, 0, 0.005}));
  msd::write_obj(dir.file("quad.obj"), msd::make_box({-0.025, 0.018, 0.17}, {0.025, 0.042, 0.28}));
  msd::write_obj(dir.file("ham.obj"), msd::make_box({-0.025, -0.042, 0.17}, {0.025, -0.018, 0.28}));
  const std::string scene = R"(name: cylinder_leg
leg: {skin: skin.obj, upper_bone: femur.obj, lower_bone: tibia.obj, front_muscle: quad.obj, back_muscle: ham.obj}
mesh: {spacing: 0.01, rotation: [0, 0, 10], pull: [{name: behind_knee, lo: [-0.06, -0.06, 0.12], hi: [0.06, -0.01, 0.18]}]}
tendons:
  - {name: hamstrings_lower, muscle: back_muscle, bone: lower_bone, strands: 6,
     path: [[0, -0.03, 0.17], [0, -0.03, 0.14], [0, -0.012, 0.13]]}
)";
  std::ofstream(dir.file("leg.yaml")) << scene;
  const Result r = sh("mesh " + dir.file("leg.yaml") + " --out " + dir.file("out"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("bone points"), std::string::npos) << r.output;
  EXPECT_NE(slurp(dir.file("out/summary.json")).find("\"tendon_strands\": 6"), std::string::npos);
  for (const char* f : {"mesh.vtu", "bone_points.vtu", "tendons.vtu", "surfaces/skin.vtu", "surfaces/upper_bone.vtu",
                        "surfaces/back_muscle.vtu", "summary.json"})
    EXPECT_TRUE(std::filesystem::exists(dir.file("out/" + std::string(f)))) << f;
  const std::string summary = slurp(dir.file("out/summary.json"));
  EXPECT_EQ(summary.find("\"pulled_nodes\": 0,"), std::string::npos) << "the pull moved no node\n" << summary;
  for (const char* key : {"\"cubes\"", "\"tets\"", "\"tets_by_region\"", "\"bone_points\"", "\"tendon_strands\"",
                          "\"embedded_vertices\"", "\"embedded_outside\"", "\"min_quality\"", "\"seconds\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;
  EXPECT_NE(summary.find("\"front_muscle\": "), std::string::npos);
  // The printed counts are the summary's.
  const size_t at = summary.find("\"tets\": ");
  const std::string tets = summary.substr(at + 8, summary.find(',', at) - at - 8);
  EXPECT_NE(r.output.find("tets               " + tets), std::string::npos) << r.output;

  // Bad scenes: a field name, a missing file, a bone outside the skin. A
  // refused run into a folder that holds an earlier run touches none of its
  // files (issue 19: a refused run never touches an existing output).
  std::ofstream(dir.file("typo.yaml")) << replaced(scene, "spacing", "spaceing");
  Result bad = sh("mesh " + dir.file("typo.yaml") + " --out " + dir.file("out"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(slurp(dir.file("out/summary.json")), summary);
  bad = sh("mesh " + dir.file("typo.yaml") + " --out " + dir.file("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("spaceing"), std::string::npos) << bad.output;
  std::ofstream(dir.file("missing.yaml")) << replaced(scene, "ham.obj", "nothing.stl");
  bad = sh("mesh " + dir.file("missing.yaml") + " --out " + dir.file("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("leg.back_muscle"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("no such file"), std::string::npos) << bad.output;
  std::ofstream(dir.file("tendon.yaml")) << replaced(scene, "bone: lower_bone", "bone: tibia");
  bad = sh("mesh " + dir.file("tendon.yaml") + " --out " + dir.file("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("tendons[0].bone"), std::string::npos) << bad.output;
  // A tendon drawn from the bone to the muscle: its ends are on the wrong regions.
  std::ofstream(dir.file("reversed.yaml"))
      << replaced(scene, "[[0, -0.03, 0.17], [0, -0.03, 0.14], [0, -0.012, 0.13]]",
                  "[[0, -0.012, 0.13], [0, -0.03, 0.14], [0, -0.03, 0.17]]");
  bad = sh("mesh " + dir.file("reversed.yaml") + " --out " + dir.file("bad"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("tendons[0]: tendon 'hamstrings_lower': its first (muscle) point (0, -0.012, 0.13) is "
                            "not in back_muscle (" + dir.file("ham.obj") + ")"),
            std::string::npos)
      << bad.output;
  msd::write_obj(dir.file("long_femur.obj"), moved(msd::make_cylinder(0.012, 0.2, 16), {0, 0, 0.165}));
  std::ofstream(dir.file("outside.yaml")) << replaced(scene, "femur.obj", "long_femur.obj");
  bad = sh("mesh " + dir.file("outside.yaml") + " --out " + dir.file("bad"));
  EXPECT_EQ(bad.code, 2);
  // A femur through the skin: the two crossing triangles named, file and line
  // (tbio/surface_check.hpp).
  EXPECT_NE(bad.output.find(dir.file("long_femur.obj") + ":"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("the surfaces " + dir.file("skin.obj") + " and " + dir.file("long_femur.obj") +
                            " cross each other"),
            std::string::npos)
      << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad/summary.json")));
}

TEST(Cli, LegGeometryWritesALegThatMeshesAndTheShippedLegIsTheDefault) {
  testing_support::TempDir dir("cli_leg");
  // A smaller body: files and a scene that tissuebench mesh reads.
  Result r = sh("leg-geometry --stature 1.65 --mass 60 --skin-cell 0.02 --out " + dir.file("leg"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("stature 1.650 m, mass 60.0 kg"), std::string::npos) << r.output;
  for (const char* f : {"skin.obj", "upper_bone.obj", "lower_bone.obj", "front_muscle.obj", "back_muscle.obj", "leg.yaml"})
    EXPECT_TRUE(std::filesystem::exists(dir.file("leg/" + std::string(f)))) << f;
  r = sh("mesh " + dir.file("leg/leg.yaml") + " --out " + dir.file("mesh"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string summary = slurp(dir.file("mesh/summary.json"));
  EXPECT_NE(summary.find("\"tendon_strands\": 26"), std::string::npos) << summary;  // 8 + 6 + 6 + 6
  for (const char* region : {"\"front_muscle\": 0,", "\"back_muscle\": 0,", "\"upper_bone\": 0,", "\"lower_bone\": 0,"})
    EXPECT_EQ(summary.find(region), std::string::npos) << region << " has no tets\n" << summary;

  // The same body with its muscles sized to the published volumes: it meshes, with every strand routed.
  r = sh("leg-geometry --stature 1.65 --mass 60 --skin-cell 0.02 --muscles anatomical --out " + dir.file("anat"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("muscles: anatomical"), std::string::npos) << r.output;
  r = sh("mesh " + dir.file("anat/leg.yaml") + " --out " + dir.file("anat_mesh"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string anat = slurp(dir.file("anat_mesh/summary.json"));
  EXPECT_NE(anat.find("\"tendon_strands\": 26"), std::string::npos) << anat;
  for (const char* region : {"\"front_muscle\": 0,", "\"back_muscle\": 0,"})
    EXPECT_EQ(anat.find(region), std::string::npos) << region << " has no tets\n" << anat;

  // No scene: the shipped leg (msd/data/leg/leg.yaml), at the thesis' resolution.
  r = sh("mesh --out " + dir.file("default"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string s = slurp(dir.file("default/summary.json"));
  const size_t at = s.find("\"cubes\": ");
  ASSERT_NE(at, std::string::npos) << s;
  const long cubes = std::stol(s.substr(at + 9));
  EXPECT_NEAR(cubes, 959, 0.1 * 959) << s;  // the thesis' leg: 959 cubes

  // Unphysical bodies are refused by name, and nothing is written.
  r = sh("leg-geometry --stature 2.9 --out " + dir.file("bad"));
  EXPECT_EQ(r.code, 2);
  // Refused by the option's own check, before the generator runs.
  EXPECT_NE(r.output.find("--stature: must be in [1.2, 2.3] (m); got 2.9"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad")));
}

TEST(Cli, TheIsometricKneeExperimentRunsOnTheAnatomicalLeg) {
  // msd/data/experiments/isometric_knee_front.yaml (BDF2, real tendons, the Hill
  // law with the PCSA's force): its first 0.05 s, the knee starting to bend.
  testing_support::TempDir dir("cli_leg_isometric");
  const Result r = sh("leg " + std::string(TISSUEBENCH_DATA_DIR) + "/experiments/isometric_knee_front.yaml --out " +
                      dir.file("iso") + " --duration 0.05 --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("isometric_knee_front: complete, 0.05 s simulated"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir.file("iso/leg.h5")));
}

TEST(Cli, LegRunsASceneSaysWhatItWroteAndRefusesBadOnesOrBlowUpsWithTheirExitCodes) {
  testing_support::TempDir dir("cli_leg_scene");
  const std::string scenes = std::string(TISSUEBENCH_DATA_DIR) + "/scenes/";
  // The first 0.12 s of the pre-tension scene.
  Result r = sh("leg " + scenes + "pretension.yaml --out " + dir.file("pre") + " --duration 0.12 --obj-every 1 --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("pretension: complete, 0.12 s simulated"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("knee_angle_max_deg"), std::string::npos) << r.output;
  for (const char* f : {"leg.h5", "leg.csv", "leg.xdmf", "summary.json", "skin/frame_0003.obj"})
    EXPECT_TRUE(std::filesystem::exists(dir.file("pre/" + std::string(f)))) << f;
  // A scene with a wrong field: exit 2, the file and field named, no summary.
  std::string bad = replaced(slurp(scenes + "pretension.yaml"), "dt: 2.0e-4", "dt: -1");
  std::ofstream(dir.file("bad.yaml")) << bad;
  r = sh("leg " + dir.file("bad.yaml") + " --out " + dir.file("bad"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.yaml:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dt"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad/summary.json")));
  // A step far past stability: exit 1 (README, exit codes), when and where it
  // failed, the frames kept.
  std::string unstable = replaced(slurp(scenes + "drop.yaml"), "dt: 2.0e-4", "dt: 8.0e-3");
  std::ofstream(dir.file("unstable.yaml")) << unstable;
  r = sh("leg " + dir.file("unstable.yaml") + " --out " + dir.file("unstable") + " --obj-every 0 --quiet");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(r.output.find("blow-up: ") != std::string::npos || r.output.find("non-finite") != std::string::npos)
      << r.output;
  EXPECT_NE(slurp(dir.file("unstable/summary.json")).find("\"status\": \"failed\""), std::string::npos);
}
