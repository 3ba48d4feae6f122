#include "msd/mesh/tet_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace msd {

double tet_signed_volume(const Points& x, const Tet& t) {
  return tet_signed_volume(x.col(t[0]), x.col(t[1]), x.col(t[2]), x.col(t[3]));
}

double total_volume(const Points& x, const std::vector<Tet>& tets) {
  double v = 0.0;
  for (const Tet& t : tets) v += tet_signed_volume(x, t);
  return v;
}

int count_inverted(const Points& x, const std::vector<Tet>& tets) {
  int n = 0;
  for (const Tet& t : tets) n += tet_signed_volume(x, t) <= 0.0;
  return n;
}

double tet_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double v = std::abs(tet_signed_volume(a, b, c, d));
  const double l2 = (b - a).squaredNorm() + (c - a).squaredNorm() + (d - a).squaredNorm() +
                    (c - b).squaredNorm() + (d - b).squaredNorm() + (d - c).squaredNorm();
  if (l2 <= 0.0) return 0.0;
  return 12.0 * std::pow(3.0 * v, 2.0 / 3.0) / l2;
}

double min_quality(const TetMesh& mesh) {
  if (mesh.tets.empty()) return 0.0;
  double q = 1e300;
  for (const Tet& t : mesh.tets)
    q = std::min(q, tet_quality(mesh.nodes.col(t[0]), mesh.nodes.col(t[1]), mesh.nodes.col(t[2]),
                                mesh.nodes.col(t[3])));
  return q;
}

namespace {

// Faces of a positively oriented tet (a,b,c,d), each listed with an outward normal.
constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

std::array<int, 3> sorted_key(int a, int b, int c) {
  std::array<int, 3> k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

std::vector<Tri> boundary_faces(const std::vector<Tet>& tets) {
  std::map<std::array<int, 3>, std::pair<int, Tri>> faces;  // key -> (count, oriented face)
  for (const Tet& t : tets)
    for (const auto& f : kFaces) {
      const Tri tri{t[f[0]], t[f[1]], t[f[2]]};
      auto& slot = faces[sorted_key(tri[0], tri[1], tri[2])];
      ++slot.first;
      slot.second = tri;
    }
  std::vector<Tri> out;
  for (const auto& [key, val] : faces)
    if (val.first == 1) out.push_back(val.second);
  return out;
}

std::vector<int> face_sharing_histogram(const std::vector<Tet>& tets) {
  std::map<std::array<int, 3>, int> faces;
  for (const Tet& t : tets)
    for (const auto& f : kFaces) ++faces[sorted_key(t[f[0]], t[f[1]], t[f[2]])];
  std::vector<int> hist(3, 0);
  for (const auto& [key, n] : faces) {
    if (n >= static_cast<int>(hist.size())) hist.resize(static_cast<size_t>(n) + 1, 0);
    ++hist[static_cast<size_t>(n)];
  }
  return hist;
}

void check_tet_mesh(const TetMesh& mesh, const std::string& name) {
  const int n = mesh.num_nodes();
  if (!mesh.nodes.allFinite()) throw Error(name + ": a node coordinate is not finite");
  if (mesh.region.size() != mesh.tets.size())
    throw Error(name + ": " + std::to_string(mesh.region.size()) + " region labels for " +
                std::to_string(mesh.tets.size()) + " tets");
  for (size_t e = 0; e < mesh.tets.size(); ++e) {
    const Tet& t = mesh.tets[e];
    for (int k = 0; k < 4; ++k)
      if (t[k] < 0 || t[k] >= n)
        throw Error(name + ": tet " + std::to_string(e) + " refers to node " +
                    std::to_string(t[k]) + " (the mesh has " + std::to_string(n) + ")");
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (t[i] == t[j]) throw Error(name + ": tet " + std::to_string(e) + " repeats a node");
    if (!(tet_signed_volume(mesh.nodes, t) > 0.0))
      throw Error(name + ": tet " + std::to_string(e) +
                  " is inverted or degenerate (signed volume <= 0)");
  }
}

}  // namespace msd
