// Tests for io/src/parameter.cpp: ranges, reading through a declaration, the
// generated table.
#include "tbio/parameter.hpp"

#include "msd/core/types.hpp"

#include <gtest/gtest.h>

namespace {

tbio::Fields fields(const std::string& yaml) { return tbio::Fields(YAML::Load(yaml), "knee", "scene.yaml"); }

tbio::Parameter damping() {
  tbio::Parameter p;
  p.path = "knee.damping";
  p.unit = "N m s/rad";
  p.fallback = 0.5;
  p.range = tbio::Range::non_negative();
  p.doc = "viscous";
  return p;
}

std::string error(const std::function<void()>& f) {
  try {
    f();
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Range, EndsOpenClosedAndUnbounded) {
  EXPECT_FALSE(tbio::Range::positive().contains(0.0));
  EXPECT_TRUE(tbio::Range::non_negative().contains(0.0));
  EXPECT_TRUE(tbio::Range::closed(0, 1).contains(1.0));
  EXPECT_FALSE(tbio::Range::closed_open(0, 1).contains(1.0));
  EXPECT_FALSE(tbio::Range::any().contains(std::nan("")));
  EXPECT_FALSE(tbio::Range::any().contains(1.0 / 0.0));
  EXPECT_EQ(tbio::Range::positive().text(), "(0, inf)");
  EXPECT_EQ(tbio::Range::closed_open(0, 1).text(), "[0, 1)");
  EXPECT_EQ(tbio::Range::any().text(), "any");
}

TEST(Parameter, ReadsTheValueOrTheDefaultAndRefusesOutOfRangeNamingFieldRangeUnit) {
  EXPECT_EQ(tbio::read_number(fields("damping: 2.5"), damping()), 2.5);
  EXPECT_EQ(tbio::read_number(fields("centre: [0, 0, 1]"), damping()), 0.5);
  const std::string e = error([] { tbio::read_number(fields("damping: -1"), damping()); });
  EXPECT_NE(e.find("scene.yaml:1:10: knee.damping: must lie in [0, inf) N m s/rad, got -1"), std::string::npos) << e;
  tbio::Parameter required = damping();
  required.fallback.reset();
  EXPECT_NE(error([&] { tbio::read_number(fields("axis: [0, 1, 0]"), required); }).find("required field is missing"),
            std::string::npos);
}

TEST(Parameter, IntegersVectorsFlagsAndChoices) {
  tbio::Parameter every;
  every.path = "outputs.obj_every";
  every.kind = tbio::Kind::Integer;
  every.fallback = 1;
  every.range = tbio::Range::non_negative();
  EXPECT_EQ(tbio::read_integer(fields("obj_every: 3"), every), 3);
  EXPECT_EQ(tbio::read_integer(fields("x: 1"), every), 1);
  EXPECT_NE(error([&] { tbio::read_integer(fields("obj_every: -3"), every); }).find("got -3"), std::string::npos);
  tbio::Parameter axis;
  axis.path = "knee.axis";
  axis.kind = tbio::Kind::Vector3;
  axis.default_text = "[0, 1, 0]";
  axis.fallback3 = Eigen::Vector3d::UnitY();
  EXPECT_EQ(tbio::read_vector3(fields("x: 1"), axis), Eigen::Vector3d::UnitY());
  EXPECT_EQ(tbio::read_vector3(fields("axis: [1, 0, 0]"), axis), Eigen::Vector3d::UnitX());
  tbio::Parameter pull;
  pull.path = "mesh_pull";
  pull.kind = tbio::Kind::Flag;
  pull.fallback = 1.0;
  EXPECT_TRUE(tbio::read_flag(fields("x: 1"), pull));
  EXPECT_FALSE(tbio::read_flag(fields("mesh_pull: false"), pull));
  EXPECT_NE(error([&] { tbio::read_flag(fields("mesh_pull: maybe"), pull); }).find("true or false"), std::string::npos);
  tbio::Parameter ins;
  ins.path = "tendons.insertions";
  ins.kind = tbio::Kind::Choice;
  ins.choices = {"path", "nodes"};
  ins.default_text = "path";
  EXPECT_EQ(tbio::read_choice(fields("x: 1"), ins), "path");
  EXPECT_NE(error([&] { tbio::read_choice(fields("insertions: bones"), ins); }).find("'bones' is not one of: path, nodes"),
            std::string::npos);
}

TEST(Parameter, TheTableShowsFieldUnitDefaultRangeAndDoc) {
  const std::string t = tbio::markdown_table({damping()});
  EXPECT_EQ(t, "| field | unit | default | range | what |\n|---|---|---|---|---|\n"
               "| `knee.damping` | N m s/rad | 0.5 | [0, inf) | viscous |\n");
}
