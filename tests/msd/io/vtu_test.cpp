// VTU output: counts, connectivity, offsets, types and data arrays as ParaView
// reads them; bad grids are refused before anything is written.
#include "msd/io/vtu.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

using testing_support::read_text;

// The whitespace-separated values of the DataArray called `name`.
std::vector<double> array(const std::string& text, const std::string& name) {
  const size_t at = text.find("Name=\"" + name + "\"");
  EXPECT_NE(at, std::string::npos) << name;
  const size_t begin = text.find('>', at) + 1, end = text.find("</DataArray>", begin);
  std::istringstream in(text.substr(begin, end - begin));
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

msd::VtuGrid mixed() {
  msd::VtuGrid g;
  g.points.resize(3, 5);
  g.points << 0, 1, 0, 0, 1,  //
      0, 0, 1, 0, 1,          //
      0, 0, 0, 1, 1;
  g.cells = {{0, 1, 2, 3}, {1, 2, 3, 4}, {0, 4}, {2}};
  g.types = {msd::kVtkTetra, msd::kVtkTetra, msd::kVtkPolyLine, msd::kVtkVertex};
  g.cell_data["region"] = {0, 3, -1, -1};
  g.point_data["bone_point"] = {0, 0, 1, 0, 0};
  return g;
}

}  // namespace

TEST(Vtu, WritesCellsOffsetsTypesAndData) {
  testing_support::TempDir dir("vtu");
  msd::write_vtu(dir.file("m.vtu"), mixed());
  const std::string t = read_text(dir.file("m.vtu"));
  EXPECT_NE(t.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(t.find("NumberOfPoints=\"5\" NumberOfCells=\"4\""), std::string::npos);
  EXPECT_EQ(array(t, "connectivity"), (std::vector<double>{0, 1, 2, 3, 1, 2, 3, 4, 0, 4, 2}));
  EXPECT_EQ(array(t, "offsets"), (std::vector<double>{4, 8, 10, 11}));
  EXPECT_EQ(array(t, "types"), (std::vector<double>{10, 10, 4, 1}));
  EXPECT_EQ(array(t, "region"), (std::vector<double>{0, 3, -1, -1}));
  EXPECT_EQ(array(t, "bone_point"), (std::vector<double>{0, 0, 1, 0, 0}));
  const auto p = array(t, "Points");
  ASSERT_EQ(p.size(), 15u);
  EXPECT_EQ(p[12], 1.0);  // point 4 = (1, 1, 1), stored x y z per point
  EXPECT_FALSE(std::filesystem::exists(dir.file("m.vtu.partial")));
}

TEST(Vtu, BadGridsAreRefusedAndWriteNothing) {
  testing_support::TempDir dir("vtu");
  auto g = mixed();
  g.cells[1][3] = 7;
  try {
    msd::write_vtu(dir.file("bad.vtu"), g);
    FAIL();
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("cell 1 refers to point 7"), std::string::npos) << e.what();
  }
  g = mixed();
  g.cell_data["region"].pop_back();
  EXPECT_THROW(msd::write_vtu(dir.file("bad.vtu"), g), msd::Error);
  g = mixed();
  g.types.pop_back();
  EXPECT_THROW(msd::write_vtu(dir.file("bad.vtu"), g), msd::Error);
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.vtu")));
}
