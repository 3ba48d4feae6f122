#include "bench/compare.hpp"

#include "bench/shared_io.hpp"
#include "tbio/json.hpp"

#include "msd/core/types.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace bench {

namespace {

std::optional<Loading> loading_of(const Results& r) {
  return loading_of_test_label(r.meta.count("test") ? r.meta.at("test") : "");
}

std::string name_of(const std::optional<Loading>& loading) { return loading ? loading_name(*loading) : ""; }


const std::vector<double>& series(const Results& r, const std::string& name, const std::string& file) {
  const auto it = r.series.find(name);
  if (it == r.series.end()) throw msd::Error(file + ": no /series/" + name);
  return it->second;
}

// Two YAML nodes equal in content (scalars as numbers when both are numbers,
// else as text; maps key by key; sequences item by item), whatever their style.
bool same_yaml(const YAML::Node& a, const YAML::Node& b) {
  if (a.Type() != b.Type()) return false;
  if (a.IsScalar()) {
    double x = 0.0, y = 0.0;
    if (YAML::convert<double>::decode(a, x) && YAML::convert<double>::decode(b, y)) return x == y;
    return a.Scalar() == b.Scalar();
  }
  if (a.IsSequence()) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
      if (!same_yaml(a[i], b[i])) return false;
    return true;
  }
  if (a.IsMap()) {
    if (a.size() != b.size()) return false;
    for (const auto& kv : a) {
      const YAML::Node other = b[kv.first.as<std::string>()];
      if (!other || !same_yaml(kv.second, other)) return false;
    }
    return true;
  }
  return true;  // both null
}

// Both files must come from one test: the same spec (name, and the sections
// both solvers read: geometry, material, loading) and the same material
// constants (/meta/material entries both files record).
void require_same_test(const Results& m, const Results& f, const std::string& msd_file,
                       const std::string& fem_file) {
  const std::string pair = msd_file + " and " + fem_file;
  if (m.meta.at("spec_name") != f.meta.at("spec_name"))
    throw msd::Error("compare: the files come from different specs (" + m.meta.at("spec_name") + ", " +
                     f.meta.at("spec_name") + ")");
  YAML::Node sm, sf;
  try {
    sm = YAML::Load(m.meta.count("spec") ? m.meta.at("spec") : "");
    sf = YAML::Load(f.meta.count("spec") ? f.meta.at("spec") : "");
  } catch (const YAML::Exception& e) {
    throw msd::Error("compare: " + pair + ": /meta/spec is not readable YAML (" + e.msg + ")");
  }
  if (sm.IsMap() && sf.IsMap())
    for (const char* section : {"geometry", "material", "loading"})
      if (!same_yaml(sm[section], sf[section]))
        throw msd::Error("compare: " + pair + " come from different specs: their /meta/spec '" + section +
                         "' sections differ");
  for (const auto& [key, a] : m.material) {
    const auto it = f.material.find(key);
    if (it == f.material.end()) continue;
    const double b = it->second;
    if (!(std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b))))
      throw msd::Error("compare: " + pair + " used different materials: /meta/material/" + key + " " +
                       json_number(a, 10) + " against " + json_number(b, 10));
  }
}

// Refuses a non-finite sample in a series the comparison reads: a complete run
// holds none, and dropping it would lower the error.
void require_finite(const std::vector<double>& v, const std::string& name, const std::string& file,
                    const std::vector<double>& time) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw msd::Error("compare: " + file + ": /series/" + name + " row " + std::to_string(i + 1) + " (t = " +
                       (i < time.size() ? json_number(time[i], 6) : std::string("?")) +
                       " s) is not finite; a complete run holds only finite samples");
}

