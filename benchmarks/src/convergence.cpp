#include "bench/convergence.hpp"

#include "bench/fem_runner.hpp"
#include "bench/shared_io.hpp"
#include "fem/fem.hpp"
#include "tbio/json.hpp"

#include <cmath>
#include <filesystem>

namespace bench {

namespace fs = std::filesystem;

Spec refined_spec(const Spec& spec, int level, unsigned degree) {
  if (level < 0 || level > 8) throw msd::Error("convergence: levels must be between 0 and 8");
  Spec s = spec;
  s.fem.degree = degree;
  if (spec.geometry.shape == "cooks_membrane") {
    const std::array<unsigned, 3> base = spec.fem.cells.value_or(std::array<unsigned, 3>{{2, 2, 1}});
    s.fem.cells = std::array<unsigned, 3>{{base[0] << level, base[1] << level, base[2]}};
  } else {
    s.fem.refinement = static_cast<unsigned>(level);
  }
  s.fem.vtu = false;
  return s;
}

namespace {

// The quantity a refinement study follows: the load curve, Cook's membrane's
// tip displacement, else the first frequency.
std::pair<std::string, std::string> quantity_of(Loading loading) {
  switch (loading) {
    case Loading::Uniaxial: return {"nominal_stress", "Pa"};
    case Loading::SimpleShear: return {"shear_stress", "Pa"};
    case Loading::CooksMembrane: return {"tip_displacement", "m"};
    case Loading::Vibration:
    case Loading::Static:
    case Loading::Indentation: break;
  }
  return {"first_frequency", "Hz"};
}

}  // namespace

ConvergenceStudy run_convergence(const Spec& spec, const std::vector<int>& levels, unsigned degree,
                                 const std::string& out_dir, const Progress& progress) {
  ConvergenceStudy st;
  st.spec_name = spec.name;
  std::tie(st.quantity, st.units) = quantity_of(spec.loading.type);
  const bool root = fem::Session::rank() == 0;
  for (int level : levels) {
    const Spec s = refined_spec(spec, level, degree);
    const std::string file =
        (fs::path(out_dir) / (spec.name + "_p" + std::to_string(degree) + "_l" + std::to_string(level) + ".h5"))
            .string();
    ConvergenceLevel L;
    L.level = level;
    L.degree = degree;
    L.refinement = s.fem.refinement;
    L.cells = s.fem.cells.value_or(std::array<unsigned, 3>{{0, 0, 0}});
    L.run = run_fem(s, file, progress);
    if (!L.run.complete)
      throw msd::Error("convergence: level " + std::to_string(level) + " failed: " + L.run.failure);
    if (root) {
      const Results r = read_results(file);
      if (st.quantity == "first_frequency") L.values = {r.metrics.at("first_frequency")};
      else L.values = r.series.at(st.quantity);
    }
    st.levels.push_back(std::move(L));
  }
  if (!root || st.levels.empty()) return st;
  for (double v : st.levels.back().values) st.scale = std::max(st.scale, std::abs(v));
  for (size_t k = 0; k + 1 < st.levels.size(); ++k) {
    const auto& a = st.levels[k].values;
    const auto& b = st.levels[k + 1].values;
    if (a.size() != b.size()) throw msd::Error("convergence: levels report at different times");
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) sum += (b[i] - a[i]) * (b[i] - a[i]);
    st.differences.push_back(std::sqrt(sum / static_cast<double>(a.size())));
  }
  const size_t n = st.differences.size();
  if (n >= 2 && st.differences[n - 1] > 0.0 && st.differences[n - 2] > 0.0) {
    st.observed_order = std::log2(st.differences[n - 2] / st.differences[n - 1]);
    const double p = std::max(st.observed_order, 0.5);  // guard against a non-asymptotic range
    st.finest_error = st.differences[n - 1] / (std::pow(2.0, p) - 1.0);
  } else if (n == 1) {
    st.finest_error = st.differences[0];  // no order: the last difference bounds it crudely
  }
  if (st.scale > 0.0) st.finest_relative_error = st.finest_error / st.scale;
  return st;
}

double peak(const std::vector<double>& v) {
  double p = 0.0;
  for (double x : v)
    if (std::abs(x) > std::abs(p)) p = x;
  return p;
}

void write_convergence_json(const ConvergenceStudy& st, const std::string& path) {
  tbio::Json levels = tbio::Json::array();
  for (const auto& L : st.levels)
    levels.push_back({{"level", L.level},
                      {"degree", L.degree},
                      {"refinement", L.refinement},
                      {"cells", L.run.cells},
                      {"dofs", L.run.dofs},
                      {"wall_seconds", L.run.wall_seconds},
                      {"final_value", L.values.empty() ? 0.0 : L.values.back()},
                      {"file", L.run.out_path}});
  tbio::Json j;
  j["spec"] = st.spec_name;
  j["quantity"] = st.quantity;
  j["units"] = st.units;
  j["levels"] = std::move(levels);
  j["differences"] = st.differences;
  j["scale"] = st.scale;
  j["observed_order"] = st.observed_order;
  j["finest_error"] = st.finest_error;
  j["finest_relative_error"] = st.finest_relative_error;
  tbio::write_json_file(path, j);
}

}  // namespace bench
