// STL and PLY input for user-supplied surfaces (a scanned limb, a segmented
// bone). OBJ lives beside the mesh type in triangle_mesh.cpp.
#include "msd/geometry/triangle_mesh.hpp"
#include "msd/io/input_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace msd {

namespace {

std::string at_line(const std::string& path, int line) { return path + ":" + std::to_string(line) + ": "; }

TriangleMesh from_lists(const std::vector<Vec3>& verts, std::vector<Tri> tris, std::vector<int> lines = {}) {
  TriangleMesh m;
  m.vertices.resize(3, static_cast<Eigen::Index>(verts.size()));
  for (size_t i = 0; i < verts.size(); ++i) m.vertices.col(static_cast<Eigen::Index>(i)) = verts[i];
  m.triangles = std::move(tris);
  m.triangle_line = std::move(lines);
  return m;
}

// Merges corners with identical coordinates (STL has no shared vertices).
class Welder {
 public:
  int add(const Vec3& p) {
    const auto [it, fresh] = ids_.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, static_cast<int>(verts_.size()));
    if (fresh) verts_.push_back(p);
    return it->second;
  }
  std::vector<Vec3>& vertices() { return verts_; }

 private:
  std::map<std::array<double, 3>, int> ids_;
  std::vector<Vec3> verts_;
};

}  // namespace

TriangleMesh read_stl(const std::string& path) {
  std::istringstream in(read_input_file(path, "STL file", kMaxSurfaceInputBytes), std::ios::binary);
  const auto size = static_cast<std::uint64_t>(in.str().size());
  char header[84] = {};
  in.read(header, 84);
  const bool have_header = in.gcount() == 84;
  std::uint32_t count = 0;
  if (have_header) std::memcpy(&count, header + 80, 4);
  Welder weld;
  std::vector<Tri> tris;
  std::vector<int> lines;  // ASCII: the line of each facet
  if (have_header && size == 84 + 50ull * count) {  // binary
    for (std::uint32_t t = 0; t < count; ++t) {
      char rec[50];
      in.read(rec, 50);
      if (in.gcount() != 50) throw Error(path + ": binary STL ends inside triangle " + std::to_string(t + 1));
      Tri tri;
      for (int k = 0; k < 3; ++k) {
        float xyz[3];
        std::memcpy(xyz, rec + 12 + 12 * k, 12);
        const Vec3 p(xyz[0], xyz[1], xyz[2]);
        if (!p.allFinite()) throw Error(path + ": binary STL triangle " + std::to_string(t + 1) + " has a non-finite vertex");
        tri[static_cast<size_t>(k)] = weld.add(p);
      }
      tris.push_back(tri);
    }
  } else {  // ASCII
    in.clear();
    in.seekg(0);
    std::string line, tag;
    int lineno = 0, corners = 0, facet_line = 0;
    Tri tri{};
    bool solid = false;
    while (std::getline(in, line)) {
      ++lineno;
      std::istringstream ls(line);
      if (!(ls >> tag)) continue;
      std::transform(tag.begin(), tag.end(), tag.begin(), [](unsigned char c) { return std::tolower(c); });
      if (tag == "solid") {
        solid = true;
      } else if (tag == "facet") {
        corners = 0;
        facet_line = lineno;
      } else if (tag == "vertex") {
        Vec3 p;
        if (!(ls >> p.x() >> p.y() >> p.z())) throw Error(at_line(path, lineno) + "vertex needs three numbers");
        if (!p.allFinite()) throw Error(at_line(path, lineno) + "vertex coordinate is not finite");
        if (corners == 3) throw Error(at_line(path, lineno) + "facet has more than three vertices");
        tri[static_cast<size_t>(corners++)] = weld.add(p);
      } else if (tag == "endfacet") {
        if (corners != 3) throw Error(at_line(path, lineno) + "facet has " + std::to_string(corners) + " vertices, not 3");
        tris.push_back(tri);
        lines.push_back(facet_line);
      } else if (!solid) {
        throw Error(path + ": not an STL file (neither binary of the size its header states nor ASCII starting with 'solid')");
      }
    }
    if (!solid) throw Error(path + ": not an STL file (empty)");
  }
  if (tris.empty()) throw Error(path + ": STL file has no triangles");
  return from_lists(weld.vertices(), std::move(tris), std::move(lines));
}

