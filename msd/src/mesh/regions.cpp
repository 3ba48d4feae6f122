#include "msd/mesh/regions.hpp"

#include <set>
#include <string>

namespace msd {

namespace {

struct Cell {
  int i, j, k;
};

Cell cell_of(const CubicGrid& g, long id) {
  return {static_cast<int>(id % g.nx), static_cast<int>((id / g.nx) % g.ny),
          static_cast<int>(id / (static_cast<long>(g.nx) * g.ny))};
}

bool in_grid(const CubicGrid& g, int i, int j, int k) {
  return i >= 0 && j >= 0 && k >= 0 && i < g.nx && j < g.ny && k < g.nz;
}

// Label of cube (i, j, k), -1 outside the grid.
int label_at(const CubicGrid& g, const std::vector<int>& label, int i, int j, int k) {
  return in_grid(g, i, j, k) ? label[static_cast<size_t>(g.cube_id(i, j, k))] : -1;
}

// One cube thick at `id` for the cubes where `in(id)` holds: along some axis,
// neither face neighbour is in.
template <typename In>
bool one_thick(const CubicGrid& g, long id, In in) {
  const Cell c = cell_of(g, id);
  const int d[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& a : d) {
    const bool lo = in_grid(g, c.i - a[0], c.j - a[1], c.k - a[2]) && in(g.cube_id(c.i - a[0], c.j - a[1], c.k - a[2]));
    const bool hi = in_grid(g, c.i + a[0], c.j + a[1], c.k + a[2]) && in(g.cube_id(c.i + a[0], c.j + a[1], c.k + a[2]));
    if (!lo && !hi) return true;
  }
  return false;
}

using Members = std::map<int, std::vector<char>>;

// Stage 1: the skin's cubes become passive tissue, the rest stays outside (-1).
void label_skin(const std::vector<char>& skin, RegionLabelling& out) {
  const long n = static_cast<long>(skin.size());
  out.label.assign(static_cast<size_t>(n), -1);
  long skin_cubes = 0;
  for (long c = 0; c < n; ++c)
    if (skin[static_cast<size_t>(c)]) {
      out.label[static_cast<size_t>(c)] = kPassiveTissue;
      ++skin_cubes;
    }
  if (skin_cubes == 0) throw Error("regions: no cube lies inside the skin");
}

// Stage 2: each region's cubes inside the skin.
Members region_members(const std::vector<char>& skin, const std::vector<RegionCubes>& inner, RegionLabelling& out) {
  const long n = static_cast<long>(skin.size());
  Members member;
  for (const RegionCubes& r : inner) {
    if (!is_bone(r.region) && !is_muscle(r.region))
      throw Error("regions: region " + std::to_string(r.region) + " is not a muscle or a bone");
    if (member.count(r.region)) throw Error("regions: region " + std::to_string(r.region) + " is given twice");
    if (static_cast<long>(r.member.size()) != n)
      throw Error("regions: region " + std::to_string(r.region) + "'s cube array has the wrong size");
    auto& m = member[r.region];
    m.assign(static_cast<size_t>(n), 0);
    for (long c = 0; c < n; ++c) m[static_cast<size_t>(c)] = r.member[static_cast<size_t>(c)] && skin[static_cast<size_t>(c)];
    long count = 0;
    for (char v : m) count += v ? 1 : 0;
    out.cubes_before[r.region] = count;
  }
  return member;
}

// Stage 3: overlaps. A cube claimed by a bone and a muscle goes to the muscle
// unless the bone is one cube thick there; claimed by both bones or both
// muscles it becomes passive tissue.
void resolve_overlaps(const CubicGrid& grid, const std::vector<char>& skin, Members& member, RegionLabelling& out) {
  const long n = grid.num_cubes();
  auto& label = out.label;
  for (long c = 0; c < n; ++c) {
    if (!skin[static_cast<size_t>(c)]) continue;
    std::vector<int> bones, muscles;
    for (const auto& [r, m] : member)
      if (m[static_cast<size_t>(c)]) (is_bone(r) ? bones : muscles).push_back(r);
    const size_t claims = bones.size() + muscles.size();
    if (claims == 0) continue;
    if (claims == 1) {
      label[static_cast<size_t>(c)] = bones.empty() ? muscles[0] : bones[0];
      continue;
    }
    if (bones.size() == 1 && muscles.size() == 1) {
      const auto& mb = member[bones[0]];
      if (one_thick(grid, c, [&](long d) { return mb[static_cast<size_t>(d)] != 0; })) {
        label[static_cast<size_t>(c)] = bones[0];
        ++out.eroded_muscle_cubes;
      } else {
        label[static_cast<size_t>(c)] = muscles[0];
        ++out.eroded_bone_cubes;
      }
      continue;
    }
    label[static_cast<size_t>(c)] = kPassiveTissue;
    out.eroded_bone_cubes += static_cast<long>(bones.size());
    out.eroded_muscle_cubes += static_cast<long>(muscles.size());
  }
}

// The number of cubes labelled r.
long count_of(const std::vector<int>& label, int r) {
  long k = 0;
  for (int l : label) k += l == r ? 1 : 0;
  return k;
}

// Stage 4: separation, until nothing changes.
void separate_regions(const CubicGrid& grid, RegionLabelling& out) {
  const long n = grid.num_cubes();
  auto& label = out.label;
  auto erode = [&](long c) {
    (is_bone(label[static_cast<size_t>(c)]) ? out.eroded_bone_cubes : out.eroded_muscle_cubes) += 1;
    label[static_cast<size_t>(c)] = kPassiveTissue;
  };
  // Thickness is judged on the labels as they stood at the start of each pass,
  // so the order in which a pass visits the cubes does not thin a bone early.
  std::vector<int> before;
  auto thin_now = [&](long c) {
    const int r = before[static_cast<size_t>(c)];
    return one_thick(grid, c, [&](long d) { return before[static_cast<size_t>(d)] == r; });
  };
  for (bool changed = true; changed;) {
    changed = false;
    before = label;
    for (long c = 0; c < n; ++c) {
      const int a = label[static_cast<size_t>(c)];
      if (a < kFrontMuscle) continue;
      const Cell p = cell_of(grid, c);
      for (int dk = -1; dk <= 1 && label[static_cast<size_t>(c)] == a; ++dk)
        for (int dj = -1; dj <= 1 && label[static_cast<size_t>(c)] == a; ++dj)
          for (int di = -1; di <= 1 && label[static_cast<size_t>(c)] == a; ++di) {
            if (di == 0 && dj == 0 && dk == 0) continue;
            const int i = p.i + di, j = p.j + dj, k = p.k + dk;
            const int b = label_at(grid, label, i, j, k);
            if (is_bone(a) && b < 0) {  // bone against the skin surface: eroded even when thin
              erode(c);
              changed = true;
              continue;
            }
            if (b < kFrontMuscle || b == a) continue;
            const long d = grid.cube_id(i, j, k);
            long victim = c;
            if (is_bone(a) != is_bone(b)) {
              const long bone = is_bone(a) ? c : d, muscle = is_bone(a) ? d : c;
              victim = thin_now(bone) ? muscle : bone;
            } else if (is_bone(a)) {
              victim = (thin_now(c) && !thin_now(d)) ? d : c;
            } else {
              victim = count_of(label, b) > count_of(label, a) ? d : c;
            }
            erode(victim);
            changed = true;
          }
    }
  }
}

// Bone points: where a bone's cubes vanished with no cube of that bone left
// around them, the nodes of those cubes (unless another internal region's
// cube uses the node, and only nodes of the tissue mesh).
std::vector<BonePoint> bone_points(const CubicGrid& grid, const Members& member, const std::vector<int>& label) {
  const long n = grid.num_cubes();
  std::set<std::pair<long, int>> points;
  for (const auto& [r, m] : member) {
    if (!is_bone(r)) continue;
    for (long c = 0; c < n; ++c) {
      if (!m[static_cast<size_t>(c)] || label[static_cast<size_t>(c)] == r) continue;
      const Cell p = cell_of(grid, c);
      bool bone_near = false;
      for (int dk = -1; dk <= 1 && !bone_near; ++dk)
        for (int dj = -1; dj <= 1 && !bone_near; ++dj)
          for (int di = -1; di <= 1 && !bone_near; ++di)
            bone_near = label_at(grid, label, p.i + di, p.j + dj, p.k + dk) == r;
      if (bone_near) continue;
      for (int corner = 0; corner < 8; ++corner) {
        const int ni = p.i + (corner & 1), nj = p.j + ((corner >> 1) & 1), nk = p.k + ((corner >> 2) & 1);
        bool tissue = false, other = false;
        for (int dk = -1; dk <= 0; ++dk)
          for (int dj = -1; dj <= 0; ++dj)
            for (int di = -1; di <= 0; ++di) {
              const int l = label_at(grid, label, ni + di, nj + dj, nk + dk);
              tissue |= l >= 0;
              other |= l >= kFrontMuscle && l != r;
            }
        if (tissue && !other) points.insert({grid.node_id(ni, nj, nk), r});
      }
    }
  }
  std::vector<BonePoint> out;
  std::set<long> taken;
  for (const auto& [node, r] : points)
    if (taken.insert(node).second) out.push_back({node, r});
  return out;
}

}  // namespace

RegionLabelling label_regions(const CubicGrid& grid, const std::vector<char>& skin,
                              const std::vector<RegionCubes>& inner) {
  const long n = grid.num_cubes();
  if (static_cast<long>(skin.size()) != n)
    throw Error("regions: the skin's cube array has " + std::to_string(skin.size()) + " entries, the grid " +
                std::to_string(n) + " cubes");
  RegionLabelling out;
  label_skin(skin, out);
  Members member = region_members(skin, inner, out);
  resolve_overlaps(grid, skin, member, out);
  separate_regions(grid, out);
  out.bone_points = bone_points(grid, member, out.label);
  for (const auto& [r, m] : member) out.cubes_after[r] = count_of(out.label, r);
  return out;
}

std::string separation_fault(const CubicGrid& grid, const std::vector<int>& label) {
  for (long c = 0; c < grid.num_cubes(); ++c) {
    const int a = label[static_cast<size_t>(c)];
    if (a < kFrontMuscle) continue;
    const Cell p = cell_of(grid, c);
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (di == 0 && dj == 0 && dk == 0) continue;
          const int b = label_at(grid, label, p.i + di, p.j + dj, p.k + dk);
          const std::string where = "cube (" + std::to_string(p.i) + ", " + std::to_string(p.j) + ", " +
                                    std::to_string(p.k) + ") of region " + std::to_string(a);
          if (is_bone(a) && b < 0) return where + " touches the skin surface";
          if (b >= kFrontMuscle && b != a) return where + " touches region " + std::to_string(b);
        }
  }
  return "";
}

}  // namespace msd
