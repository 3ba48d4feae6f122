#include "msd/geometry/triangle_mesh.hpp"
#include "msd/io/input_file.hpp"

#include "msd/io/atomic_file.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <utility>

namespace msd {

Aabb bounding_box(const TriangleMesh& mesh) {
  if (mesh.vertices.cols() == 0) throw Error("bounding_box: the surface has no vertices");
  Aabb box;
  box.lo = mesh.vertices.rowwise().minCoeff();
  box.hi = mesh.vertices.rowwise().maxCoeff();
  return box;
}

double enclosed_volume(const TriangleMesh& mesh) {
  double six_v = 0.0;
  for (const Tri& t : mesh.triangles) {
    const Vec3 a = mesh.vertices.col(t[0]);
    const Vec3 b = mesh.vertices.col(t[1]);
    const Vec3 c = mesh.vertices.col(t[2]);
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

TriangleMesh make_cylinder(double radius, double height, int segments) {
  if (!(radius > 0.0) || !(height > 0.0) || !std::isfinite(radius) || !std::isfinite(height))
    throw Error("cylinder: radius and height must be positive and finite (got radius " +
                std::to_string(radius) + ", height " + std::to_string(height) + ")");
  if (segments < 3) throw Error("cylinder: segments must be at least 3");
  TriangleMesh m;
  const int n = segments;
  m.vertices.resize(3, 2 * n + 2);
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * pi * i / n;
    // Exact values on the axes keep the shape symmetric under grid alignment.
    double c = std::cos(phi), s = std::sin(phi);
    if (4 * i == n || 4 * i == 3 * n) c = 0.0;
    if (2 * i == n) s = 0.0;
    m.vertices.col(i) = Vec3(radius * c, radius * s, 0.0);
    m.vertices.col(n + i) = Vec3(radius * c, radius * s, height);
  }
  const int bottom = 2 * n, top = 2 * n + 1;
  m.vertices.col(bottom) = Vec3(0, 0, 0);
  m.vertices.col(top) = Vec3(0, 0, height);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, j, n + j});
    m.triangles.push_back({i, n + j, n + i});
    m.triangles.push_back({bottom, j, i});
    m.triangles.push_back({top, n + i, n + j});
  }
  return m;
}

TriangleMesh make_box(const Vec3& lo, const Vec3& hi) {
  if (!lo.allFinite() || !hi.allFinite() || !((hi - lo).array() > 0.0).all())
    throw Error("box: need finite corners with hi > lo in every coordinate");
  TriangleMesh m;
  m.vertices.resize(3, 8);
  for (int k = 0; k < 8; ++k)
    m.vertices.col(k) = Vec3((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(),
                             (k & 4) ? hi.z() : lo.z());
  // Each face as a quad listed counter-clockwise from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

namespace {

std::string where(const std::string& path, int line) {
  return path + ":" + std::to_string(line) + ": ";
}

std::string point_text(const Vec3& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

}  // namespace

TriangleMesh read_obj(const std::string& path) {
  std::istringstream in(read_input_file(path, "OBJ file", kMaxSurfaceInputBytes));
  TriangleMesh m;
  std::vector<Vec3> verts;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    if (tag == "v") {
      Vec3 p;
      if (!(ls >> p.x() >> p.y() >> p.z()))
        throw Error(where(path, lineno) + "vertex record needs three numbers");
      if (!p.allFinite()) throw Error(where(path, lineno) + "vertex coordinate is not finite");
      verts.push_back(p);
    } else if (tag == "f") {
      std::vector<int> idx;
      std::string tok;
      while (ls >> tok) {
        const std::string first = tok.substr(0, tok.find('/'));
        int k = 0;
        try {
          size_t used = 0;
          k = std::stoi(first, &used);
          if (used != first.size()) throw std::invalid_argument(first);
        } catch (const std::exception&) {
          throw Error(where(path, lineno) + "face index '" + tok + "' is not an integer");
        }
        if (k < 0) k = static_cast<int>(verts.size()) + 1 + k;  // relative index
        if (k < 1 || k > static_cast<int>(verts.size()))
          throw Error(where(path, lineno) + "face refers to vertex " + first + " but only " +
                      std::to_string(verts.size()) + " vertices are defined so far");
        idx.push_back(k - 1);
      }
      if (idx.size() < 3) throw Error(where(path, lineno) + "face needs at least three vertices");
      for (size_t i = 1; i + 1 < idx.size(); ++i) {
        m.triangles.push_back({idx[0], idx[i], idx[i + 1]});
        m.triangle_line.push_back(lineno);
      }
    }
  }
  if (verts.empty()) throw Error(path + ": OBJ file has no vertices");
  if (m.triangles.empty()) throw Error(path + ": OBJ file has no faces");
  m.vertices.resize(3, static_cast<Eigen::Index>(verts.size()));
  for (size_t i = 0; i < verts.size(); ++i) m.vertices.col(static_cast<Eigen::Index>(i)) = verts[i];
  return m;
}

void write_obj(const std::string& path, const TriangleMesh& mesh) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (int i = 0; i < mesh.num_vertices(); ++i)
      out << "v " << mesh.vertices(0, i) << ' ' << mesh.vertices(1, i) << ' ' << mesh.vertices(2, i) << '\n';
    for (const Tri& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  });
}

