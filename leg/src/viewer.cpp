#include "leg/viewer.hpp"

#include "tbio/results_file.hpp"

#include "msd/core/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>

// viewer/embed.cmake writes these from viewer/src/page.html and the bundle.
extern const char tb_viewer_page[];
extern const unsigned long tb_viewer_page_size;
extern const char tb_viewer_bundle[];
extern const unsigned long tb_viewer_bundle_size;

namespace fs = std::filesystem;

namespace leg {

namespace {

/// `text` with every occurrence of `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

/// Where `placeholder` stands in the template; throws if it is missing.
size_t find_placeholder(const std::string& page, const std::string& placeholder) {
  const size_t at = page.find(placeholder);
  if (at == std::string::npos) throw msd::Error("viewer page template: no " + placeholder);
  return at;
}

const char* colour_of(const std::string& mesh) {
  return mesh == "bones" ? "#efe9dc" : mesh == "obstacles" ? "#6f8fb0" : "#d9a184";
}
double opacity_of(const std::string& mesh) { return mesh == "skin" ? 0.55 : mesh == "obstacles" ? 0.85 : 1.0; }

template <class T>
std::string base64_of(const std::vector<T>& v) {
  return base64(v.data(), v.size() * sizeof(T));
}

}  // namespace

std::string base64(const void* data, size_t bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes; i += 3) {
    const uint32_t w = (uint32_t{p[i]} << 16) | (uint32_t{p[i + 1]} << 8) | p[i + 2];
    for (int s = 18; s >= 0; s -= 6) out.push_back(abc[(w >> s) & 63]);
  }
  if (i < bytes) {
    const uint32_t w = (uint32_t{p[i]} << 16) | (i + 1 < bytes ? uint32_t{p[i + 1]} << 8 : 0u);
    out.push_back(abc[(w >> 18) & 63]);
    out.push_back(abc[(w >> 12) & 63]);
    out.push_back(i + 1 < bytes ? abc[(w >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

std::string viewer_page(const tbio::Json& config) {
  const std::string page(tb_viewer_page, tb_viewer_page_size);
  const std::string bundle(tb_viewer_bundle, tb_viewer_bundle_size);
  const std::string config_mark = "<!--TISSUEBENCH_CONFIG-->", bundle_mark = "<!--TISSUEBENCH_BUNDLE-->";
  // Inside a <script> element only "</script" or "<!--" can end it or change
  // how it is read: the JSON carries no '<' at all (each is written \u003c,
  // the same string to JSON), the bundle no "</script".
  const std::string config_element = "<script id=\"tissuebench-config\" type=\"application/json\">" +
                                     replaced(config.dump(), "<", "\\u003c") + "</script>";
  const std::string bundle_element =
      "<script>" + replaced(replaced(bundle, "</script", "<\\/script"), "</SCRIPT", "<\\/SCRIPT") + "</script>";
  // Both placeholders are found in the template before either is filled, so
  // nothing inside the data can be taken for one.
  const size_t at_config = find_placeholder(page, config_mark), at_bundle = find_placeholder(page, bundle_mark);
  const bool config_first = at_config < at_bundle;
  const size_t first = config_first ? at_config : at_bundle, second = config_first ? at_bundle : at_config;
  const size_t first_len = config_first ? config_mark.size() : bundle_mark.size();
  const size_t second_len = config_first ? bundle_mark.size() : config_mark.size();
  return page.substr(0, first) + (config_first ? config_element : bundle_element) +
         page.substr(first + first_len, second - first - first_len) + (config_first ? bundle_element : config_element) +
         page.substr(second + second_len);
}

tbio::Json viewer_mesh(const std::string& name, const msd::Points& rest, const std::vector<msd::Tri>& triangles) {
  std::vector<uint32_t> tris;
  tris.reserve(3 * triangles.size());
  for (const msd::Tri& t : triangles)
    for (int c = 0; c < 3; ++c) tris.push_back(static_cast<uint32_t>(t[static_cast<size_t>(c)]));
  tbio::Json m;
  m["name"] = name;
  m["color"] = colour_of(name);
  m["opacity"] = opacity_of(name);
  m["vertices"] = rest.cols();
  m["triangles"] = triangles.size();
  m["triangles_b64"] = base64_of(tris);
  m["rest_b64"] = positions_base64(rest);
  return m;
}

std::string positions_base64(const msd::Points& x) {
  std::vector<float> v(static_cast<size_t>(3 * x.cols()));
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    for (int c = 0; c < 3; ++c) v[static_cast<size_t>(3 * i + c)] = static_cast<float>(x(c, i));
  return base64_of(v);
}

namespace {

/// One mesh of the run data: rest geometry and the chosen frames' displacements as int16 counts.
tbio::Json run_mesh(const std::string& name, const tbio::PointSetData& d, const std::vector<size_t>& frames) {
  msd::Points rest(3, static_cast<Eigen::Index>(d.points.size()));
  for (size_t i = 0; i < d.points.size(); ++i)
    for (int c = 0; c < 3; ++c) rest(c, static_cast<Eigen::Index>(i)) = d.points[i][static_cast<size_t>(c)];
  std::vector<msd::Tri> tris;
  for (const auto& t : d.triangles) tris.push_back({t[0], t[1], t[2]});
  tbio::Json m = viewer_mesh(name, rest, tris);
  double largest = 0.0;
  for (size_t f : frames)
    for (const auto& u : d.displacement[f])
      for (double c : u)
        if (std::isfinite(c)) largest = std::max(largest, std::abs(c));
  const double scale = largest > 0.0 ? largest / 32767.0 : 1e-9;
  std::vector<int16_t> counts;
  counts.reserve(frames.size() * d.points.size() * 3);
  for (size_t f : frames)
    for (const auto& u : d.displacement[f])
      for (double c : u) counts.push_back(static_cast<int16_t>(std::isfinite(c) ? std::lround(c / scale) : 0));
  m["displacement_scale"] = scale;
  m["displacement_b64"] = base64_of(counts);
  return m;
}

}  // namespace

tbio::Json view_run_data(const std::string& run_dir, const ViewOptions& options) {
  const fs::path dir(run_dir);
  const fs::path h5 = dir / "leg.h5";
  if (!fs::is_directory(dir)) throw msd::Error(run_dir + ": no such folder");
  if (!fs::exists(h5)) {
    std::string variants;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_directory() && fs::exists(e.path() / "leg.h5")) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    for (const std::string& n : names) variants += (variants.empty() ? "" : ", ") + (dir / n).string();
    if (!names.empty())
      throw msd::Error(run_dir + ": no leg.h5 here; these folders hold leg runs (a scene's variants, or several runs): " +
                       variants + ": view one of them");
    throw msd::Error(run_dir + ": no leg.h5 here, so not a leg run (tissuebench leg SCENE.yaml --out " + run_dir +
                     " writes one)");
  }
  const tbio::Results r = tbio::read_results(h5.string());
  if (!r.point_sets.count("skin")) throw msd::Error(h5.string() + ": no /fields/skin: not a leg run's results file");
  const tbio::PointSetData skin = tbio::read_point_set(h5.string(), "skin");
  const size_t available = skin.time.size();
  const size_t cap = static_cast<size_t>(std::max(2, options.max_frames));
  const size_t every = available <= cap ? 1 : (available - 1 + cap - 2) / (cap - 1);  // ceil((F-1)/(cap-1))
  std::vector<size_t> frames;
  for (size_t f = 0; f < available; f += every) frames.push_back(f);
  if (available > 0 && frames.back() != available - 1) frames.push_back(available - 1);

  tbio::Json run;
  run["format"] = "tissuebench-view/1";
  auto meta = [&](const char* key) {
    const auto it = r.meta.find(key);
    return it == r.meta.end() ? std::string() : it->second;
  };
  const std::string variant = meta("variant");
  run["scene"] = meta("spec_name");
  run["variant"] = variant;
  run["title"] = meta("spec_name") + (variant.empty() ? "" : " / " + variant);
  run["run_dir"] = fs::absolute(dir).lexically_normal().string();
  run["status"] = r.status().empty() ? "incomplete" : r.status();
  run["failure"] = meta("failure");
  run["frame_times"] = tbio::Json::array();
  for (size_t f : frames) run["frame_times"].push_back(skin.time[f]);
  run["meshes"] = tbio::Json::array();
  run["meshes"].push_back(run_mesh("skin", skin, frames));
  for (const char* name : {"bones", "obstacles"}) {
    if (!r.point_sets.count(name)) continue;
    const tbio::PointSetData set = tbio::read_point_set(h5.string(), name);
    if (set.time.size() >= available) run["meshes"].push_back(run_mesh(name, set, frames));
  }
  tbio::Json columns = tbio::Json::array();
  const auto time = r.series.find("time");
  for (const auto& [name, values] : r.series) {
    if (name == "time") continue;
    tbio::Json c;
    c["name"] = name;
    const auto u = r.units.find(name);
    c["unit"] = u == r.units.end() ? "" : u->second;
    c["values"] = tbio::Json::array();
    for (double v : values) c["values"].push_back(std::isfinite(v) ? tbio::Json(v) : tbio::Json(nullptr));
    columns.push_back(std::move(c));
  }
  run["series"]["time"] = time == r.series.end() ? std::vector<double>{} : time->second;
  run["series"]["columns"] = std::move(columns);
  run["plots"] = tbio::Json::array();
  for (const char* name : {"knee_angle"})
    if (r.series.count(name)) run["plots"].push_back(name);
  return run;
}

}  // namespace leg
