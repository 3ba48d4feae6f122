#include "bench/loading.hpp"

#include "msd/core/types.hpp"

#include <ostream>

namespace bench {

const LoadingInfo& loading_info(Loading loading) {
  static const LoadingInfo uniaxial{"uniaxial",
                                    {{"time", "s"},
                                     {"strain", "1"},
                                     {"nominal_stress", "Pa"},
                                     {"volume_ratio", "1"},
                                     {"inverted_elements", "1"},
                                     {"lateral_force", "N"},
                                     {"kinetic_energy", "J"},
                                     {"nonlinear_active_elements", "1"}},
                                    {{"time", "s"},
                                     {"strain", "1"},
                                     {"nominal_stress", "Pa"},
                                     {"volume_ratio", "1"},
                                     {"inverted_elements", "1"},
                                     {"lateral_force", "N"},
                                     {"kinetic_energy", "J"},
                                     {"newton_iterations", "1"},
                                     {"min_jacobian", "1"}},
                                    "nominal_stress",
                                    "Pa",
                                    "strain",
                                    "nominal_stress",
                                    true, false};
  static const LoadingInfo simple_shear{"simple_shear",
                                        {{"time", "s"},
                                         {"shear_strain", "1"},
                                         {"shear_stress", "Pa"},
                                         {"normal_stress_zz", "Pa"},
                                         {"volume_ratio", "1"},
                                         {"inverted_elements", "1"},
                                         {"kinetic_energy", "J"}},
                                        {{"time", "s"},
                                         {"shear_strain", "1"},
                                         {"shear_stress", "Pa"},
                                         {"normal_stress_xx", "Pa"},
                                         {"normal_stress_yy", "Pa"},
                                         {"normal_stress_zz", "Pa"},
                                         {"shear_stress_mean", "Pa"},
                                         {"volume_ratio", "1"},
                                         {"newton_iterations", "1"}},
                                        "shear_stress",
                                        "Pa",
                                        "shear_strain",
                                        "shear_stress",
                                        true, false};
  static const LoadingInfo cooks_membrane{"cooks_membrane",
                                          {},
                                          {{"time", "s"},
                                           {"load_factor", "1"},
                                           {"tip_displacement", "m"},
                                           {"mid_edge_displacement", "m"},
                                           {"volume_ratio", "1"},
                                           {"newton_iterations", "1"}},
                                          "",
                                          "m",
                                          "",
                                          "",
                                          false, false};
  static const LoadingInfo vibration{"vibration",
                                     {{"time", "s"},
                                      {"tip_displacement", "m"},
                                      {"kinetic_energy", "J"},
                                      {"volume_ratio", "1"},
                                      {"inverted_elements", "1"}},
                                     {{"time", "s"}, {"tip_displacement", "m"}, {"kinetic_energy", "J"}, {"volume_ratio", "1"}},
                                     "tip_displacement",
                                     "m",
                                     "",
                                     "",
                                     false, true};
  static const LoadingInfo static_load{"static",
                                       {{"time", "s"},
                                        {"load_factor", "1"},
                                        {"tip_displacement_x", "m"},
                                        {"tip_displacement_y", "m"},
                                        {"tip_displacement_z", "m"},
                                        {"reaction_force_x", "N"},
                                        {"reaction_force_y", "N"},
                                        {"reaction_force_z", "N"},
                                        {"volume_ratio", "1"},
                                        {"inverted_elements", "1"},
                                        {"kinetic_energy", "J"}},
                                       {{"time", "s"},
                                        {"load_factor", "1"},
                                        {"tip_displacement_x", "m"},
                                        {"tip_displacement_y", "m"},
                                        {"tip_displacement_z", "m"},
                                        {"reaction_force_x", "N"},
                                        {"reaction_force_y", "N"},
                                        {"reaction_force_z", "N"},
                                        {"volume_ratio", "1"},
                                        {"newton_iterations", "1"}},
                                       "tip_displacement_z",
                                       "m",
                                       "",
                                       "",
                                       false, false};
  static const LoadingInfo indentation{"indentation",
                                       {{"time", "s"},
                                        {"depth", "m"},
                                        {"indentation_force", "N"},
                                        {"contact_nodes", "1"},
                                        {"base_reaction_z", "N"},
                                        {"volume_ratio", "1"},
                                        {"inverted_elements", "1"},
                                        {"kinetic_energy", "J"}},
                                       {{"time", "s"},
                                        {"depth", "m"},
                                        {"indentation_force", "N"},
                                        {"base_reaction_z", "N"},
                                        {"max_penetration", "m"},
                                        {"stored_energy", "J"},
                                        {"volume_ratio", "1"},
                                        {"newton_iterations", "1"},
                                        {"min_jacobian", "1"}},
                                       "indentation_force",
                                       "N",
                                       "depth",
                                       "indentation_force",
                                       false, false};
  switch (loading) {
    case Loading::Uniaxial: return uniaxial;
    case Loading::SimpleShear: return simple_shear;
    case Loading::CooksMembrane: return cooks_membrane;
    case Loading::Vibration: return vibration;
    case Loading::Static: return static_load;
    case Loading::Indentation: return indentation;
  }
  throw msd::Error("loading_info: not a Loading value (" + std::to_string(static_cast<int>(loading)) + ")");
}

const char* loading_name(Loading loading) { return loading_info(loading).name; }

std::optional<Loading> find_loading(const std::string& name) {
  for (Loading l : kLoadings)
    if (name == loading_name(l)) return l;
  return std::nullopt;
}

std::string loading_names() {
  std::string list;
  for (Loading l : kLoadings) list += (list.empty() ? "" : ", ") + std::string(loading_name(l));
  return list;
}

std::ostream& operator<<(std::ostream& out, Loading loading) { return out << loading_name(loading); }

const std::vector<SeriesColumn>& series_columns(Loading loading, Solver solver) {
  const LoadingInfo& info = loading_info(loading);
  switch (solver) {
    case Solver::Msd: return info.msd_columns;
    case Solver::Fem: return info.fem_columns;
  }
  throw msd::Error("series_columns: not a Solver value (" + std::to_string(static_cast<int>(solver)) + ")");
}

std::string test_label(Loading loading, const std::string& platens) {
  return loading_name(loading) + (loading == Loading::Uniaxial ? " (" + platens + " platens)" : std::string());
}

std::optional<Loading> loading_of_test_label(const std::string& label) {
  for (Loading l : kLoadings)
    if (label.rfind(loading_name(l), 0) == 0) return l;
  return std::nullopt;
}

std::vector<double> series_row(const std::vector<SeriesColumn>& columns,
                               std::initializer_list<std::pair<const char*, double>> named) {
  if (named.size() != columns.size())
    throw msd::Error("series_row: " + std::to_string(named.size()) + " values for " + std::to_string(columns.size()) +
                     " columns");
  std::vector<double> row;
  row.reserve(columns.size());
  for (const SeriesColumn& c : columns) {
    const auto* it = named.begin();
    while (it != named.end() && c.name != it->first) ++it;
    if (it == named.end()) throw msd::Error("series_row: no value for the column " + c.name);
    row.push_back(it->second);
  }
  return row;
}

int column_index(const std::vector<SeriesColumn>& columns, const std::string& name) {
  if (name.empty()) return -1;
  for (size_t k = 0; k < columns.size(); ++k)
    if (columns[k].name == name) return static_cast<int>(k);
  return -1;
}

}  // namespace bench
