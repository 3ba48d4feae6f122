// Memory estimated before it is allocated: a grid spacing that would need more
// memory than the machine can give is refused with the estimate, the limit and
// the field that raises it, instead of swapping or being killed half-way.
//
// Bytes per cube were measured as the peak resident size over a range of
// spacings (docs/memory.md: commands, figures, the fit). The estimate is
//   grid stage:  cubes of the bounding box  x kGridBytesPerCube
//   solid stage: cubes inside the surface    x (kMeshBytesPerCube for meshing,
//                                                kRunBytesPerCube for a run)
#pragma once

#include <string>

namespace msd {

/// Classifying a grid (a flag byte per surface, a 4-byte label, node
/// numbering), per cube of the surface's bounding box: an upper bound from the
/// arrays' sizes, not a measurement.
inline constexpr double kGridBytesPerCube = 64.0;
/// Meshing the solid (tets, nodes, regions, embedding, bone points, the VTU
/// text), per cube kept: the `mesh` command (measured 1.34 kB).
inline constexpr double kMeshBytesPerCube = 1500.0;
/// An MSD run (the mesh, the model's rest data and force plan, state, scratch,
/// results buffers), per cube kept: `run` (measured 2.7-3.0 kB).
inline constexpr double kRunBytesPerCube = 3000.0;

/// This machine's physical memory (bytes); 0 when it cannot be read.
double physical_memory_bytes();

/// A memory limit and how a user raises it, for messages.
struct MemoryLimit {
  double bytes = 0.0;        ///< 0: the default, half of this machine's memory
  std::string how_to_raise;  ///< e.g. "mesh.memory_limit_gb in leg.yaml"
  std::string context;       ///< message prefix naming the file and field ("leg.yaml:9:3: mesh.spacing: "); "" = the caller's

  /// The limit in force: `bytes`, or half the machine's memory.
  double effective_bytes() const;
  /// "the limit of 12.0 GB (half of this machine's 24.0 GB)" or "... (set by ...)".
  std::string describe() const;
};

/// Throws msd::Error "CONTEXT (or WHERE): WHAT of N cubes needs about X GB (B bytes per
/// cube, measured: docs/memory.md), more than LIMIT; raise HOW or increase the
/// spacing" when cubes x bytes_per_cube exceeds the limit.
void check_memory(double cubes, double bytes_per_cube, const std::string& what, const MemoryLimit& limit,
                  const std::string& where);

}  // namespace msd
