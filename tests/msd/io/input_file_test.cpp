// Input files are read whole with a size cap; devices, pipes and folders are
// refused by name before a byte is read (msd/io/input_file.hpp).
#include "msd/io/input_file.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>

namespace {

std::string error_of(const std::string& path, std::uint64_t cap = msd::kMaxTextInputBytes) {
  try {
    msd::read_input_file(path, "spec file", cap);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(InputFile, ReadsAWholeFileWithItsBytes) {
  testing_support::TempDir dir("input_file");
  const std::string text = std::string("name: x\n\0binary\r\n", 17) + std::string(5000, 'y');
  std::ofstream(dir.file("a.yaml"), std::ios::binary) << text;
  EXPECT_EQ(msd::read_input_file(dir.file("a.yaml"), "spec file"), text);
}

TEST(InputFile, RefusesMissingFilesFoldersDevicesAndPipesByName) {
  testing_support::TempDir dir("input_file");
  EXPECT_NE(error_of(dir.file("absent.yaml")).find("absent.yaml: cannot read the spec file"), std::string::npos)
      << error_of(dir.file("absent.yaml"));
  EXPECT_NE(error_of(dir.path().string()).find("is a folder"), std::string::npos) << error_of(dir.path().string());
  // A link to /dev/zero would be read until memory runs out.
  std::filesystem::create_symlink("/dev/zero", dir.file("zero.yaml"));
  EXPECT_NE(error_of(dir.file("zero.yaml")).find("zero.yaml: the spec file is not a regular file"), std::string::npos)
      << error_of(dir.file("zero.yaml"));
  // A FIFO would block: refused without opening it.
  ASSERT_EQ(::mkfifo(dir.file("fifo.yaml").c_str(), 0600), 0);
  EXPECT_NE(error_of(dir.file("fifo.yaml")).find("not a regular file"), std::string::npos) << error_of(dir.file("fifo.yaml"));
}

TEST(InputFile, RefusesAFileLargerThanTheCapWithBothSizes) {
  testing_support::TempDir dir("input_file");
  std::ofstream(dir.file("big.obj")) << std::string(1001, 'v');
  const std::string e = error_of(dir.file("big.obj"), 1000);
  EXPECT_NE(e.find("big.obj: the spec file is 1001 bytes, more than the limit of 1000 bytes"), std::string::npos) << e;
  EXPECT_EQ(error_of(dir.file("big.obj"), 1001), "");
}
