// Specs of every loading small enough to run in a test with either solver,
// and the check that a results file holds a loading's table columns.
#pragma once

#include "bench/loading.hpp"
#include "bench/shared_io.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace loading_specs {

using bench::Loading;

// A spec of each loading on a small box (cooks_membrane on its own shape),
// short enough to run with either solver in a test.
inline std::string spec_of(Loading loading) {
  const std::map<Loading, std::string> sections{
      {Loading::Uniaxial, "loading: {type: uniaxial, path: [[0, 0], [0.02, -0.01]]}\n"},
      {Loading::SimpleShear, "loading: {type: simple_shear, path: [[0, 0], [0.02, 0.01]]}\n"},
      {Loading::CooksMembrane, "loading: {type: cooks_membrane, force: 0.01, path: [[0, 0], [0.02, 1]]}\n"},
      {Loading::Vibration, "loading: {type: vibration, amplitude: 0.001, duration: 0.02}\n"},
      {Loading::Static,
       "loading: {type: static, fixed: bottom, traction: {face: top, force: [0, 0, 0.001]}, "
       "path: [[0, 0], [0.02, 1]]}\n"},
      {Loading::Indentation,
       "loading: {type: indentation, indenter: {radius: 0.01, depth: 0.001}, path: [[0, 0], [0.02, 1]]}\n"},
  };
  const std::string geometry = loading == Loading::CooksMembrane
                                   ? "geometry: {shape: cooks_membrane}\nfem: {cells: [1, 1, 1], vtu: false}\n"
                                   : "geometry: {shape: box, size: [0.02, 0.02, 0.02]}\n"
                                     "mesh: {spacing: 0.01}\n"
                                     "msd: {constants: physical, dt: 1.0e-4}\n"
                                     "fem: {cells: [1, 1, 1], vtu: false}\n";
  return "name: " + std::string(bench::loading_name(loading)) + "\n" + geometry +
         "material: {density: 1000, youngs_modulus: 5000, poisson_ratio: 0.3, damping_time: 0.002}\n" +
         sections.at(loading) + "output: {interval: 0.01}\n";
}

// The column names of a results file in file order (its CSV twin's header)
// with the units of its /series.
inline std::vector<bench::SeriesColumn> written_columns(const std::string& h5) {
  std::ifstream csv(h5.substr(0, h5.size() - 3) + ".csv");
  std::string header;
  std::getline(csv, header);
  const bench::Results r = bench::read_results(h5);
  std::vector<bench::SeriesColumn> columns;
  std::stringstream names(header);
  for (std::string name; std::getline(names, name, ',');)
    columns.push_back({name, r.units.count(name) ? r.units.at(name) : "?"});
  return columns;
}

inline void expect_same_columns(const std::vector<bench::SeriesColumn>& written,
                                const std::vector<bench::SeriesColumn>& table, Loading loading) {
  ASSERT_EQ(written.size(), table.size()) << loading;
  for (size_t k = 0; k < table.size(); ++k) {
    EXPECT_EQ(written[k].name, table[k].name) << loading << " column " << k;
    EXPECT_EQ(written[k].units, table[k].units) << loading << " column " << table[k].name;
  }
}

}  // namespace loading_specs
