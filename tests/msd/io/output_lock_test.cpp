// One writer per output: a second lock on the same output is refused naming
// the holder; a released lock leaves no lock file. And --out naming an input
// (by path, symbolic or hard link) is refused.
#include "msd/io/output_lock.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace {

std::string folder(const std::string& name) {
  const fs::path d = fs::path(TB_TEST_OUTPUT_DIR) / "output_lock_test" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

// Runs `f` in a child process; returns its exit code.
template <typename F>
int in_child(F&& f) {
  const pid_t pid = fork();
  if (pid == 0) _exit(f());
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

TEST(OutputLock, ASecondWriterIsRefusedNamingTheFirst) {
  const std::string out = folder("second") + "/r.h5";
  {
    const msd::OutputLock first(out, "tissuebench run first.yaml");
    EXPECT_TRUE(fs::exists(out + ".lock"));
    const int code = in_child([&] {
      try {
        const msd::OutputLock second(out, "second");
        return 0;
      } catch (const msd::Error& e) {
        const std::string m = e.what();
        const bool named = m.find("pid " + std::to_string(getppid())) != std::string::npos &&
                           m.find("tissuebench run first.yaml") != std::string::npos &&
                           m.find(out + ": another run is writing it") == 0;
        return named ? 7 : 8;
      }
    });
    EXPECT_EQ(code, 7);
  }
  EXPECT_FALSE(fs::exists(out + ".lock"));  // released: removed
  EXPECT_EQ(in_child([&] {
              const msd::OutputLock again(out, "again");
              return 0;
            }),
            0);
}

TEST(OutputLock, AnOutputNamingAnInputIsRefused) {
  const std::string dir = folder("inputs");
  std::ofstream(dir + "/spec.yaml") << "name: x\n";
  try {
    msd::refuse_output_over_inputs("--out", {dir + "/./spec.yaml"}, {dir + "/spec.yaml"});
    ADD_FAILURE() << "--out = the spec was accepted";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("--out: the run would write"), std::string::npos) << e.what();
  }
  fs::create_symlink(dir + "/spec.yaml", dir + "/link.yaml");
  EXPECT_THROW(msd::refuse_output_over_inputs("--out", {dir + "/link.yaml"}, {dir + "/spec.yaml"}), msd::Error);
  fs::create_hard_link(dir + "/spec.yaml", dir + "/hard.yaml");
  EXPECT_THROW(msd::refuse_output_over_inputs("--out", {dir + "/hard.yaml"}, {dir + "/spec.yaml"}), msd::Error);
  EXPECT_NO_THROW(msd::refuse_output_over_inputs("--out", {dir + "/out.h5", ""}, {dir + "/spec.yaml", ""}));
}