// The displacement field at the MSD nodes against the FEM solution there
// (/fields/nodes against /fields/probes, frames matched by time).
void compare_field(const std::string& msd_file, const std::string& fem_file, Comparison& c) {
  const PointSetData a = read_point_set(msd_file, "nodes"), b = read_point_set(fem_file, "probes");
  if (a.points.size() != b.points.size())
    throw msd::Error("compare: " + fem_file + " holds the FEM solution at " + std::to_string(b.points.size()) +
                     " points, " + msd_file + " has " + std::to_string(a.points.size()) + " nodes");
  for (size_t i = 0; i < a.points.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (std::abs(a.points[i][static_cast<size_t>(k)] - b.points[i][static_cast<size_t>(k)]) > 1e-12)
        throw msd::Error("compare: the FEM probe points are not the MSD nodes (point " + std::to_string(i) + ")");
  double umax = 0.0, sum = 0.0, emax = 0.0;
  long count = 0;
  for (size_t fb = 0; fb < b.time.size(); ++fb) {
    size_t fa = 0;
    double best = 1e300;
    for (size_t k = 0; k < a.time.size(); ++k)
      if (std::abs(a.time[k] - b.time[fb]) < best) {
        best = std::abs(a.time[k] - b.time[fb]);
        fa = k;
      }
    if (best > 1e-6) continue;
    ++c.frames_compared;
    long outside = 0;
    for (size_t i = 0; i < b.points.size(); ++i) {
      const auto& uf = b.displacement[fb][i];
      const auto& um = a.displacement[fa][i];
      // A probe outside the FEM mesh is NaN in all three components (legitimately);
      // anything else non-finite is refused.
      if (std::isnan(uf[0]) && std::isnan(uf[1]) && std::isnan(uf[2])) {
        ++outside;
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(uf[static_cast<size_t>(k)]))
          throw msd::Error("compare: " + fem_file + ": /fields/probes_displacement frame " + std::to_string(fb + 1) +
                           ", point " + std::to_string(i + 1) +
                           " is not finite in some components only (a probe outside the mesh is NaN in all three)");
        if (!std::isfinite(um[static_cast<size_t>(k)]))
          throw msd::Error("compare: " + msd_file + ": /fields/nodes_displacement frame " + std::to_string(fa + 1) +
                           ", node " + std::to_string(i + 1) + " is not finite");
      }
      const double e2 = (um[0] - uf[0]) * (um[0] - uf[0]) + (um[1] - uf[1]) * (um[1] - uf[1]) +
                        (um[2] - uf[2]) * (um[2] - uf[2]);
      umax = std::max(umax, std::sqrt(uf[0] * uf[0] + uf[1] * uf[1] + uf[2] * uf[2]));
      sum += e2;
      emax = std::max(emax, std::sqrt(e2));
      ++count;
    }
    c.nodes_outside = outside;
    c.nodes_compared = static_cast<long>(b.points.size()) - outside;
  }
  if (count > 0 && umax > 0.0) {
    c.displacement_rel_rms = std::sqrt(sum / count) / umax;
    c.displacement_rel_max = emax / umax;
  }
}

}  // namespace

std::string load_series_name(Loading loading) { return loading_info(loading).load_series; }