namespace {

struct PlyProperty {
  std::string name, type, count_type;  // count_type set for lists
  bool list = false;
};
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> props;
};

int type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

class PlyReader {
 public:
  PlyReader(std::istream& in, const std::string& path, int format) : in_(in), path_(path), format_(format) {}

  double read(const std::string& type, const std::string& what) {
    if (format_ == 0) {
      double v = 0;
      if (!(in_ >> v)) throw Error(path_ + ": " + what + ": expected a number");
      return v;
    }
    const int n = type_size(type);
    unsigned char b[8];
    in_.read(reinterpret_cast<char*>(b), n);
    if (in_.gcount() != n) throw Error(path_ + ": " + what + ": the file ends early");
    const bool host_little = [] {
      const std::uint16_t one = 1;
      unsigned char c;
      std::memcpy(&c, &one, 1);
      return c == 1;
    }();
    if ((format_ == 1) != host_little) std::reverse(b, b + n);
    auto get = [&](auto v) {
      std::memcpy(&v, b, sizeof v);
      return static_cast<double>(v);
    };
    if (type == "char" || type == "int8") return get(std::int8_t{});
    if (type == "uchar" || type == "uint8") return get(std::uint8_t{});
    if (type == "short" || type == "int16") return get(std::int16_t{});
    if (type == "ushort" || type == "uint16") return get(std::uint16_t{});
    if (type == "int" || type == "int32") return get(std::int32_t{});
    if (type == "uint" || type == "uint32") return get(std::uint32_t{});
    if (type == "float" || type == "float32") return get(float{});
    return get(double{});
  }

 private:
  std::istream& in_;
  std::string path_;
  int format_;  // 0 ascii, 1 little endian, 2 big endian
};

}  // namespace

