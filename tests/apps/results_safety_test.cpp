// Results are never lost or faked, and runs restart (issue 19): the program
// from the outside - a full disk (a file size limit), a refused run, a file
// held open, two runs to one output, --out naming an input, SIGINT mid-run,
// and checkpoints whose resumed results are bit-identical.
#include "bench/shared_io.hpp"
#include "msd/io/output_lock.hpp"
#include "run_program.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

namespace fs = std::filesystem;

namespace {

using Result = testing_support::ShellResult;
using testing_support::sh;

// The program started in the background (output to `log`).
pid_t start(const std::vector<std::string>& args, const std::string& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> argv{const_cast<char*>(TISSUEBENCH_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(TISSUEBENCH_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

int wait_for(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Waits (up to 60 s) until `path` exists or the process ended; true if it exists.
bool wait_until_exists(const std::string& path, pid_t pid) {
  for (int i = 0; i < 6000; ++i) {
    if (fs::exists(path)) return true;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return fs::exists(path);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// Starts the program with `args` (output to `log`), waits until it has
// written `checkpoint`, stops it with SIGINT and expects exit 130. Call it
// inside ASSERT_NO_FATAL_FAILURE.
void interrupt_after_checkpoint(const std::vector<std::string>& args, const std::string& checkpoint,
                                const std::string& log) {
  const pid_t pid = start(args, log);
  ASSERT_TRUE(wait_until_exists(checkpoint, pid));
  kill(pid, SIGINT);
  ASSERT_EQ(wait_for(pid), 130) << testing_support::read_text(log);
}

std::vector<std::string> leftovers(const std::string& dir) {
  std::vector<std::string> r;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.find(".partial-") != std::string::npos || (n.size() > 5 && n.substr(n.size() - 5) == ".lock"))
      r.push_back(e.path().string());
  }
  return r;
}

// A uni-axial run of a few thousand steps (about a second).
std::string uniaxial(double end_time) {
  return "name: safety\n"
         "geometry: {shape: box, size: [0.02, 0.02, 0.04]}\n"
         "mesh: {spacing: 0.005}\n"
         "material: {density: 1000, youngs_modulus: 5000, damping_time: 0.002}\n"
         "msd: {constants: physical, dt: 1.0e-4}\n"
         "loading: {type: uniaxial, path: [[0, 0], [" +
         std::to_string(end_time) + ", 0.05]]}\noutput: {interval: 0.01, fields_interval: 0.05}\n";
}

// A ring-down (metrics) with velocity Verlet (an integrator with memory).
const char* kRingDown = R"(name: ringdown
geometry: {shape: box, size: [0.01, 0.01, 0.04]}
mesh: {spacing: 0.005}
material: {density: 1000, youngs_modulus: 20000, damping_time: 0.004}
msd: {constants: physical, integrator: velocity_verlet, dt: 5.0e-5}
loading: {type: vibration, initial: preload, traction: {face: top, force: [0, 0, 0.05]}, release: 0.3, duration: 0.5}
output: {interval: 0.001, fields_interval: 0.02}
)";

void expect_same_results(const std::string& a, const std::string& b) {
  const bench::Results ra = bench::read_results(a), rb = bench::read_results(b);
  EXPECT_EQ(ra.status(), "complete");
  EXPECT_EQ(rb.status(), "complete");
  ASSERT_EQ(ra.series.size(), rb.series.size());
  for (const auto& [name, v] : ra.series) {
    ASSERT_TRUE(rb.series.count(name)) << name;
    EXPECT_EQ(v, rb.series.at(name)) << "/series/" << name << " differs";
  }
  EXPECT_EQ(ra.metrics, rb.metrics);
  EXPECT_EQ(ra.point_sets, rb.point_sets);
  for (const auto& [name, dims] : ra.point_sets) {
    const tbio::PointSetData fa = tbio::read_point_set(a, name), fb = tbio::read_point_set(b, name);
    EXPECT_EQ(fa.time, fb.time) << name;
    EXPECT_EQ(fa.displacement, fb.displacement) << "/fields/" << name << " differs";
  }
}

}  // namespace

TEST(ResultsSafety, AFullDiskNeverCrashesAndLeavesAFailedFileOrTheOldOne) {
  // A file size limit of 20 MB (ulimit -f counts KiB; MPI's start-up needs a
  // few MB) against a run writing every node every step (about 55 MB): its
  // writes fail with EFBIG as they would with ENOSPC on a full disk.
  testing_support::TempDir dir("safety_full");
  std::string spec = uniaxial(1.0);
  spec.replace(spec.find("output: {interval: 0.01, fields_interval: 0.05}"), 47,
               "output: {interval: 0.0001, fields_interval: 0.0001}");
  std::ofstream(dir.file("big.yaml")) << spec;
  std::ofstream(dir.file("s.yaml")) << uniaxial(0.2);
  ASSERT_EQ(sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5") + " --quiet").code, 0);
  const std::string before = testing_support::read_text(dir.file("o.h5"));
  const Result r = sh("run " + dir.file("big.yaml") + " --out " + dir.file("o.h5") + " --quiet", "ulimit -f 20000; ");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("disk full or file size limit"), std::string::npos) << r.output;
  if (testing_support::read_text(dir.file("o.h5")) != before) {
    EXPECT_EQ(bench::read_results(dir.file("o.h5")).status(), "failed") << r.output;
    EXPECT_NE(r.output.find("(status: failed)"), std::string::npos) << r.output;
  } else {
    EXPECT_NE(r.output.find("no results file could be written"), std::string::npos) << r.output;
  }
  EXPECT_EQ(leftovers(dir.file("")), std::vector<std::string>{});
}

TEST(ResultsSafety, ARefusedRunLeavesTheExistingFileIntact) {
  testing_support::TempDir dir("safety_refused");
  std::ofstream(dir.file("s.yaml")) << uniaxial(0.2);
  ASSERT_EQ(sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5") + " --quiet").code, 0);
  const std::string before = testing_support::read_text(dir.file("o.h5"));
  const std::string csv = testing_support::read_text(dir.file("o.csv"));
  // Another run holds the output (its lock): refused, exit 2, naming it.
  {
    const msd::OutputLock held(dir.file("o.h5"), "tissuebench run other.yaml");
    const Result r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5") + " --quiet");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("another run is writing it (pid " + std::to_string(getpid())), std::string::npos)
        << r.output;
  }
  // A bad spec: refused before anything is written.
  std::ofstream(dir.file("bad.yaml")) << "name: bad\n";
  EXPECT_EQ(sh("run " + dir.file("bad.yaml") + " --out " + dir.file("o.h5")).code, 2);
  EXPECT_EQ(testing_support::read_text(dir.file("o.h5")), before);
  EXPECT_EQ(testing_support::read_text(dir.file("o.csv")), csv);
  EXPECT_EQ(leftovers(dir.file("")), std::vector<std::string>{});
}

TEST(ResultsSafety, AFileHeldOpenByAnotherProgramIsNotDestroyed) {
  testing_support::TempDir dir("safety_open");
  std::ofstream(dir.file("s.yaml")) << uniaxial(0.2);
  ASSERT_EQ(sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5") + " --quiet").code, 0);
  const std::string before = testing_support::read_text(dir.file("o.h5"));
  std::ifstream held(dir.file("o.h5"), std::ios::binary);
  const Result r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("o.h5") + " --quiet");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(bench::read_results(dir.file("o.h5")).status(), "complete");
  const std::string still((std::istreambuf_iterator<char>(held)), std::istreambuf_iterator<char>());
  EXPECT_EQ(still, before);
}

TEST(ResultsSafety, TwoRunsToOneOutputEndWithOneIntactFileAndAClearRefusal) {
  testing_support::TempDir dir("safety_two");
  std::ofstream(dir.file("s.yaml")) << uniaxial(200.0);  // runs until stopped
  const std::vector<std::string> args{"run", dir.file("s.yaml"), "--out", dir.file("o.h5"), "--quiet"};
  const pid_t a = start(args, dir.file("a.log"));
  ASSERT_TRUE(wait_until_exists(dir.file("o.h5.lock"), a));
  const pid_t b = start(args, dir.file("b.log"));
  const int cb = wait_for(b);
  kill(a, SIGTERM);  // the first run ends (marked failed: interrupted)
  const int ca = wait_for(a);
  EXPECT_EQ(ca, 143) << testing_support::read_text(dir.file("a.log"));
  EXPECT_EQ(cb, 2) << testing_support::read_text(dir.file("b.log"));
  EXPECT_NE(testing_support::read_text(dir.file("b.log")).find("another run is writing it (pid " + std::to_string(a)),
            std::string::npos)
      << testing_support::read_text(dir.file("b.log"));
  const bench::Results r = bench::read_results(dir.file("o.h5"));
  EXPECT_EQ(r.status(), "failed");
  EXPECT_EQ(r.meta.at("failure").find("interrupted by signal 15 (SIGTERM)"), 0u) << r.meta.at("failure");
  EXPECT_EQ(leftovers(dir.file("")), std::vector<std::string>{});
}

TEST(ResultsSafety, AnOutputNamingAnInputIsRefused) {
  testing_support::TempDir dir("safety_input");
  const std::string spec = uniaxial(0.1);
  std::ofstream(dir.file("s.yaml")) << spec;
  Result r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("s.yaml"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--out: the run would write"), std::string::npos) << r.output;
  EXPECT_EQ(testing_support::read_text(dir.file("s.yaml")), spec);
  // The CSV twin of --out s.h5 would be s.csv: an input too.
  std::ofstream(dir.file("data.csv")) << "x\n1\n";
  std::ofstream(dir.file("t.yaml")) << spec;
  r = sh("run " + dir.file("t.yaml") + " --out " + dir.file("data.h5") + " --calibration " + dir.file("data.csv"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(testing_support::read_text(dir.file("data.csv")), "x\n1\n");
}

TEST(ResultsSafety, SigintMidRunLeavesAReadableFileMarkedFailedAndNoTemporaries) {
  testing_support::TempDir dir("safety_sigint");
  std::ofstream(dir.file("s.yaml")) << uniaxial(200.0);  // far longer than the test waits
  const pid_t pid = start({"run", dir.file("s.yaml"), "--out", dir.file("o.h5"), "--quiet"}, dir.file("run.log"));
  ASSERT_TRUE(wait_until_exists(dir.file("o.h5.partial-" + std::to_string(pid)), pid));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid, SIGINT);
  const int code = wait_for(pid);
  const std::string log = testing_support::read_text(dir.file("run.log"));
  EXPECT_EQ(code, 130) << log;
  const bench::Results r = bench::read_results(dir.file("o.h5"));
  EXPECT_EQ(r.status(), "failed");
  EXPECT_EQ(r.meta.at("failure").find("interrupted by signal 2 (SIGINT) at t = "), 0u) << r.meta.at("failure");
  EXPECT_GT(r.series.at("time").size(), 1u);
  EXPECT_TRUE(fs::exists(dir.file("o.csv")));
  EXPECT_EQ(leftovers(dir.file("")), std::vector<std::string>{});
}

TEST(ResultsSafety, AnInterruptedMeshLeavesNoPartialFile) {
  // Signalled while it meshes (it holds m.lock then): the handler removes the
  // lock and any temporary and exits 143; nothing half-written is left.
  testing_support::TempDir dir("safety_mesh");
  const pid_t pid = start({"mesh", "--out", dir.file("m")}, dir.file("mesh.log"));
  ASSERT_TRUE(wait_until_exists(dir.file("m.lock"), pid));
  kill(pid, SIGTERM);
  const int code = wait_for(pid);
  EXPECT_TRUE(code == 143 || code == 0) << code << testing_support::read_text(dir.file("mesh.log"));
  if (fs::exists(dir.file("m"))) {
    EXPECT_EQ(leftovers(dir.file("m")), std::vector<std::string>{});
  }
  EXPECT_FALSE(fs::exists(dir.file("m.lock")));
  if (code == 143) {
    EXPECT_FALSE(fs::exists(dir.file("m/summary.json")));
  }
}

TEST(Checkpoint, AResumedRunIsBitIdenticalToAnUninterruptedOne) {
  testing_support::TempDir dir("checkpoint_run");
  std::ofstream(dir.file("s.yaml")) << kRingDown;
  Result r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("a.h5") + " --quiet");
  ASSERT_EQ(r.code, 0) << r.output;
  // Interrupted after its first checkpoint, then resumed.
  ASSERT_NO_FATAL_FAILURE(interrupt_after_checkpoint(
      {"run", dir.file("s.yaml"), "--out", dir.file("b.h5"), "--quiet", "--checkpoint-every", "0.05"},
      dir.file("b.h5.checkpoint"), dir.file("b.log")));
  EXPECT_EQ(bench::read_results(dir.file("b.h5")).status(), "failed");
  r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("b.h5") + " --quiet --resume " + dir.file("b.h5.checkpoint"));
  ASSERT_EQ(r.code, 0) << r.output;
  expect_same_results(dir.file("a.h5"), dir.file("b.h5"));
  EXPECT_EQ(testing_support::read_text(dir.file("a.csv")), testing_support::read_text(dir.file("b.csv")));
  // Only the provenance tells them apart: the resumed file names its checkpoint.
  EXPECT_EQ(bench::read_results(dir.file("a.h5")).meta.count("resumed_from"), 0u);
  EXPECT_EQ(bench::read_results(dir.file("b.h5")).meta.at("resumed_from").rfind(dir.file("b.h5.checkpoint") + " at t = 0.", 0),
            0u);
  EXPECT_FALSE(fs::exists(dir.file("b.h5.checkpoint")));  // a completed run resumed from it removes it
  EXPECT_EQ(leftovers(dir.file("")), std::vector<std::string>{});
}

TEST(Checkpoint, AResumeAgainstAnotherInputOrSolverIsRefused) {
  testing_support::TempDir dir("checkpoint_refused");
  std::ofstream(dir.file("s.yaml")) << kRingDown;
  const pid_t pid = start({"run", dir.file("s.yaml"), "--out", dir.file("b.h5"), "--quiet", "--checkpoint-every",
                           "0.05"},
                          dir.file("b.log"));
  ASSERT_TRUE(wait_until_exists(dir.file("b.h5.checkpoint"), pid));
  kill(pid, SIGTERM);
  EXPECT_EQ(wait_for(pid), 143);
  const std::string before = testing_support::read_text(dir.file("b.h5"));
  std::string other = kRingDown;
  other.replace(other.find("youngs_modulus: 20000"), 21, "youngs_modulus: 20001");
  std::ofstream(dir.file("t.yaml")) << other;
  Result r = sh("run " + dir.file("t.yaml") + " --out " + dir.file("b.h5") + " --resume " + dir.file("b.h5.checkpoint"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("written for different input"), std::string::npos) << r.output;
  EXPECT_EQ(testing_support::read_text(dir.file("b.h5")), before);
  r = sh("run " + dir.file("s.yaml") + " --out " + dir.file("c.h5") + " --solver fem --checkpoint-every 0.1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("only the msd solver can be checkpointed"), std::string::npos) << r.output;
  other = kRingDown;
  other.replace(other.find("integrator: velocity_verlet, dt: 5.0e-5"), 39, "integrator: cvode");
  std::ofstream(dir.file("cvode.yaml")) << other;
  r = sh("run " + dir.file("cvode.yaml") + " --out " + dir.file("c.h5") + " --checkpoint-every 0.1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("'cvode' cannot be checkpointed"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.file("c.h5")));
}

namespace {

// The obstacle scene shortened: the scripted knee released at 0.3 s, the
// tendons engaged at 0.25 s, the obstacle, the activation script - state a
// resumed leg run must carry across its checkpoint (at 0.28 s).
std::string short_obstacle_scene(const std::string& dir) {
  std::string text = testing_support::read_text(std::string(TISSUEBENCH_DATA_DIR) + "/scenes/obstacle.yaml");
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("angle_deg: [[0, 0], [1.5, 90]]", "angle_deg: [[0, 0], [0.3, 30]]");
  replace("release: 2.0", "release: 0.3");
  replace("engage_at: 2.0", "engage_at: 0.25");
  replace("../scripts/", std::string(TISSUEBENCH_DATA_DIR) + "/scripts/");
  const std::string path = dir + "/obstacle_short.yaml";
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(Checkpoint, AResumedLegRunIsBitIdenticalToAnUninterruptedOne) {
  testing_support::TempDir dir("checkpoint_leg");
  const std::string scene = short_obstacle_scene(dir.file(""));
  const std::string common = " --duration 0.6 --obj-every 3 --quiet";
  Result r = sh("leg " + scene + " --out " + dir.file("a") + common);
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_NO_FATAL_FAILURE(interrupt_after_checkpoint({"leg", scene, "--out", dir.file("b"), "--duration", "0.6",
                                                      "--obj-every", "3", "--quiet", "--checkpoint-every", "0.28"},
                                                     dir.file("b/leg.checkpoint"), dir.file("b.log")));
  EXPECT_EQ(bench::read_results(dir.file("b/leg.h5")).status(), "failed");
  // The frames written after the checkpoint are removed: the resumed run
  // must write them again itself.
  for (const auto& e : fs::directory_iterator(dir.file("b/skin"))) fs::remove(e.path());
  r = sh("leg " + scene + " --out " + dir.file("b") + common + " --resume " + dir.file("b/leg.checkpoint"));
  ASSERT_EQ(r.code, 0) << r.output;
  expect_same_results(dir.file("a/leg.h5"), dir.file("b/leg.h5"));
  EXPECT_EQ(testing_support::read_text(dir.file("a/leg.csv")), testing_support::read_text(dir.file("b/leg.csv")));
  EXPECT_EQ(testing_support::read_text(dir.file("a/leg.xdmf")), testing_support::read_text(dir.file("b/leg.xdmf")));
  std::vector<std::string> objs;
  for (const auto& e : fs::directory_iterator(dir.file("a/skin"))) objs.push_back(e.path().filename().string());
  EXPECT_EQ(objs.size(), 6u);  // frames 0, 3, ..., 15 of 16
  for (const std::string& f : objs)
    EXPECT_EQ(testing_support::read_text(dir.file("a/skin/" + f)), testing_support::read_text(dir.file("b/skin/" + f)))
        << f;
  const auto ja = nlohmann::json::parse(testing_support::read_text(dir.file("a/summary.json")));
  const auto jb = nlohmann::json::parse(testing_support::read_text(dir.file("b/summary.json")));
  for (const char* k : {"status", "values", "knee_angle_trajectory_deg", "steps", "frames", "simulated_seconds"})
    EXPECT_EQ(ja.at(k), jb.at(k)) << k;
  EXPECT_FALSE(fs::exists(dir.file("b/leg.checkpoint")));  // a completed run resumed from it removes it
  EXPECT_EQ(leftovers(dir.file("")), std::vector<std::string>{});
}

TEST(Checkpoint, AResumedSceneWithVariantsIsBitIdenticalToAnUninterruptedOne) {
  // The wobble scene's two variants (relaxed, active), shortened: interrupted
  // in the second, resumed from its checkpoint, which runs the first again.
  testing_support::TempDir dir("checkpoint_variants");
  const std::string scene = std::string(TISSUEBENCH_DATA_DIR) + "/scenes/wobble.yaml";
  const std::string common = " --duration 0.4 --obj-every 0 --quiet";
  Result r = sh("leg " + scene + " --out " + dir.file("a") + common);
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_NO_FATAL_FAILURE(interrupt_after_checkpoint({"leg", scene, "--out", dir.file("b"), "--duration", "0.4",
                                                      "--obj-every", "0", "--quiet", "--checkpoint-every", "0.08"},
                                                     dir.file("b/active/leg.checkpoint"), dir.file("b.log")));
  EXPECT_FALSE(fs::exists(dir.file("b/relaxed/leg.checkpoint")));  // the completed variant removed its own
  EXPECT_EQ(bench::read_results(dir.file("b/active/leg.h5")).status(), "failed");
  fs::copy_file(dir.file("b/active/leg.checkpoint"), dir.file("kept.checkpoint"));
  r = sh("leg " + scene + " --out " + dir.file("b") + common + " --resume " + dir.file("b/active/leg.checkpoint"));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto ja = nlohmann::json::parse(testing_support::read_text(dir.file("a/summary.json")));
  const auto jb = nlohmann::json::parse(testing_support::read_text(dir.file("b/summary.json")));
  for (const char* v : {"relaxed", "active"}) {
    expect_same_results(dir.file(std::string("a/") + v + "/leg.h5"), dir.file(std::string("b/") + v + "/leg.h5"));
    EXPECT_EQ(testing_support::read_text(dir.file(std::string("a/") + v + "/leg.csv")),
              testing_support::read_text(dir.file(std::string("b/") + v + "/leg.csv")))
        << v;
    for (const char* k : {"status", "values", "knee_angle_trajectory_deg", "steps", "frames"})
      EXPECT_EQ(ja.at("variants").at(v).at(k), jb.at("variants").at(v).at(k)) << v << " " << k;
  }
  EXPECT_FALSE(fs::exists(dir.file("b/active/leg.checkpoint")));
  EXPECT_EQ(leftovers(dir.file("")), std::vector<std::string>{});
  // The first variant ran again from rest; the second continued from its checkpoint.
  EXPECT_EQ(bench::read_results(dir.file("b/relaxed/leg.h5")).meta.count("resumed_from"), 0u);
  EXPECT_EQ(bench::read_results(dir.file("b/active/leg.h5"))
                .meta.at("resumed_from")
                .rfind(dir.file("b/active/leg.checkpoint") + " at t = 0.", 0),
            0u);
  // The same checkpoint against other options matches none of the variants.
  r = sh("leg " + scene + " --out " + dir.file("c") + " --duration 0.5 --obj-every 0 --quiet --resume " +
         dir.file("kept.checkpoint"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("a checkpoint of none of the variants of"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.file("c")));  // refused before anything is written
}
