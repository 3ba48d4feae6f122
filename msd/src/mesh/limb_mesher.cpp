#include "msd/mesh/limb_mesher.hpp"

#include "msd/geometry/inside_test.hpp"

#include <cmath>
#include <limits>
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

Vec3 closest_on_surface(const TriangleMesh& m, const Vec3& p) {
  Vec3 best = m.vertices.col(m.triangles[0][0]);
  double best_d = std::numeric_limits<double>::infinity();
  for (const Tri& t : m.triangles) {
    const Vec3 q = closest_point_on_triangle(p, m.vertices.col(t[0]), m.vertices.col(t[1]), m.vertices.col(t[2]));
    const double d = (q - p).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = q;
    }
  }
  return best;
}

// Thesis 4.6: boundary nodes inside the areas towards the skin.
PullReport pull_to_skin(TetMesh& mesh, const TriangleMesh& skin, const std::vector<PullArea>& areas,
                        double min_quality) {
  PullReport r;
  if (areas.empty()) return r;
  std::vector<std::vector<int>> tets_of(static_cast<size_t>(mesh.num_nodes()));
  for (size_t e = 0; e < mesh.tets.size(); ++e)
    for (int v : mesh.tets[e]) tets_of[static_cast<size_t>(v)].push_back(static_cast<int>(e));
  std::vector<char> boundary(static_cast<size_t>(mesh.num_nodes()), 0);
  for (const Tri& f : boundary_faces(mesh.tets))
    for (int v : f) boundary[static_cast<size_t>(v)] = 1;
  auto worst = [&](int v) {
    double q = 1.0;
    for (int e : tets_of[static_cast<size_t>(v)]) {
      const Tet& t = mesh.tets[static_cast<size_t>(e)];
      const Vec3 a = mesh.nodes.col(t[0]), b = mesh.nodes.col(t[1]), c = mesh.nodes.col(t[2]), d = mesh.nodes.col(t[3]);
      q = std::min(q, tet_signed_volume(a, b, c, d) > 0 ? tet_quality(a, b, c, d) : 0.0);
    }
    return q;
  };
  for (int v = 0; v < mesh.num_nodes(); ++v) {
    if (!boundary[static_cast<size_t>(v)]) continue;
    const Vec3 x = mesh.nodes.col(v);
    bool inside = false;
    for (const PullArea& a : areas) inside |= (x.array() >= a.lo.array()).all() && (x.array() <= a.hi.array()).all();
    if (!inside) continue;
    ++r.candidates;
    const Vec3 target = closest_on_surface(skin, x);
    r.gap_before += (target - x).norm();
    double step = 1.0;
    bool moved = false;
    for (int attempt = 0; attempt < 7 && !moved; ++attempt, step *= 0.5) {
      mesh.nodes.col(v) = x + step * (target - x);
      moved = worst(v) >= min_quality;
    }
    if (!moved) mesh.nodes.col(v) = x;
    r.moved += (mesh.nodes.col(v) - x).norm() > 0.0 ? 1 : 0;
    r.gap_after += (closest_on_surface(skin, mesh.nodes.col(v)) - mesh.nodes.col(v)).norm();
  }
  if (r.candidates > 0) {
    r.gap_before /= static_cast<double>(r.candidates);
    r.gap_after /= static_cast<double>(r.candidates);
  }
  return r;
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
        throw Error(label_of(s, r) + ": vertex " + std::to_string(v + 1) + " at " + point_text(m.vertices.col(v)) +
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
                        std::to_string(v + 1) + " of the first at " + point_text(m.vertices.col(v)) +
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
  try {
    out.grid = make_grid(bounding_box(skin), o.spacing, o.origin, o.max_cubes);
  } catch (const Error& e) {
    throw Error((o.memory.context.empty() ? std::string("limb mesh: ") : o.memory.context) + e.what());
  }
  const std::string where = "limb mesh: spacing " + std::to_string(o.spacing) + " m: ";
  // One flag array per surface besides the labels.
  check_memory(static_cast<double>(out.grid.nx) * out.grid.ny * out.grid.nz,
               kGridBytesPerCube * (1.0 + 0.25 * static_cast<double>(s.inner.size())), "a grid", o.memory, where);
  const std::vector<char> skin_cubes = classify_cubes(out.grid, InsideTest(skin), o.rule);
  std::vector<RegionCubes> inner;
  for (const auto& [r, m] : s.inner) inner.push_back({r, classify_cubes(out.grid, InsideTest(rotated(m)), o.rule)});
  out.labels = label_regions(out.grid, skin_cubes, inner);
  {
    double solid = 0.0;
    for (int l : out.labels.label) solid += l >= 0 ? 1.0 : 0.0;
    check_memory(solid, o.solid_bytes_per_cube, "a limb", o.memory, where);
  }

  GridMeshInfo info;
  out.mesh = split_cubes(out.grid, out.labels.label, &info);
  out.tet_cube = std::move(info.tet_cube_id);
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

  for (const PullArea& a : o.pull_areas)
    if (!a.lo.allFinite() || !a.hi.allFinite() || (a.hi.array() < a.lo.array()).any())
      throw Error("limb mesh: pull area '" + a.name + "' needs finite corners with lo <= hi");
  if (!(o.pull_min_quality >= 0.0 && o.pull_min_quality < 1.0))
    throw Error("limb mesh: pull_min_quality must lie in [0, 1)");
  out.pull = pull_to_skin(out.mesh, s.skin, o.pull_areas, o.pull_min_quality);

  out.embedded[kPassiveTissue] = embed_vertices(out.mesh, s.skin.vertices);
  for (const auto& [r, m] : s.inner) out.embedded[r] = embed_vertices(out.mesh, m.vertices);
  return out;
}

}  // namespace msd
