#include "msd/io/vtu.hpp"

#include "msd/io/atomic_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>

namespace msd {

namespace {

void write_array(std::ostream& out, const std::string& type, const std::string& name, int components,
                 const std::vector<double>& values) {
  out << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\"";
  if (components > 1) out << " NumberOfComponents=\"" << components << "\"";
  out << " format=\"ascii\">\n";
  for (size_t i = 0; i < values.size(); ++i) out << (i % 12 == 0 ? "          " : " ") << values[i] << (i % 12 == 11 ? "\n" : "");
  out << "\n        </DataArray>\n";
}

}  // namespace

void write_vtu(const std::string& path, const VtuGrid& g) {
  const long n = g.points.cols();
  if (g.cells.size() != g.types.size())
    throw Error(path + ": " + std::to_string(g.cells.size()) + " cells but " + std::to_string(g.types.size()) + " cell types");
  if (!g.points.allFinite()) throw Error(path + ": a point coordinate is not finite");
  for (size_t c = 0; c < g.cells.size(); ++c)
    for (int i : g.cells[c])
      if (i < 0 || i >= n)
        throw Error(path + ": cell " + std::to_string(c) + " refers to point " + std::to_string(i) + " of " + std::to_string(n));
  for (const auto& [name, v] : g.cell_data)
    if (v.size() != g.cells.size()) throw Error(path + ": cell array '" + name + "' has the wrong length");
  for (const auto& [name, v] : g.point_data)
    if (static_cast<long>(v.size()) != n) throw Error(path + ": point array '" + name + "' has the wrong length");

  write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(10);
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << g.cells.size() << "\">\n";
    out << "      <Points>\n";
    std::vector<double> xyz(g.points.data(), g.points.data() + 3 * n);
    write_array(out, "Float64", "Points", 3, xyz);
    out << "      </Points>\n      <Cells>\n";
    std::vector<double> conn, offsets, types;
    long off = 0;
    for (size_t c = 0; c < g.cells.size(); ++c) {
      for (int i : g.cells[c]) conn.push_back(i);
      off += static_cast<long>(g.cells[c].size());
      offsets.push_back(static_cast<double>(off));
      types.push_back(g.types[c]);
    }
    write_array(out, "Int64", "connectivity", 1, conn);
    write_array(out, "Int64", "offsets", 1, offsets);
    write_array(out, "UInt8", "types", 1, types);
    out << "      </Cells>\n";
    if (!g.cell_data.empty()) {
      out << "      <CellData>\n";
      for (const auto& [name, v] : g.cell_data) write_array(out, "Float64", name, 1, v);
      out << "      </CellData>\n";
    }
    if (!g.point_data.empty()) {
      out << "      <PointData>\n";
      for (const auto& [name, v] : g.point_data) write_array(out, "Float64", name, 1, v);
      out << "      </PointData>\n";
    }
    out << "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  });
}

}  // namespace msd
