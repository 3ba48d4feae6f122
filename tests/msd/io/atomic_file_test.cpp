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

TEST(AtomicFile, AFullDiskIsAWriteFailureAndLeavesNothing) {
  // /dev/full accepts the open and fails every write with ENOSPC.
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string dir = folder("full");
  const std::string path = dir + "/out.txt";
  fs::create_symlink("/dev/full", msd::partial_path(path));
  try {
    msd::write_file_atomically(path, [](std::ostream& out) { out << std::string(1 << 16, 'x'); });
    ADD_FAILURE() << "a write to a full device succeeded";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": write failed"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
}