Comparison compare_results(const std::string& msd_file, const std::string& fem_file, bool displacement_field) {
  const Results m = read_results(msd_file), f = read_results(fem_file);
  for (const auto& [r, file, solver] : {std::tuple<const Results&, const std::string&, const char*>{m, msd_file, "msd"},
                                        {f, fem_file, "fem"}}) {
    if (r.meta.count("solver") == 0 || r.meta.at("solver") != solver)
      throw msd::Error(file + ": expected a results file of the " + std::string(solver) + " solver");
    if (r.status() != "complete") throw msd::Error(file + ": the run is not complete (status " + r.status() + ")");
  }
  Comparison c;
  c.spec = m.meta.at("spec_name");
  const std::optional<Loading> loading = loading_of(m);
  if (!loading || loading != loading_of(f))
    throw msd::Error("compare: " + msd_file + " and " + fem_file + " are not the same test (" + name_of(loading) +
                     " / " + name_of(loading_of(f)) + ")");
  c.loading = *loading;
  const LoadingInfo& info = loading_info(c.loading);
  require_same_test(m, f, msd_file, fem_file);

  const auto& tm = series(m, "time", msd_file);
  const auto& tf = series(f, "time", fem_file);
  c.load_series = info.load_series;
  c.units = info.load_units;
  if (c.loading == Loading::Static) {
    // The tip displacement component the FEM moves most along.
    double best = -1.0;
    for (const char* k : {"tip_displacement_x", "tip_displacement_y", "tip_displacement_z"}) {
      const auto& v = series(f, k, fem_file);
      const double a = v.empty() ? 0.0 : std::abs(v.back());
      if (a > best) {
        best = a;
        c.load_series = k;
      }
    }
  }
  const std::string x_name = info.working_range ? info.strain_column : "";
  const auto& ym = series(m, c.load_series, msd_file);
  const auto& yf = series(f, c.load_series, fem_file);
  double sum_d = 0, sum_f = 0, sum_dw = 0, sum_fw = 0, max_d = 0;
  long n = 0, nw = 0;
  double max_v = 0.0;
  const auto* vm = m.series.count("volume_ratio") ? &m.series.at("volume_ratio") : nullptr;
  const auto* vf = f.series.count("volume_ratio") ? &f.series.at("volume_ratio") : nullptr;
  require_finite(tm, "time", msd_file, tm);
  require_finite(tf, "time", fem_file, tf);
  require_finite(ym, c.load_series, msd_file, tm);
  require_finite(yf, c.load_series, fem_file, tf);
  if (vm && vf) {
    require_finite(*vm, "volume_ratio", msd_file, tm);
    require_finite(*vf, "volume_ratio", fem_file, tf);
  }
  if (!x_name.empty()) require_finite(series(f, x_name, fem_file), x_name, fem_file, tf);
  for (size_t i = 0; i < tf.size(); ++i) {
    const double y = interpolate(tm, ym, tf[i]);
    if (std::isnan(y)) continue;
    const double d = y - yf[i];
    sum_d += d * d;
    sum_f += yf[i] * yf[i];
    max_d = std::max(max_d, std::abs(d));
    ++n;
    if (!x_name.empty() && std::abs(series(f, x_name, fem_file)[i]) <= 0.4 + 1e-12) {
      sum_dw += d * d;
      sum_fw += yf[i] * yf[i];
      ++nw;
    }
    if (vm && vf) max_v = std::max(max_v, std::abs(interpolate(tm, *vm, tf[i]) - (*vf)[i]));
  }
  c.points = n;
  if (n > 0) {
    c.load_rms_fem = std::sqrt(sum_f / n);
    c.load_rel_rms = sum_f > 0 ? std::sqrt(sum_d / sum_f) : std::numeric_limits<double>::quiet_NaN();
    c.load_max_abs_error = max_d;
    if (vm && vf) c.volume_ratio_max_error = max_v;
  }
  if (nw > 0 && sum_fw > 0) c.load_rel_rms_working = std::sqrt(sum_dw / sum_fw);

  // Displacement field at the MSD nodes.
  if (displacement_field && m.point_sets.count("nodes") && f.point_sets.count("probes"))
    compare_field(msd_file, fem_file, c);

  auto cost = [](const Results& r, const char* key) {
    if (!r.timing.count(key) || !r.series.count("time") || r.series.at("time").empty())
      return std::numeric_limits<double>::quiet_NaN();
    const double sim = r.series.at("time").back();
    return sim > 0.0 ? r.timing.at(key) / sim : std::numeric_limits<double>::quiet_NaN();
  };
  c.msd_cost = cost(m, "wall_seconds");
  c.fem_cost = cost(f, "wall_seconds");
  c.msd_cpu_cost = cost(m, "cpu_seconds");
  c.fem_cpu_cost = cost(f, "cpu_seconds");
  const bool cpu = c.msd_cpu_cost > 0.0 && c.fem_cpu_cost > 0.0;
  c.cost_ratio = cpu ? c.msd_cpu_cost / c.fem_cpu_cost : c.msd_cost / c.fem_cost;
  if (info.ring_down) {
    auto metric = [](const Results& r, const char* k) {
      return r.metrics.count(k) ? r.metrics.at(k) : std::numeric_limits<double>::quiet_NaN();
    };
    c.frequency_msd = metric(m, "first_frequency");
    c.frequency_fem = metric(f, "first_frequency");
    c.frequency_rel_error = (c.frequency_msd - c.frequency_fem) / c.frequency_fem;
    c.damping_ratio_msd = metric(m, "damping_ratio");
    c.damping_ratio_fem = metric(f, "damping_ratio");
    c.damping_ratio_abs_error = c.damping_ratio_msd - c.damping_ratio_fem;
  }
  return c;
}

