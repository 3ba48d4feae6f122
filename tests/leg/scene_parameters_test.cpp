// Tests for leg/src/scene_parameters.cpp: every scene field declared once,
// the docs' table generated from the declarations, the reader using them.
#include "leg/scene.hpp"

#include "msd/core/types.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(LegSceneParameters, EachPathIsDeclaredOnceWithADocAndADefaultInItsRange) {
  std::set<std::string> seen;
  for (const tbio::Parameter& p : leg::leg_scene_parameters()) {
    SCOPED_TRACE(p.path);
    EXPECT_TRUE(seen.insert(p.path).second) << "declared twice";
    EXPECT_FALSE(p.doc.empty());
    if ((p.kind == tbio::Kind::Number || p.kind == tbio::Kind::Integer) && p.fallback) {
      EXPECT_TRUE(p.range.contains(*p.fallback)) << *p.fallback << " outside " << p.range.text();
    }
  }
  EXPECT_THROW(leg::leg_scene_parameter("knee.dampign"), std::logic_error);
}

TEST(LegSceneParameters, TheDocsFieldTableIsTheGeneratedOne) {
  const std::string expected = tbio::markdown_table(leg::leg_scene_parameters());
  const std::string doc = read(std::string(TISSUEBENCH_SOURCE_DIR) + "/docs/leg-scenes.md");
  const std::string begin = "<!-- fields:begin (generated from leg/src/scene_parameters.cpp) -->\n",
                    end = "<!-- fields:end -->";
  const size_t a = doc.find(begin), b = doc.find(end);
  ASSERT_NE(a, std::string::npos) << "docs/leg-scenes.md has no field table markers";
  ASSERT_NE(b, std::string::npos);
  const std::string table = doc.substr(a + begin.size(), b - a - begin.size());
  if (table != expected) {
    const std::string out = std::string(TB_TEST_OUTPUT_DIR) + "/leg_scene_fields.md";
    std::ofstream(out) << expected;
    ADD_FAILURE() << "docs/leg-scenes.md's field table differs from the declarations; the generated one is in " << out;
  }
}

TEST(LegSceneParameters, AValueOutsideItsDeclaredRangeNamesFieldRangeAndUnit) {
  const std::string dir = std::string(TB_TEST_OUTPUT_DIR) + "/leg_scene_parameters";
  std::filesystem::create_directories(dir);
  std::string text = read(std::string(TISSUEBENCH_DATA_DIR) + "/scenes/drop.yaml");
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
