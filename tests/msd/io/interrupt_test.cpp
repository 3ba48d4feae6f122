// SIGINT/SIGTERM: inside an interruptible section the signal is a flag the
// loop polls; elsewhere the handler removes the registered temporaries and
// ends the process with 128 + N.
#include "msd/io/interrupt.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace {

std::string folder(const std::string& name) {
  const fs::path d = fs::path(TB_TEST_OUTPUT_DIR) / "interrupt_test" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

template <typename F>
int in_child(F&& f) {
  const pid_t pid = fork();
  if (pid == 0) _exit(f());
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

TEST(Interrupt, OutsideALoopTheTemporariesAreRemovedAndTheCodeIs128PlusN) {
  const std::string dir = folder("outside");
  const std::string tmp = dir + "/mesh.vtu.partial-1", other = dir + "/kept.txt";
  for (int sig : {SIGINT, SIGTERM}) {
    std::ofstream(tmp) << "half";
    std::ofstream(other) << "not registered";
    const int code = in_child([&] {
      msd::install_interrupt_handlers();
      const msd::RegisteredTemporary r(tmp);
      raise(sig);
      return 0;  // not reached
    });
    EXPECT_EQ(code, 128 + sig);
    EXPECT_FALSE(fs::exists(tmp));
    EXPECT_TRUE(fs::exists(other));
  }
  EXPECT_EQ(msd::interrupted_exit_code(SIGINT), 130);
  EXPECT_EQ(msd::interrupted_exit_code(SIGTERM), 143);
}

TEST(Interrupt, InsideALoopTheSignalIsAFlagAndASecondOneEndsTheProcess) {
  const std::string dir = folder("inside");
  const std::string tmp = dir + "/r.h5.partial-1";
  std::ofstream(tmp) << "rows";
  const int code = in_child([&] {
    msd::install_interrupt_handlers();
    const msd::RegisteredTemporary r(tmp);
    const msd::InterruptibleSection loop;
    raise(SIGINT);
    if (msd::interrupt_signal() != SIGINT) return 3;
    try {
      msd::throw_if_interrupted(0.25, 2500);
      return 4;
    } catch (const msd::Interrupted& e) {
      if (e.signal != SIGINT || std::string(e.what()).find("interrupted by signal 2 (SIGINT) at t = 0.25") != 0)
        return 5;
    }
    if (!fs::exists(tmp)) return 6;
    raise(SIGTERM);  // a second signal: at once
    return 7;
  });
  EXPECT_EQ(code, 128 + SIGTERM);
  EXPECT_FALSE(fs::exists(tmp));
}