TriangleMesh read_ply(const std::string& path) {
  std::istringstream in(read_input_file(path, "PLY file", kMaxSurfaceInputBytes), std::ios::binary);
  std::string line;
  int lineno = 0, format = -1;
  std::vector<PlyElement> elements;
  if (!std::getline(in, line) || line.substr(0, 3) != "ply") throw Error(at_line(path, 1) + "not a PLY file (no 'ply' line)");
  lineno = 1;
  for (;;) {
    if (!std::getline(in, line)) throw Error(path + ": PLY header has no 'end_header'");
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag == "comment" || tag == "obj_info") continue;
    if (tag == "end_header") break;
    if (tag == "format") {
      std::string f, version;
      ls >> f >> version;
      if (f == "ascii") format = 0;
      else if (f == "binary_little_endian") format = 1;
      else if (f == "binary_big_endian") format = 2;
      else throw Error(at_line(path, lineno) + "unknown PLY format '" + f + "'");
    } else if (tag == "element") {
      PlyElement e;
      if (!(ls >> e.name >> e.count) || e.count < 0) throw Error(at_line(path, lineno) + "element needs a name and a count");
      elements.push_back(e);
    } else if (tag == "property") {
      if (elements.empty()) throw Error(at_line(path, lineno) + "property before any element");
      PlyProperty p;
      std::string t;
      ls >> t;
      if (t == "list") {
        p.list = true;
        ls >> p.count_type >> p.type >> p.name;
        if (type_size(p.count_type) == 0 || type_size(p.type) == 0)
          throw Error(at_line(path, lineno) + "unknown list types '" + p.count_type + " " + p.type + "'");
      } else {
        p.type = t;
        ls >> p.name;
        if (type_size(p.type) == 0) throw Error(at_line(path, lineno) + "unknown property type '" + t + "'");
      }
      elements.back().props.push_back(p);
    } else {
      throw Error(at_line(path, lineno) + "unexpected header line '" + line + "'");
    }
  }
  if (format < 0) throw Error(path + ": PLY header has no 'format' line");
  // ASCII: one element per line, so a count in the header that does not match
  // the file is found at the line where it shows, not later as a bad index.
  int ascii_line = lineno;
  std::vector<Vec3> verts;
  std::vector<Tri> tris;
  std::vector<int> tri_lines;
  bool have_vertices = false, have_faces = false;
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int ix = -1, iy = -1, iz = -1, iface = -1;
    for (size_t k = 0; k < e.props.size(); ++k) {
      const auto& n = e.props[k].name;
      if (is_vertex && n == "x") ix = static_cast<int>(k);
      if (is_vertex && n == "y") iy = static_cast<int>(k);
      if (is_vertex && n == "z") iz = static_cast<int>(k);
      if (is_face && (n == "vertex_indices" || n == "vertex_index") && e.props[k].list) iface = static_cast<int>(k);
    }
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0)) throw Error(path + ": PLY vertex element lacks x, y or z");
    if (is_face && iface < 0) throw Error(path + ": PLY face element has no vertex_indices list");
    have_vertices |= is_vertex;
    have_faces |= is_face;
    for (long i = 0; i < e.count; ++i) {
      const std::string what = e.name + " " + std::to_string(i + 1) + " of " + std::to_string(e.count);
      std::istringstream line_in;
      if (format == 0) {
        std::string text;
        do {
          if (!std::getline(in, text))
            throw Error(path + ": the file ends after line " + std::to_string(ascii_line) + ", before " + what +
                        " that the header declares: the header's element counts do not match the file");
          ++ascii_line;
        } while (text.find_first_not_of(" \t\r") == std::string::npos);
        line_in.str(text);
      }
      PlyReader r(format == 0 ? static_cast<std::istream&>(line_in) : in,
                  format == 0 ? path + ":" + std::to_string(ascii_line) : path, format);
      Vec3 p = Vec3::Zero();
      std::vector<int> poly;
      for (size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& pr = e.props[k];
        if (pr.list) {
          const double n = r.read(pr.count_type, what);
          if (n < 0 || n != std::floor(n))
            throw Error((format == 0 ? at_line(path, ascii_line) : path + ": ") + what + ": bad list length " +
                        std::to_string(n) + " (if this is a line of another element, the header's element counts do "
                        "not match the file)");
          for (long j = 0; j < static_cast<long>(n); ++j) {
            const double v = r.read(pr.type, what);
            if (static_cast<int>(k) == iface) poly.push_back(static_cast<int>(v));
          }
        } else {
          const double v = r.read(pr.type, what);
          if (static_cast<int>(k) == ix) p.x() = v;
          if (static_cast<int>(k) == iy) p.y() = v;
          if (static_cast<int>(k) == iz) p.z() = v;
        }
      }
      std::string extra;
      if (format == 0 && (line_in >> extra))
        throw Error(at_line(path, ascii_line) + what + " has more values than its properties in the header ('" + extra +
                    "' left over): the header's element counts or properties do not match the file");
      if (is_vertex) {
        if (!p.allFinite()) throw Error(path + ": " + what + " has a non-finite coordinate");
        verts.push_back(p);
      }
      if (is_face) {
        if (poly.size() < 3) throw Error(path + ": " + what + " has fewer than three vertices");
        for (size_t j = 1; j + 1 < poly.size(); ++j) {
          tris.push_back({poly[0], poly[j], poly[j + 1]});
          tri_lines.push_back(format == 0 ? ascii_line : 0);
        }
      }
    }
  }
  if (format == 0) {
    std::string text;
    while (std::getline(in, text)) {
      ++ascii_line;
      if (text.find_first_not_of(" \t\r") != std::string::npos)
        throw Error(at_line(path, ascii_line) + "data after the last element the header declares: the header's element "
                    "counts do not match the file");
    }
  } else if (in.peek() != std::char_traits<char>::eof()) {
    throw Error(path + ": data after the last element the header declares: the header's element counts or property "
                "types do not match the file");
  }
  if (!have_vertices || verts.empty()) throw Error(path + ": PLY file has no vertices");
  if (!have_faces || tris.empty()) throw Error(path + ": PLY file has no faces");
  for (size_t t = 0; t < tris.size(); ++t)
    for (int k : tris[t])
      if (k < 0 || k >= static_cast<int>(verts.size()))
        throw Error((tri_lines[t] > 0 ? at_line(path, tri_lines[t]) : path + ": ") + "PLY face refers to vertex " +
                    std::to_string(k) + " (0-based, as PLY counts) but the file has " + std::to_string(verts.size()) +
                    " vertices (0 to " + std::to_string(verts.size() - 1) + ")");
  return from_lists(verts, std::move(tris), std::move(tri_lines));
}

TriangleMesh read_surface(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return read_obj(path);
  if (ext == ".stl") return read_stl(path);
  if (ext == ".ply") return read_ply(path);
  throw Error(path + ": unknown surface format '" + ext + "' (expected .obj, .stl or .ply)");
}

}  // namespace msd
