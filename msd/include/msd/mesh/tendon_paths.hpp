// Tendon strands through the grid (thesis 4.5, figure 4.7d): a tendon's
// geometric path (a polyline from the muscle end to the bone attachment) is
// approximated by polylines through mesh nodes, several strands per tendon so
// its pull spreads over the muscle end (the thesis used 8, 6, 6 and 6).
//
// Each strand starts at its own node of the muscle - the muscle's nodes nearest
// the path's first point, spread apart by farthest-point selection among those
// within one cube diagonal of the nearest - follows the path's interior snapped
// to the nearest mesh nodes (samples one cube apart, repeats dropped), and ends
// at the node nearest the path's last point that a tet of the bone uses or
// that is a bone point of that bone.
#pragma once

#include "msd/mesh/limb_mesher.hpp"

#include <string>
#include <vector>

namespace msd {

struct TendonPathSpec {
  std::string name;
  int muscle = kBackMuscle;
  int bone = kUpperBone;
  std::vector<Vec3> path;  ///< at least two points, muscle end first (m)
  int strands = 6;
};

struct TendonStrands {
  std::string name;
  int muscle = kBackMuscle, bone = kUpperBone;
  std::vector<std::vector<int>> strands;  ///< mesh node indices, muscle node first, bone node last
};

/// Checks a tendon's geometric ends against the limb's surfaces: the path's
/// first point must lie in (or within `tolerance` of) its muscle's surface and
/// its last point in (or within `tolerance` of) its bone's surface. Throws
/// msd::Error naming the tendon, the end, the region and its file otherwise,
/// or when the limb has no such surface.
void validate_tendon_ends(const LimbSurfaces& surfaces, const TendonPathSpec& spec, double tolerance);

/// Throws msd::Error naming the tendon for a path of fewer than two points, a
/// strand count below 1, a muscle or bone with no tets (or bone points) in the
/// mesh, or fewer muscle nodes than strands.
TendonStrands route_tendon(const LimbMesh& mesh, const TendonPathSpec& spec);

}  // namespace msd
