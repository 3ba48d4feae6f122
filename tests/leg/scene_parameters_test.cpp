// Tests for leg/src/scene_parameters.cpp: every scene field declared once,
// the docs' table generated from the declarations, the reader using them.
#include "leg/scene.hpp"

#include "msd/core/types.hpp"
#include "parameter_checks.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

using testing_support::read_text;

}  // namespace

TEST(LegSceneParameters, EachPathIsDeclaredOnceWithADocAndADefaultInItsRange) {
  EXPECT_GE(testing_support::expect_well_declared(leg::leg_scene_parameters()), 50u);
  EXPECT_THROW(leg::leg_scene_parameter("knee.dampign"), std::logic_error);
}

TEST(LegSceneParameters, TheDocsFieldTableIsTheGeneratedOne) {
  testing_support::expect_docs_table("docs/leg-scenes.md", "leg/src/scene_parameters.cpp", leg::leg_scene_parameters(),
                                     "leg_scene_fields.md");
}

TEST(LegSceneParameters, AValueOutsideItsDeclaredRangeNamesFieldRangeAndUnit) {
  const std::string dir = std::string(TB_TEST_OUTPUT_DIR) + "/leg_scene_parameters";
  std::filesystem::create_directories(dir);
  std::string text = read_text(std::string(TISSUEBENCH_DATA_DIR) + "/scenes/drop.yaml");
  const size_t at = text.find("dt: 2.0e-4");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 10, "dt: -1.0e-4");
  std::ofstream(dir + "/negative_dt.yaml") << text;
  try {
    leg::read_leg_scene(dir + "/negative_dt.yaml");
    ADD_FAILURE() << "a negative dt was accepted";
  } catch (const msd::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("negative_dt.yaml:"), std::string::npos) << m;
    EXPECT_NE(m.find("dt: must lie in (0, inf) s, got -0.0001"), std::string::npos) << m;
  }
}
