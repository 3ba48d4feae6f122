// Every input the fuzzers found a defect with (tests/fuzz/regressions/TARGET/,
// docs/fuzzing.md), replayed through the same target body the libFuzzer
// programs run (fuzz_targets.cpp): after the fix each is read or refused with
// one message. In the sanitizer build (.ci/run) a memory or UB defect aborts.
#include "fuzz_targets.hpp"

#include "msd/core/types.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace {

const fs::path kRegressions = fs::path(TISSUEBENCH_SOURCE_DIR) / "tests/fuzz/regressions";

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string run(const tbfuzz::Target& t, const std::string& bytes) {
  return tbfuzz::run_target(t, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace

TEST(FuzzRegressions, EveryKeptInputIsReadOrRefusedWithAMessage) {
  ASSERT_TRUE(fs::is_directory(kRegressions)) << kRegressions;
  int replayed = 0;
  for (const auto& dir : fs::directory_iterator(kRegressions)) {
    if (!dir.is_directory()) continue;
    const tbfuzz::Target* t = tbfuzz::find_target(dir.path().filename().string());
    ASSERT_NE(t, nullptr) << dir.path() << " names no fuzz target";
    for (const auto& f : fs::directory_iterator(dir.path())) {
      if (!f.is_regular_file() || f.path().filename() == "README.md") continue;
      EXPECT_EQ(run(*t, bytes_of(f.path())), "") << f.path();
      ++replayed;
    }
  }
  EXPECT_GT(replayed, 0) << "no regression inputs under " << kRegressions;
}

TEST(FuzzRegressions, TheBodyTellsARefusalFromAnEscapedException) {
  // Negative controls: the verdict the fuzzer aborts on must see an escaped
  // exception that is not msd::Error, and accept a refusal.
  const tbfuzz::Target refuses{"refuses", "", [](const std::string&) -> std::string { throw msd::Error("x: bad"); }};
  const tbfuzz::Target leaks{"leaks", "", [](const std::string&) -> std::string { throw std::out_of_range("map::at"); }};
  EXPECT_EQ(run(refuses, "a"), "");
  EXPECT_NE(run(leaks, "a").find("map::at"), std::string::npos);
}

TEST(FuzzRegressions, EveryTargetReadsItsOwnKindOfShippedFile) {
  // The bodies reach the readers: a shipped file of each kind is read, and
  // a broken one refused (each a spot check; the seeds are scripts/fuzz.sh's).
  const fs::path src(TISSUEBENCH_SOURCE_DIR);
  const std::map<std::string, fs::path> shipped{
      {"spec", src / "benchmarks/specs/uniaxial.yaml"},
      {"calibration", src / "benchmarks/calibration/passive_muscle.yaml"},
      {"baseline", src / "reports/baselines/quick.yaml"},
      {"activation_script", src / "msd/data/scripts/hamstrings.txt"},
      {"leg_scene", src / "msd/data/scenes/hamstrings.yaml"},
      {"mesh_scene", src / "msd/data/leg/leg.yaml"},
      {"obj", src / "tests/fuzz/seeds/obj/cube.obj"},
      {"stl", src / "tests/fuzz/seeds/stl/cube_binary.stl"},
      {"ply", src / "tests/fuzz/seeds/ply/cube_binary_be.ply"}};
  ASSERT_EQ(shipped.size(), tbfuzz::targets().size());
  for (const auto& t : tbfuzz::targets()) {
    const std::string bytes = bytes_of(shipped.at(t.name));
    ASSERT_FALSE(bytes.empty()) << shipped.at(t.name);
    EXPECT_NO_THROW(t.run(bytes)) << t.name << " refused " << shipped.at(t.name);
    // Cut a third of the way in, then junk - also on a line of its own (the cut may end in a comment).
    const std::string junk = "\x01\x02 [{";
    EXPECT_THROW(t.run(bytes.substr(0, bytes.size() / 3) + junk + "\n" + junk), msd::Error) << t.name;
  }
}