void write_obj(const std::string& path, const Points& positions, const std::vector<Tri>& triangles, int decimals) {
  write_file_atomically(path, [&](std::ostream& out) {
    char line[128];
    for (int i = 0; i < positions.cols(); ++i) {
      std::snprintf(line, sizeof line, "v %.*f %.*f %.*f\n", decimals, positions(0, i), decimals, positions(1, i),
                    decimals, positions(2, i));
      out << line;
    }
    for (const Tri& t : triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  });
}

Points vertex_normals(const TriangleMesh& mesh) {
  Points n = Points::Zero(3, mesh.num_vertices());
  for (const Tri& t : mesh.triangles) {
    const Vec3 a = mesh.vertices.col(t[0]), b = mesh.vertices.col(t[1]), c = mesh.vertices.col(t[2]);
    const Vec3 w = (b - a).cross(c - a);
    for (int v : t) n.col(v) += w;
  }
  for (int i = 0; i < n.cols(); ++i)
    if (n.col(i).norm() > 0.0) n.col(i).normalize();
  return n;
}

std::string triangle_where(const TriangleMesh& mesh, const std::string& name, int t) {
  const size_t i = static_cast<size_t>(t);
  const int line = i < mesh.triangle_line.size() ? mesh.triangle_line[i] : 0;
  return name + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": triangle " + std::to_string(t + 1);
}

// Messages count vertices and triangles from 1, as OBJ does (PLY counts from
// 0 in its own records; the reading order is the same).
void validate_closed_surface(const TriangleMesh& mesh, const std::string& name) {
  const int nv = mesh.num_vertices();
  if (nv == 0 || mesh.triangles.empty()) throw Error(name + ": the surface is empty");
  if (!mesh.vertices.allFinite()) throw Error(name + ": a vertex coordinate is not finite");
  const Aabb box = bounding_box(mesh);
  const double scale = (box.hi - box.lo).norm();
  auto at = [&](size_t t) { return triangle_where(mesh, name, static_cast<int>(t)); };
  auto vertex = [](int v) { return "vertex " + std::to_string(v + 1); };
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Tri& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] < 0 || tri[k] >= nv)
        throw Error(at(t) + " refers to " + vertex(tri[k]) + " (the surface has " + std::to_string(nv) +
                    " vertices, counted from 1)");
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) throw Error(at(t) + " repeats a vertex");
    const Vec3 a = mesh.vertices.col(tri[0]), b = mesh.vertices.col(tri[1]),
               c = mesh.vertices.col(tri[2]);
    if ((b - a).cross(c - a).norm() <= 1e-14 * scale * scale) throw Error(at(t) + " is degenerate (zero area)");
  }
  // Directed edges: each must appear exactly once, and its reverse exactly once.
  std::map<std::pair<int, int>, int> directed;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Tri& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> e{tri[k], tri[(k + 1) % 3]};
      auto [it, fresh] = directed.emplace(e, static_cast<int>(t));
      if (!fresh) {
        // Same directed edge twice: either three or more triangles meet here, or
        // two neighbours disagree on orientation.
        const auto rev = directed.find({e.second, e.first});
        const std::string edge = "the edge from " + vertex(e.first) + " to " + vertex(e.second);
        if (rev != directed.end())
          throw Error(at(t) + ": " + edge + " is shared by more than two triangles (non-manifold)");
        throw Error(at(t) + ": inconsistent orientation: " + edge + " is listed in the same direction by " +
                    at(static_cast<size_t>(it->second)));
      }
    }
  }
  for (const auto& [e, t] : directed) {
    if (!directed.count({e.second, e.first}))
      throw Error(at(static_cast<size_t>(t)) + ": the surface is open: its edge from " + vertex(e.first) + " to " +
                  vertex(e.second) + " has no neighbour");
  }
  // Vertex manifoldness: the triangles around each vertex form one cycle.
  std::vector<std::vector<std::pair<int, int>>> fan(static_cast<size_t>(nv));
  for (const Tri& tri : mesh.triangles)
    for (int k = 0; k < 3; ++k) fan[tri[k]].push_back({tri[(k + 1) % 3], tri[(k + 2) % 3]});
  for (int v = 0; v < nv; ++v) {
    const auto& f = fan[v];
    if (f.empty()) continue;  // unreferenced vertices are harmless
    std::map<int, int> next;
    for (const auto& [a, b] : f) next[a] = b;
    int steps = 0, cur = f.front().first;
    do {
      cur = next.at(cur);
      ++steps;
    } while (cur != f.front().first && steps <= static_cast<int>(f.size()));
    if (steps != static_cast<int>(f.size()))
      throw Error(name + ": " + vertex(v) + " at " + point_text(mesh.vertices.col(v)) +
                  " is non-manifold (its triangles form more than one fan)");
  }
  const double vol = enclosed_volume(mesh);
  if (!(vol > 0.0))
    throw Error(name + (vol < 0.0 ? ": triangles face inwards (negative enclosed volume); reverse "
                                    "their orientation"
                                  : ": encloses no volume"));
}

}  // namespace msd