void write_comparison_json(const Comparison& c, const std::string& path) {
  tbio::Json j;
  j["spec"] = c.spec;
  j["loading"] = loading_name(c.loading);
  j["load_series"] = c.load_series;
  j["units"] = c.units;
  j["points"] = c.points;
  j["load_rms_fem"] = c.load_rms_fem;
  j["load_rel_rms"] = c.load_rel_rms;
  j["load_rel_rms_working"] = c.load_rel_rms_working;
  j["load_max_abs_error"] = c.load_max_abs_error;
  j["volume_ratio_max_error"] = c.volume_ratio_max_error;
  j["displacement_rel_rms"] = c.displacement_rel_rms;
  j["displacement_rel_max"] = c.displacement_rel_max;
  j["nodes_compared"] = c.nodes_compared;
  j["nodes_outside"] = c.nodes_outside;
  j["frames_compared"] = c.frames_compared;
  j["frequency_msd"] = c.frequency_msd;
  j["frequency_fem"] = c.frequency_fem;
  j["frequency_rel_error"] = c.frequency_rel_error;
  j["damping_ratio_msd"] = c.damping_ratio_msd;
  j["damping_ratio_fem"] = c.damping_ratio_fem;
  j["damping_ratio_abs_error"] = c.damping_ratio_abs_error;
  j["msd_cost"] = c.msd_cost;
  j["fem_cost"] = c.fem_cost;
  j["msd_cpu_cost"] = c.msd_cpu_cost;
  j["fem_cpu_cost"] = c.fem_cpu_cost;
  j["cost_ratio"] = c.cost_ratio;
  tbio::write_json_file(path, j);
}

std::string format_comparison(const Comparison& c) {
  std::ostringstream s;
  s << std::setprecision(4);
  auto pct = [&](const char* label, double v) {
    if (!std::isnan(v)) s << "  " << std::left << std::setw(44) << label << 100.0 * v << " %\n";
  };
  auto val = [&](const char* label, double v, const char* unit) {
    if (!std::isnan(v)) s << "  " << std::left << std::setw(44) << label << v << " " << unit << "\n";
  };
  s << "MSD against FEM: " << c.spec << " (" << c.loading << ", " << c.load_series << ", " << c.points
    << " points)\n";
  pct("load curve, relative RMS error", c.load_rel_rms);
  pct("  over the working range |strain| <= 0.4", c.load_rel_rms_working);
  val("load curve, largest error", c.load_max_abs_error, c.units.c_str());
  val("volume ratio, largest error", c.volume_ratio_max_error, "");
  if (!std::isnan(c.displacement_rel_rms)) {
    pct("displacement field, RMS / max |u_fem|", c.displacement_rel_rms);
    pct("displacement field, max / max |u_fem|", c.displacement_rel_max);
    s << "  (" << c.nodes_compared << " nodes in " << c.frames_compared << " frames; " << c.nodes_outside
      << " msd nodes lie outside the fem mesh)\n";
  }
  if (!std::isnan(c.frequency_fem)) {
    s << "  first frequency: msd " << c.frequency_msd << " Hz, fem " << c.frequency_fem << " Hz\n";
    pct("  relative error", c.frequency_rel_error);
    s << "  damping ratio: msd " << c.damping_ratio_msd << ", fem " << c.damping_ratio_fem << "\n";
  }
  if (!std::isnan(c.cost_ratio))
    s << "  cost (wall s per simulated s): msd " << c.msd_cost << ", fem " << c.fem_cost << " (ratio "
      << c.cost_ratio << (c.msd_cpu_cost > 0.0 && c.fem_cpu_cost > 0.0 ? " in CPU time" : "") << ")\n";
  return s.str();
}

}  // namespace bench
