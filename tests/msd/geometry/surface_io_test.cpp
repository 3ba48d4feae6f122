// STL and PLY input: each format round-trips a closed box (corners welded, so
// the surface validates and encloses the box's volume), and malformed files are
// refused with the file and the line, triangle or element named.
#include "msd/geometry/triangle_mesh.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>

namespace {

const msd::TriangleMesh kBox = msd::make_box(msd::Vec3(0, 0, 0), msd::Vec3(0.02, 0.03, 0.05));
const double kVolume = 0.02 * 0.03 * 0.05;

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string ascii_stl(const msd::TriangleMesh& m) {
  std::ostringstream s;
  s.precision(17);
  s << "solid box\n";
  for (const auto& t : m.triangles) {
    s << "  facet normal 0 0 0\n    outer loop\n";
    for (int k : t) s << "      vertex " << m.vertices(0, k) << ' ' << m.vertices(1, k) << ' ' << m.vertices(2, k) << '\n';
    s << "    endloop\n  endfacet\n";
  }
  s << "endsolid box\n";
  return s.str();
}

template <typename T>
void put(std::string& out, T v, bool big_endian = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

std::string binary_stl(const msd::TriangleMesh& m) {
  std::string s(80, ' ');
  put<std::uint32_t>(s, static_cast<std::uint32_t>(m.triangles.size()));
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) put<float>(s, 0.0f);
    for (int k : t)
      for (int d = 0; d < 3; ++d) put<float>(s, static_cast<float>(m.vertices(d, k)));
    put<std::uint16_t>(s, 0);
  }
  return s;
}

std::string ply(const msd::TriangleMesh& m, const std::string& format) {
  std::ostringstream h;
  h << "ply\nformat " << format << " 1.0\ncomment made by a test\nelement vertex " << m.num_vertices()
    << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty double nz\n"
    << "element face " << m.num_triangles() << "\nproperty list uchar int vertex_indices\nend_header\n";
  std::string s = h.str();
  const bool big = format == "binary_big_endian";
  if (format == "ascii") {
    std::ostringstream b;
    b.precision(9);
    for (int i = 0; i < m.num_vertices(); ++i)
      b << m.vertices(0, i) << ' ' << m.vertices(1, i) << ' ' << m.vertices(2, i) << " 255 0.5\n";
    for (const auto& t : m.triangles) b << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    return s + b.str();
  }
  for (int i = 0; i < m.num_vertices(); ++i) {
    for (int d = 0; d < 3; ++d) put<float>(s, static_cast<float>(m.vertices(d, i)), big);
    put<std::uint8_t>(s, 255);
    put<double>(s, 0.5, big);
  }
  for (const auto& t : m.triangles) {
    put<std::uint8_t>(s, 3);
    for (int k : t) put<std::int32_t>(s, k, big);
  }
  return s;
}

