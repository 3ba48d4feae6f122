// Strict YAML reading (tbio/yaml_fields.hpp): a repeated key is refused at any
// depth with both places named (yaml-cpp would keep the first and never check
// the second), syntax errors name the line, and files go through the input
// size cap.
#include "tbio/yaml_fields.hpp"

#include "msd/core/types.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

std::string error_of(const std::string& text) {
  try {
    tbio::parse_yaml(text, "s.yaml");
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(YamlFields, ARepeatedKeyIsRefusedWithBothLines) {
  EXPECT_EQ(error_of("a: 1\nb: 2\n"), "");
  const std::string top = error_of("name: x\ndt: 1.0e-4\nloading: {}\ndt: -5\n");
  EXPECT_EQ(top, "s.yaml:4:1: duplicate key 'dt' (first given at line 2)") << top;
}

TEST(YamlFields, ARepeatedKeyIsFoundInNestedMappingsFlowStyleAndListItems) {
  EXPECT_NE(error_of("msd:\n  dt: 1\n  k_s: 2\n  dt: 3\n").find("s.yaml:4:3: duplicate key 'dt' (first given at line 2)"),
            std::string::npos) << error_of("msd:\n  dt: 1\n  k_s: 2\n  dt: 3\n");
  EXPECT_NE(error_of("mesh: {spacing: 0.01, spacing: 0.02}\n").find("duplicate key 'spacing'"), std::string::npos);
  EXPECT_NE(error_of("variants:\n  - {name: a, name: b}\n").find("s.yaml:2:15: duplicate key 'name'"), std::string::npos)
      << error_of("variants:\n  - {name: a, name: b}\n");
  // The same key in two different mappings is not a repeat.
  EXPECT_EQ(error_of("a: {x: 1}\nb: {x: 2}\nc: [{x: 1}, {x: 2}]\n"), "");
}

TEST(YamlFields, SyntaxErrorsNameTheLine) {
  EXPECT_NE(error_of("a: [1, 2\nb: 3\n").find("s.yaml:"), std::string::npos);
  EXPECT_NE(error_of("a: [1, 2\nb: 3\n").find("YAML syntax error"), std::string::npos);
}

TEST(YamlFields, LoadingAFileRefusesDevicesAndRepeatsAndNamesTheFile) {
  testing_support::TempDir dir("yaml_fields");
  std::filesystem::create_symlink("/dev/zero", dir.file("zero.yaml"));
  try {
    tbio::load_yaml_file(dir.file("zero.yaml"), "scene file");
    FAIL() << "/dev/zero was read";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("zero.yaml: the scene file is not a regular file"), std::string::npos) << e.what();
  }
  std::ofstream(dir.file("twice.yaml")) << "duration: 1\nduration: nan\n";
  try {
    tbio::load_yaml_file(dir.file("twice.yaml"), "scene file");
    FAIL() << "a repeated key was read";
  } catch (const msd::Error& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("twice.yaml") + ":2:1: duplicate key 'duration' (first given at line 1)");
  }
}
