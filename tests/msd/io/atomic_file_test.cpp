// Whole-or-nothing writing: a finished write replaces the file; a write that
// throws or cannot open leaves the old file untouched and no temporary behind.
#include "msd/io/atomic_file.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <csignal>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using testing_support::read_text;

std::string folder(const std::string& name) {
  const fs::path d = fs::path(TB_TEST_OUTPUT_DIR) / "atomic_file_test" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

}  // namespace

TEST(AtomicFile, AFinishedWriteReplacesTheFileAndLeavesNoTemporary) {
  const std::string path = folder("finished") + "/out.txt";
  std::ofstream(path) << "old";
  msd::write_file_atomically(path, [](std::ostream& out) { out << "new\n"; });
  EXPECT_EQ(read_text(path), "new\n");
  EXPECT_FALSE(fs::exists(msd::partial_path(path)));
}

TEST(AtomicFile, AWriteThatThrowsLeavesTheOldFileAndNoTemporary) {
  const std::string path = folder("throws") + "/out.txt";
  std::ofstream(path) << "old";
  EXPECT_THROW(msd::write_file_atomically(path,
                                          [](std::ostream& out) {
                                            out << "half";
                                            throw std::runtime_error("stopped half-way");
                                          }),
               std::runtime_error);
  EXPECT_EQ(read_text(path), "old");
  EXPECT_FALSE(fs::exists(msd::partial_path(path)));
}

TEST(AtomicFile, AnUnwritableFolderIsAnErrorNamingThePath) {
  const std::string path = folder("missing") + "/no/such/folder/out.txt";
  try {
    msd::write_file_atomically(path, [](std::ostream& out) { out << "x"; });
    ADD_FAILURE() << "wrote into a folder that does not exist";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": cannot write"), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, AFullDiskIsAWriteFailureAndLeavesTheOldFileAndNoTemporary) {
  // A file size limit makes writes fail with EFBIG, as a full disk does (ENOSPC).
  const std::string path = folder("full") + "/out.txt";
  std::ofstream(path) << "old";
  struct rlimit old {};
  getrlimit(RLIMIT_FSIZE, &old);
  const auto previous = signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = old;
  small.rlim_cur = 4096;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string message;
  try {
    msd::write_file_atomically(path, [](std::ostream& out) { out << std::string(1 << 20, 'x'); });
  } catch (const msd::Error& e) {
    message = e.what();
  }
  setrlimit(RLIMIT_FSIZE, &old);
  signal(SIGXFSZ, previous);
  EXPECT_NE(message.find(path + ": write failed"), std::string::npos) << message;
  EXPECT_EQ(read_text(path), "old");
  EXPECT_FALSE(fs::exists(msd::partial_path(path)));
}

TEST(AtomicFile, TheTemporaryIsUniqueToTheProcessAndALeftoverIsReplaced) {
  const std::string path = folder("unique") + "/out.txt";
  EXPECT_EQ(msd::partial_path(path), path + ".partial-" + std::to_string(getpid()));
  // A leftover of a dead process that had our pid (a symbolic link, even) is
  // replaced, never written through.
  const std::string target = folder("unique_target") + "/victim.txt";
  std::ofstream(target) << "victim";
  fs::create_symlink(target, msd::partial_path(path));
  msd::write_file_atomically(path, [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(read_text(path), "new");
  EXPECT_EQ(read_text(target), "victim");
  // Two processes writing the same file at once each write their own temporary.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    for (int i = 0; i < 200; ++i) msd::write_file_atomically(path, [](std::ostream& out) { out << std::string(5000, 'c'); });
    _exit(0);
  }
  for (int i = 0; i < 200; ++i) msd::write_file_atomically(path, [](std::ostream& out) { out << std::string(5000, 'p'); });
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const std::string text = read_text(path);
  EXPECT_TRUE(text == std::string(5000, 'c') || text == std::string(5000, 'p')) << "a mixed file of " << text.size();
}