std::string error_of(const std::string& path) {
  try {
    msd::read_surface(path);
  } catch (const msd::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SurfaceIo, EveryFormatReadsAClosedBox) {
  testing_support::TempDir dir("surface_io");
  write_text(dir.file("ascii.stl"), ascii_stl(kBox));
  write_text(dir.file("binary.STL"), binary_stl(kBox));
  write_text(dir.file("ascii.ply"), ply(kBox, "ascii"));
  write_text(dir.file("le.ply"), ply(kBox, "binary_little_endian"));
  write_text(dir.file("be.ply"), ply(kBox, "binary_big_endian"));
  msd::write_obj(dir.file("box.obj"), kBox);
  for (const char* f : {"ascii.stl", "binary.STL", "ascii.ply", "le.ply", "be.ply", "box.obj"}) {
    const msd::TriangleMesh m = msd::read_surface(dir.file(f));
    EXPECT_EQ(m.num_vertices(), 8) << f << ": STL corners are welded into shared vertices";
    EXPECT_EQ(m.num_triangles(), 12) << f;
    EXPECT_NO_THROW(msd::validate_closed_surface(m, f));
    EXPECT_NEAR(msd::enclosed_volume(m), kVolume, 1e-6 * kVolume) << f;
  }
}

TEST(SurfaceIo, MalformedFilesNameTheFileAndThePlace) {
  testing_support::TempDir dir("surface_io");
  // ASCII STL with a two-corner facet: the line of its endfacet.
  write_text(dir.file("short.stl"),
             "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n");
  EXPECT_NE(error_of(dir.file("short.stl")).find("short.stl:7: facet has 2 vertices"), std::string::npos)
      << error_of(dir.file("short.stl"));
  write_text(dir.file("word.stl"), "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 zero 0\n");
  EXPECT_NE(error_of(dir.file("word.stl")).find("word.stl:4: vertex needs three numbers"), std::string::npos);
  // A binary STL cut short is neither a binary STL of its stated size nor ASCII.
  std::string cut = binary_stl(kBox);
  cut.resize(cut.size() - 20);
  write_text(dir.file("cut.stl"), cut);
  EXPECT_NE(error_of(dir.file("cut.stl")).find("not an STL file"), std::string::npos) << error_of(dir.file("cut.stl"));
  // PLY: an unknown property type names its header line.
  write_text(dir.file("type.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n");
  EXPECT_NE(error_of(dir.file("type.ply")).find("type.ply:4: unknown property type 'quad'"), std::string::npos)
      << error_of(dir.file("type.ply"));
  // A face that refers past the vertices.
  std::string bad = ply(kBox, "ascii");
  {  // the last face's first index becomes 99 ("3 a b c" -> "3 99 b c")
    const size_t at = bad.rfind("\n3 ") + 3;
    bad.replace(at, bad.find(' ', at) - at, "99");
  }
  write_text(dir.file("index.ply"), bad);
  EXPECT_NE(error_of(dir.file("index.ply")).find("refers to vertex 99"), std::string::npos) << error_of(dir.file("index.ply"));
  // A binary PLY that ends early names the element.
  std::string early = ply(kBox, "binary_little_endian");
  early.resize(early.size() - 30);
  write_text(dir.file("early.ply"), early);
  EXPECT_NE(error_of(dir.file("early.ply")).find("face "), std::string::npos) << error_of(dir.file("early.ply"));
  EXPECT_NE(error_of(dir.file("early.ply")).find("ends early"), std::string::npos);
  write_text(dir.file("noend.ply"), "ply\nformat ascii 1.0\nelement vertex 0\n");
  EXPECT_NE(error_of(dir.file("noend.ply")).find("no 'end_header'"), std::string::npos);
  EXPECT_NE(error_of(dir.file("leg.fbx")).find("unknown surface format '.fbx'"), std::string::npos);
  EXPECT_NE(error_of(dir.file("absent.stl")).find("absent.stl: cannot read the STL file"), std::string::npos)
      << error_of(dir.file("absent.stl"));
}

TEST(SurfaceIo, APlyWhoseHeaderCountsDoNotMatchItsDataSaysSoAtTheLine) {
  testing_support::TempDir dir("surface_io");
  const std::string good = ply(kBox, "ascii");  // 8 vertices, 12 faces; the header ends on line 12
  ASSERT_NE(good.find("element vertex 8\n"), std::string::npos);
  ASSERT_NE(good.find("element face 12\n"), std::string::npos);
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  // One face more in the header than in the file: the file ends first.
  write_text(dir.file("more.ply"), with("element face 12\n", "element face 13\n"));
  const std::string more = error_of(dir.file("more.ply"));
  EXPECT_NE(more.find("more.ply: the file ends after line 32, before face 13 of 13"), std::string::npos) << more;
  EXPECT_NE(more.find("the header's element counts do not match the file"), std::string::npos) << more;
  // One face fewer: the last line is data after the last element.
  write_text(dir.file("fewer.ply"), with("element face 12\n", "element face 11\n"));
  const std::string fewer = error_of(dir.file("fewer.ply"));
  EXPECT_NE(fewer.find("fewer.ply:32: data after the last element"), std::string::npos) << fewer;
  // One vertex fewer: the eighth vertex's line is read as the first face.
  write_text(dir.file("shifted.ply"), with("element vertex 8\n", "element vertex 7\n"));
  const std::string shifted = error_of(dir.file("shifted.ply"));
  EXPECT_NE(shifted.find("shifted.ply:20: face 1 of 12"), std::string::npos) << shifted;
  EXPECT_NE(shifted.find("the header's element counts do not match the file"), std::string::npos) << shifted;
  // A face with an index past the vertices names its line.
  std::string past = good;
  past.replace(past.rfind("\n3 ") + 3, 1, "9");
  write_text(dir.file("past.ply"), past);
  EXPECT_NE(error_of(dir.file("past.ply")).find("past.ply:32: PLY face refers to vertex 9"), std::string::npos)
      << error_of(dir.file("past.ply"));
}

TEST(SurfaceIo, SurfaceErrorsCountFromOneAndNameTheFileLine) {
  testing_support::TempDir dir("surface_io");
  msd::TriangleMesh open = kBox;
  open.triangles.pop_back();
  msd::write_obj(dir.file("open.obj"), open);
  const msd::TriangleMesh m = msd::read_surface(dir.file("open.obj"));
  ASSERT_EQ(m.triangle_line.size(), m.triangles.size());
  try {
    msd::validate_closed_surface(m, dir.file("open.obj"));
    FAIL() << "an open surface validated";
  } catch (const msd::Error& e) {
    // The open edge belongs to some triangle: its message names the OBJ line
    // of that face ("open.obj:LINE: triangle T"), T counted from 1.
    const std::string w = e.what();
    const size_t at = w.find("open.obj:");
    ASSERT_NE(at, std::string::npos) << w;
    const int line = std::stoi(w.substr(at + 9));
    const size_t tri = w.find(": triangle ");
    ASSERT_NE(tri, std::string::npos) << w;
    const int t = std::stoi(w.substr(tri + 11));
    ASSERT_GE(t, 1);
    ASSERT_LE(t, m.num_triangles());
    EXPECT_EQ(line, m.triangle_line[static_cast<size_t>(t - 1)]) << w;
    const std::string text = testing_support::read_text(dir.file("open.obj"));
    std::istringstream lines(text);
    std::string l;
    for (int k = 0; k < line; ++k) std::getline(lines, l);
    EXPECT_EQ(l.substr(0, 2), "f ") << "line " << line << " of open.obj is '" << l << "'";
  }
}

TEST(SurfaceIo, AnOpenOrFlippedUserSurfaceFailsValidationByName) {
  testing_support::TempDir dir("surface_io");
  msd::TriangleMesh open = kBox;
  open.triangles.pop_back();
  write_text(dir.file("open.stl"), ascii_stl(open));
  const msd::TriangleMesh m = msd::read_surface(dir.file("open.stl"));
  try {
    msd::validate_closed_surface(m, "skin (open.stl)");
    FAIL() << "an open surface validated";
  } catch (const msd::Error& e) {
    // "skin (open.stl):LINE: triangle T: the surface is open: ..." (the facet's line).
    EXPECT_NE(std::string(e.what()).find("skin (open.stl):"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(": the surface is open: its edge from vertex"), std::string::npos) << e.what();
  }
  msd::TriangleMesh flipped = kBox;
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  write_text(dir.file("flipped.ply"), ply(flipped, "ascii"));
  EXPECT_THROW(msd::validate_closed_surface(msd::read_surface(dir.file("flipped.ply")), "femur"), msd::Error);
}
