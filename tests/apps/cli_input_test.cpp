// The command line refuses bad values before anything runs: every numeric
// option is checked for range and finiteness (NaN included), with the option
// named, exit 2 and nothing written. Fast: no simulation runs.
#include "run_program.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

using Result = testing_support::ShellResult;
using testing_support::sh;

void expect_refused(const std::string& args, const std::string& message) {
  const Result r = sh(args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
}

}  // namespace

TEST(CliInput, LegOptionsAreCheckedForRangeAndFiniteness) {
  testing_support::TempDir dir("cli_input");
  const std::string out = " --out " + dir.file("leg");
  expect_refused("leg --duration nan" + out, "--duration: must be a finite number (simulated seconds); got nan");
  expect_refused("leg --duration -1" + out, "--duration: must be in (0, inf] (simulated seconds); got -1");
  expect_refused("leg --duration 0" + out, "--duration: must be in (0, inf]");
  expect_refused("leg --duration inf" + out, "--duration: must be a finite number");
  expect_refused("leg --duration 1s" + out, "--duration: must be a number (simulated seconds); got '1s'");
  expect_refused("leg --obj-every -3" + out, "--obj-every: must be in [0, 1000000000] (frames); got -3");
  // Fewer than ten steps of the scene's dt (the hamstrings: 2e-4 s).
  expect_refused("leg --duration 0.001" + out, "--duration: 0.001 s is fewer than ten steps of the scene's dt");
  EXPECT_FALSE(std::filesystem::exists(dir.file("leg")));
}

// --set takes one KEY=VALUE each time, before or after the scene; a bad one
// is refused naming the scene file it changed (not the default scene's).
TEST(CliInput, LegSetTakesOneFieldEachTimeAndIsChecked) {
  testing_support::TempDir dir("cli_input_set");
  const std::string scene = std::string(TISSUEBENCH_DATA_DIR) + "/scenes/gravity.yaml";
  const std::string out = " --out " + dir.file("leg");
  expect_refused("leg --set knee.damping=-1 " + scene + out, "gravity.yaml: knee.damping: must lie in");
  expect_refused("leg --set knee.damping=-1 " + scene + out, "--set knee.damping=-1");
  expect_refused("leg " + scene + " --set knee.damping=0.1 --set knee.damping=-2" + out, "got -2");
  expect_refused("leg " + scene + " --set knee.damping" + out, "--set knee.damping: give KEY=VALUE");
  EXPECT_FALSE(std::filesystem::exists(dir.file("leg")));
}

TEST(CliInput, GeometryViewAndServeOptionsAreChecked) {
  testing_support::TempDir dir("cli_input");
  const std::string out = " --out " + dir.file("g");
  expect_refused("leg-geometry --spacing -1" + out, "--spacing: must be in (0, inf] (m); got -1");
  expect_refused("leg-geometry --spacing nan" + out, "--spacing: must be a finite number (m)");
  expect_refused("leg-geometry --stature 3" + out, "--stature: must be in [1.2, 2.3] (m); got 3");
  expect_refused("leg-geometry --mass nan" + out, "--mass: must be a finite number (kg)");
  expect_refused("leg-geometry --skin-cell 0" + out, "--skin-cell: must be in (0, inf]");
  expect_refused("leg-geometry --muscles bogus" + out, "--muscles: bogus not in {thesis,anatomical}");
  expect_refused("leg-geometry --muscles anatomical", "--muscles anatomical needs --out");  // not over the shipped leg
  EXPECT_FALSE(std::filesystem::exists(dir.file("g")));
  expect_refused("view " + dir.path().string() + " --max-frames 1", "--max-frames: must be in [2, 100000] (frames); got 1");
  expect_refused("serve --seconds nan", "--seconds: must be a finite number (wall seconds)");
  expect_refused("serve --port 70000", "--port: must be in [0, 65535] (a TCP port); got 70000");
  expect_refused("serve --threads 0", "--threads: must be in [1, 256] (threads); got 0");
}
