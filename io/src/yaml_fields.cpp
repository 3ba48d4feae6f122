#include "tbio/yaml_fields.hpp"

#include "msd/core/types.hpp"
#include "msd/io/input_file.hpp"

#include <cmath>
#include <map>

namespace tbio {

namespace {

std::string mark(const std::string& file, const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  if (m.is_null()) return file + ": ";
  return file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1) + ": ";
}

}  // namespace

YAML::Node load_yaml_file(const std::string& path, const std::string& what) {
  return parse_yaml(msd::read_input_file(path, what), path);
}

YAML::Node parse_yaml(const std::string& text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw msd::Error(file + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                     ": YAML syntax error: " + e.msg);
  }
  refuse_duplicate_keys(root, file);
  return root;
}

void refuse_duplicate_keys(const YAML::Node& node, const std::string& file) {
  if (node.IsSequence()) {
    for (const auto& item : node) refuse_duplicate_keys(item, file);
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> first_line;  // key -> 1-based line
  for (const auto& kv : node) {
    // Keys are compared as written (scalars); a collection as a key is
    // compared by its text.
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : YAML::Dump(kv.first);
    const int line = kv.first.Mark().is_null() ? 0 : kv.first.Mark().line + 1;
    const auto [it, fresh] = first_line.emplace(key, line);
    if (!fresh)
      throw msd::Error(mark(file, kv.first) + "duplicate key '" + key + "' (first given at line " +
                       std::to_string(it->second) + ")");
    refuse_duplicate_keys(kv.second, file);
  }
}

Fields::Fields(YAML::Node node, std::string path, std::string file)
    : node_(std::move(node)), path_(std::move(path)), file_(std::move(file)) {
  if (!node_.IsMap())
    throw msd::Error(mark(file_, node_) + (path_.empty() ? "the spec" : path_) +
                     ": expected a mapping of fields");
}

std::string Fields::dotted(const std::string& key) const {
  if (key.empty()) return path_.empty() ? "spec" : path_;
  return path_.empty() ? key : path_ + "." + key;
}

std::string Fields::where(const std::string& key) const {
  const YAML::Node n = (!key.empty() && node_[key]) ? node_[key] : node_;
  return mark(file_, n) + dotted(key) + ": ";
}

bool Fields::has(const std::string& key) const { return static_cast<bool>(node_[key]); }

YAML::Node Fields::get(const std::string& key) const {
  const YAML::Node n = node_[key];
  if (!n) throw msd::Error(mark(file_, node_) + dotted(key) + ": required field is missing");
  return n;
}

Fields Fields::section(const std::string& key) const { return Fields(get(key), dotted(key), file_); }

std::optional<Fields> Fields::optional_section(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return section(key);
}

double Fields::number(const std::string& key) const {
  const YAML::Node n = get(key);
  double v = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v))
    throw msd::Error(where(key) + "expected a number, got '" + (n.IsScalar() ? n.Scalar() : "a collection") + "'");
  if (!std::isfinite(v)) throw msd::Error(where(key) + "must be finite");
  return v;
}

double Fields::number_or(const std::string& key, double fallback) const {
  return has(key) ? number(key) : fallback;
}

long Fields::integer_or(const std::string& key, long fallback) const {
  if (!has(key)) return fallback;
  const YAML::Node n = get(key);
  long v = 0;
  if (!n.IsScalar() || !YAML::convert<long>::decode(n, v))
    throw msd::Error(where(key) + "expected an integer, got '" + (n.IsScalar() ? n.Scalar() : "a collection") + "'");
  return v;
}

std::string Fields::text(const std::string& key) const {
  const YAML::Node n = get(key);
  if (!n.IsScalar()) throw msd::Error(where(key) + "expected a text value");
  return n.Scalar();
}

std::string Fields::text_or(const std::string& key, const std::string& fallback) const {
  return has(key) ? text(key) : fallback;
}

std::vector<std::string> Fields::text_list(const std::string& key) const {
  const YAML::Node n = get(key);
  if (!n.IsSequence()) throw msd::Error(where(key) + "expected a list");
  std::vector<std::string> out;
  for (const auto& item : n) {
    if (!item.IsScalar()) throw msd::Error(mark(file_, item) + dotted(key) + ": expected text items");
    out.push_back(item.Scalar());
  }
  return out;
}

std::vector<double> Fields::number_list(const std::string& key) const {
  const YAML::Node n = get(key);
  if (!n.IsSequence()) throw msd::Error(where(key) + "expected a list of numbers");
  std::vector<double> out;
  for (const auto& item : n) {
    double v = 0.0;
    if (!item.IsScalar() || !YAML::convert<double>::decode(item, v) || !std::isfinite(v))
      throw msd::Error(mark(file_, item) + dotted(key) + ": expected a finite number");
    out.push_back(v);
  }
  return out;
}

std::vector<std::pair<double, double>> Fields::pair_list(const std::string& key) const {
  const YAML::Node n = get(key);
  if (!n.IsSequence()) throw msd::Error(where(key) + "expected a list of [a, b] pairs");
  std::vector<std::pair<double, double>> out;
  for (const auto& item : n) {
    double a = 0.0, b = 0.0;
    if (!item.IsSequence() || item.size() != 2 || !YAML::convert<double>::decode(item[0], a) ||
        !YAML::convert<double>::decode(item[1], b))
      throw msd::Error(mark(file_, item) + dotted(key) + ": expected a pair [a, b] of numbers");
    out.emplace_back(a, b);
  }
  return out;
}

Eigen::Vector3d Fields::vec3(const std::string& key) const {
  const auto v = number_list(key);
  if (v.size() != 3) throw msd::Error(where(key) + "needs three numbers [x, y, z]");
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Eigen::Vector3d Fields::vec3_or(const std::string& key, const Eigen::Vector3d& fallback) const {
  return has(key) ? vec3(key) : fallback;
}

double Fields::positive(const std::string& key) const {
  const double v = number(key);
  if (!(v > 0.0)) throw msd::Error(where(key) + "must be a positive number");
  return v;
}

double Fields::non_negative_or(const std::string& key, double fallback) const {
  const double v = number_or(key, fallback);
  if (!(v >= 0.0) || !std::isfinite(v)) throw msd::Error(where(key) + "must be a number >= 0");
  return v;
}

bool Fields::flag_or(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  bool v = false;
  const YAML::Node n = get(key);
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) throw msd::Error(where(key) + "must be true or false");
  return v;
}

std::string Fields::choice(const std::string& key, const std::vector<std::string>& options) const {
  return choice_or(key, options, text(key));
}

std::string Fields::choice_or(const std::string& key, const std::vector<std::string>& options,
                              const std::string& fallback) const {
  const std::string v = text_or(key, fallback);
  for (const auto& o : options)
    if (v == o) return v;
  std::string list;
  for (const auto& o : options) list += (list.empty() ? "" : ", ") + o;
  throw msd::Error(where(key) + "'" + v + "' is not one of: " + list);
}

void Fields::only(const std::set<std::string>& allowed) const {
  for (const auto& kv : node_) {
    const std::string key = kv.first.Scalar();
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw msd::Error(mark(file_, kv.first) + dotted(key) + ": unknown field (expected one of: " +
                       list + ")");
    }
  }
}

}  // namespace tbio
