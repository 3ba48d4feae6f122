#include "msd/mesh/tendon_paths.hpp"

#include "msd/geometry/inside_test.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace msd {

void validate_tendon_ends(const LimbSurfaces& surfaces, const TendonPathSpec& spec, double tolerance) {
  const std::string who = "tendon '" + spec.name + "': ";
  if (spec.path.empty()) throw Error(who + "the path needs at least two points");
  auto check = [&](int region, const Vec3& p, const char* end) {
    const auto it = surfaces.inner.find(region);
    if (it == surfaces.inner.end()) throw Error(who + "the limb has no " + region_name(region));
    if (!InsideTest(it->second).inside(p, tolerance)) {
      const auto src = surfaces.source.find(region);
      std::ostringstream m;
      m << who << "its " << end << " point (" << p.x() << ", " << p.y() << ", " << p.z() << ") is not in "
        << region_name(region) << (src != surfaces.source.end() ? " (" + src->second + ")" : std::string())
        << " nor within " << tolerance << " m of it";
      throw Error(m.str());
    }
  };
  check(spec.muscle, spec.path.front(), "first (muscle)");
  check(spec.bone, spec.path.back(), "last (bone)");
}

TendonStrands route_tendon(const LimbMesh& m, const TendonPathSpec& spec) {
  const std::string who = "tendon '" + spec.name + "': ";
  if (spec.path.size() < 2) throw Error(who + "the path needs at least two points");
  for (const Vec3& p : spec.path)
    if (!p.allFinite()) throw Error(who + "a path point is not finite");
  if (spec.strands < 1) throw Error(who + "strands must be at least 1");
  if (!is_muscle(spec.muscle)) throw Error(who + "'" + region_name(spec.muscle) + "' is not a muscle");
  if (!is_bone(spec.bone)) throw Error(who + "'" + region_name(spec.bone) + "' is not a bone");

  const int n = m.mesh.num_nodes();
  std::vector<char> in_muscle(static_cast<size_t>(n), 0), on_bone(static_cast<size_t>(n), 0);
  for (size_t e = 0; e < m.mesh.tets.size(); ++e)
    for (int v : m.mesh.tets[e]) {
      if (m.mesh.region[e] == spec.muscle) in_muscle[static_cast<size_t>(v)] = 1;
      if (m.mesh.region[e] == spec.bone) on_bone[static_cast<size_t>(v)] = 1;
    }
  for (const auto& [node, region] : m.bone_points)
    if (region == spec.bone) on_bone[static_cast<size_t>(node)] = 1;

  auto nearest = [&](const Vec3& p, const std::vector<char>* among) {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      if (among && !(*among)[static_cast<size_t>(i)]) continue;
      const double d = (m.mesh.nodes.col(i) - p).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = i;
      }
    }
    return best;
  };

  // The muscle end: candidates within one cube diagonal of the nearest muscle node.
  const Vec3 start = spec.path.front();
  const int first = nearest(start, &in_muscle);
  if (first < 0) throw Error(who + "the mesh has no " + region_name(spec.muscle) + " tets");
  const double h = m.grid.spacing, reach = (m.mesh.nodes.col(first) - start).norm() + h * std::sqrt(3.0);
  std::vector<int> candidates;
  for (int i = 0; i < n; ++i)
    if (in_muscle[static_cast<size_t>(i)] && (m.mesh.nodes.col(i) - start).norm() <= reach + 1e-12 * h)
      candidates.push_back(i);
  if (static_cast<int>(candidates.size()) < spec.strands)
    throw Error(who + "the muscle end offers " + std::to_string(candidates.size()) + " nodes for " +
                std::to_string(spec.strands) + " strands; use fewer strands or a finer grid");
  // Farthest-point selection, starting from the node nearest the path.
  std::vector<int> ends{first};
  std::vector<double> gap(candidates.size(), std::numeric_limits<double>::infinity());
  while (static_cast<int>(ends.size()) < spec.strands) {
    int pick = -1;
    double far = -1.0;
    for (size_t c = 0; c < candidates.size(); ++c) {
      gap[c] = std::min(gap[c], (m.mesh.nodes.col(candidates[c]) - m.mesh.nodes.col(ends.back())).norm());
      if (gap[c] > far) {
        far = gap[c];
        pick = candidates[c];
      }
    }
    ends.push_back(pick);
  }

  const int bone_node = nearest(spec.path.back(), &on_bone);
  if (bone_node < 0) throw Error(who + "the mesh has no " + region_name(spec.bone) + " tets or bone points");

  // The path's interior, sampled one cube apart and snapped to mesh nodes.
  std::vector<int> middle;
  for (size_t s = 0; s + 1 < spec.path.size(); ++s) {
    const Vec3 a = spec.path[s], b = spec.path[s + 1];
    const int samples = std::max(1, static_cast<int>(std::ceil((b - a).norm() / h)));
    for (int k = (s == 0 ? 1 : 0); k < samples; ++k) {
      const int node = nearest(a + (b - a) * (static_cast<double>(k) / samples), nullptr);
      if (middle.empty() || middle.back() != node) middle.push_back(node);
    }
  }

  TendonStrands out;
  out.name = spec.name;
  out.muscle = spec.muscle;
  out.bone = spec.bone;
  for (int e : ends) {
    std::vector<int> strand{e};
    for (int v : middle)
      if (v != strand.back() && !in_muscle[static_cast<size_t>(v)] && !on_bone[static_cast<size_t>(v)])
        strand.push_back(v);
    if (strand.back() != bone_node) strand.push_back(bone_node);
    out.strands.push_back(strand);
  }
  return out;
}

}  // namespace msd
