#include "msd/mesh/limb_mesher.hpp"

#include "msd/geometry/inside_test.hpp"

#include <cmath>
#include <sstream>
#include <unordered_map>

namespace msd {

std::string region_name(int region) {
  switch (region) {
    case kPassiveTissue: return "passive_tissue";
    case kFrontMuscle: return "front_muscle";
    case kBackMuscle: return "back_muscle";
    case kUpperBone: return "upper_bone";
    case kLowerBone: return "lower_bone";
    default: return "region_" + std::to_string(region);
  }
}

namespace {

std::string label_of(const LimbSurfaces& s, int region) {
  const std::string name = region == kPassiveTissue ? "skin" : region_name(region);
  const auto it = s.source.find(region);
  return it == s.source.end() || it->second.empty() ? name : name + " (" + it->second + ")";
}

std::string point_text(const Vec3& p) {
  std::ostringstream o;
  o.precision(6);
  o << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return o.str();
}

Mat3 rotation_from_degrees(const Vec3& deg) {
  const Vec3 r = deg * (M_PI / 180.0);
  return (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

}  // namespace

void validate_limb(const LimbSurfaces& s) {
  validate_closed_surface(s.skin, label_of(s, kPassiveTissue));
  for (const auto& [r, m] : s.inner) {
    if (!is_bone(r) && !is_muscle(r)) throw Error("limb: region " + std::to_string(r) + " is not a muscle or a bone");
    validate_closed_surface(m, label_of(s, r));
  }
  const InsideTest skin(s.skin);
  for (const auto& [r, m] : s.inner)
    for (int v = 0; v < m.num_vertices(); ++v)
      if (!skin.inside(m.vertices.col(v)))
        throw Error(label_of(s, r) + ": vertex " + std::to_string(v) + " at " + point_text(m.vertices.col(v)) +
                    " lies outside the skin");
  for (auto a = s.inner.begin(); a != s.inner.end(); ++a)
    for (auto b = std::next(a); b != s.inner.end(); ++b) {
      if (is_bone(a->first) != is_bone(b->first)) continue;  // bone against muscle: erosion decides
      for (const auto& [first, second] : {std::pair{a, b}, std::pair{b, a}}) {
        const InsideTest inside(second->second);
        const TriangleMesh& m = first->second;
        for (int v = 0; v < m.num_vertices(); ++v)
          if (inside.inside(m.vertices.col(v)))
            throw Error(label_of(s, first->first) + " and " + label_of(s, second->first) + " overlap: vertex " +
                        std::to_string(v) + " of the first at " + point_text(m.vertices.col(v)) +
                        " lies inside the second");
      }
    }
}

LimbMesh mesh_limb(const LimbSurfaces& s, const LimbMeshOptions& o) {
  if (!(o.spacing > 0.0) || !std::isfinite(o.spacing))
    throw Error("limb mesh: spacing must be a positive length (m), got " + std::to_string(o.spacing));
  if (!o.rotation_deg.allFinite()) throw Error("limb mesh: rotation must be finite (degrees)");
  validate_limb(s);
  LimbMesh out;
  out.rotation = rotation_from_degrees(o.rotation_deg);
  auto rotated = [&](const TriangleMesh& m) {
    TriangleMesh r = m;
    r.vertices = out.rotation * m.vertices;
    return r;
  };
  const TriangleMesh skin = rotated(s.skin);
  out.grid = make_grid(bounding_box(skin), o.spacing, o.origin, o.max_cubes);
  const std::vector<char> skin_cubes = classify_cubes(out.grid, InsideTest(skin), o.rule);
  std::vector<RegionCubes> inner;
  for (const auto& [r, m] : s.inner) inner.push_back({r, classify_cubes(out.grid, InsideTest(rotated(m)), o.rule)});
  out.labels = label_regions(out.grid, skin_cubes, inner);

  GridMeshInfo info;
  out.mesh = split_cubes(out.grid, out.labels.label, &info);
  out.mesh.nodes = out.rotation.transpose() * out.mesh.nodes;
  check_tet_mesh(out.mesh, "limb mesh");
  for (int l : out.labels.label) out.cubes += l >= 0 ? 1 : 0;
  for (int r : out.mesh.region) ++out.tets_by_region[r];

  std::unordered_map<long, int> node_of;
  for (size_t i = 0; i < info.node_grid_id.size(); ++i) node_of[info.node_grid_id[i]] = static_cast<int>(i);
  for (const BonePoint& p : out.labels.bone_points) {
    const auto it = node_of.find(p.grid_node);
    if (it != node_of.end()) out.bone_points.push_back({it->second, p.region});
  }

  out.embedded[kPassiveTissue] = embed_vertices(out.mesh, s.skin.vertices);
  for (const auto& [r, m] : s.inner) out.embedded[r] = embed_vertices(out.mesh, m.vertices);
  return out;
}

}  // namespace msd
