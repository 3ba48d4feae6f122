// The loadings a spec names in loading.type, and per loading what the harness
// knows of it: its YAML name, the /series columns each solver writes, the load
// curve a comparison judges and the strain and stress columns a summary tracks.
#pragma once

#include "bench/shared_io.hpp"

#include <array>
#include <initializer_list>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bench {

enum class Loading { Uniaxial, SimpleShear, CooksMembrane, Vibration, Static, Indentation };

/// Every loading, in the order messages list them.
constexpr std::array<Loading, 6> kLoadings{Loading::Uniaxial,  Loading::SimpleShear, Loading::CooksMembrane,
                                           Loading::Vibration, Loading::Static,      Loading::Indentation};

enum class Solver { Msd, Fem };

struct LoadingInfo {
  const char* name;                     ///< the YAML spelling, e.g. "simple_shear"
  /// /series of each solver, in file order; empty where the solver does not
  /// run the loading (cooks_membrane with msd).
  std::vector<SeriesColumn> msd_columns, fem_columns;
  /// The load curve a comparison judges ("" where none: cooks_membrane); for
  /// static the default, a comparison takes the tip component the FEM moves
  /// most along.
  const char* load_series;
  const char* load_units;
  /// The deformation and the load a run summary tracks ("" where none).
  const char* strain_column;
  const char* stress_column;
  /// The comparison also reports the error over |strain_column| <= 0.4, the
  /// tissue working range (thesis 5.2.6).
  bool working_range;
  /// The run ends in a free ring-down: the first frequency and damping ratio
  /// of the load series after the release are the run's metrics.
  bool ring_down;
};

const LoadingInfo& loading_info(Loading loading);

const char* loading_name(Loading loading);

/// The loading named `name` (its YAML spelling), if any.
std::optional<Loading> find_loading(const std::string& name);

/// "uniaxial, simple_shear, ...": the names, for messages.
std::string loading_names();

std::ostream& operator<<(std::ostream& out, Loading loading);

const std::vector<SeriesColumn>& series_columns(Loading loading, Solver solver);

/// The results file's /meta/test: the loading's name, for uniaxial followed by
/// " (PLATENS platens)".
std::string test_label(Loading loading, const std::string& platens);

/// The loading a /meta/test label starts with, if any.
std::optional<Loading> loading_of_test_label(const std::string& label);

/// One /series row: the values of `named` in the order of `columns`. Throws
/// msd::Error unless `named` gives every column exactly once.
std::vector<double> series_row(const std::vector<SeriesColumn>& columns,
                               std::initializer_list<std::pair<const char*, double>> named);

/// Position of the column `name` in `columns`, -1 if absent or "".
int column_index(const std::vector<SeriesColumn>& columns, const std::string& name);

}  // namespace bench
