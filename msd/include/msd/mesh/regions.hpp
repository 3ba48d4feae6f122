// The multi-region cubic approximation of a limb (thesis 4.5, figure 4.7):
//
//   1. the skin's cubes (passive tissue);
//   2. each internal region's cubes (muscles, bones) inside the skin;
//   3. bones eroded where they overlap or touch a muscle or the other bone -
//      bone first, unless the bone is only one cube thick there, in which case
//      the muscle gives way;
//   4. internal regions kept apart by at least one cube of passive tissue, and
//      bones kept off the skin surface, eroding bone even where it is a single
//      cube thick. Where a bone vanishes that way its grid nodes become "bone
//      points": they stay attached to the bone as if it were still there.
//
// "Erosion" switches a region's boundary cube to passive tissue. "Touching"
// is 26-adjacency (sharing a face, an edge or a corner), because regions that
// share a node would share a node's motion. A bone is one cube thick at a cube
// when, along some axis, neither face neighbour belongs to the same bone.
// Cube membership arrays are indexed by CubicGrid::cube_id.
#pragma once

#include "msd/mesh/cubic_grid.hpp"

#include <map>
#include <vector>

namespace msd {

/// One internal region's cubes before erosion: member[cube_id] != 0 where the
/// cube belongs to the region's surface (under the mesher's cube rule).
struct RegionCubes {
  int region = kFrontMuscle;  ///< kFrontMuscle, kBackMuscle, kUpperBone or kLowerBone
  std::vector<char> member;
};

/// A grid node attached to a bone that has no cube there (stage 4).
struct BonePoint {
  long grid_node = 0;  ///< CubicGrid::node_id
  int region = kUpperBone;
};

struct RegionLabelling {
  std::vector<int> label;  ///< per cube: -1 outside the skin, else a Region
  std::vector<BonePoint> bone_points;
  long eroded_bone_cubes = 0;    ///< bone cubes switched to passive tissue or muscle
  long eroded_muscle_cubes = 0;  ///< muscle cubes switched to passive tissue
  std::map<int, long> cubes_before, cubes_after;  ///< per region, stages 2 and 4
};

inline bool is_bone(int region) { return region == kUpperBone || region == kLowerBone; }
inline bool is_muscle(int region) { return region == kFrontMuscle || region == kBackMuscle; }

/// Stages 1-4 on membership arrays. Throws msd::Error for arrays of the wrong
/// size, an unknown or repeated region, or no skin cube.
RegionLabelling label_regions(const CubicGrid& grid, const std::vector<char>& skin,
                              const std::vector<RegionCubes>& inner);

/// The first violation of the stage-4 invariants, or "" when there is none:
/// two different internal regions 26-adjacent, or a bone cube 26-adjacent to a
/// cube outside the skin (or to the grid's edge).
std::string separation_fault(const CubicGrid& grid, const std::vector<int>& label);

}  // namespace msd
