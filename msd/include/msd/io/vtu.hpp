// VTK XML unstructured grids (.vtu, ASCII), the format ParaView opens for tet
// meshes, surfaces, polylines and point sets alike. Files are written to a
// temporary name and renamed, so a crash never leaves a half-written file that
// looks complete.
#pragma once

#include "msd/core/types.hpp"

#include <map>
#include <string>
#include <vector>

namespace msd {

/// VTK cell type codes used here.
enum VtkCellType : int { kVtkVertex = 1, kVtkPolyLine = 4, kVtkTriangle = 5, kVtkTetra = 10 };

/// One unstructured grid: `points` 3 x N (m); cell c lists its point indices
/// and has type types[c]; data arrays hold one value per cell or per point.
struct VtuGrid {
  Points points;
  std::vector<std::vector<int>> cells;
  std::vector<int> types;
  std::map<std::string, std::vector<double>> cell_data, point_data;
};

/// Checks sizes and indices (msd::Error naming `path` and the fault), then writes.
void write_vtu(const std::string& path, const VtuGrid& grid);

}  // namespace msd
