// Strict reading of YAML mappings (test specs, leg scenes, mesh scenes,
// baselines): every field is looked up by name, unknown fields are errors, and
// every message names the file, line and the field's dotted path (e.g.
// "uniaxial.yaml:14:5: msd.dt: must be positive").
#pragma once

#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace tbio {

/// Loads a YAML file (at most msd::kMaxTextInputBytes, a regular file) and
/// parses it with parse_yaml. Throws msd::Error "PATH: cannot read the WHAT"
/// for a missing or unreadable file, and what parse_yaml throws.
YAML::Node load_yaml_file(const std::string& path, const std::string& what);

/// Parses YAML text read from `file` (named in messages). Throws msd::Error
/// "FILE:LINE:COL: YAML syntax error: ..." for bad YAML and
/// "FILE:LINE:COL: duplicate key 'K' (first given at line L)" when a mapping,
/// at any depth, repeats a key: YAML forbids it, and yaml-cpp would silently
/// read the first one, so an invalid second value would never be checked.
YAML::Node parse_yaml(const std::string& text, const std::string& file);

/// Throws the duplicate-key error above for the first mapping under `node`
/// (itself included) that repeats a key.
void refuse_duplicate_keys(const YAML::Node& node, const std::string& file);

/// A YAML mapping with the dotted path it was found at, for messages.
class Fields {
 public:
  Fields(YAML::Node node, std::string path, std::string file);

  bool has(const std::string& key) const;
  Fields section(const std::string& key) const;  ///< required mapping
  std::optional<Fields> optional_section(const std::string& key) const;

  double number(const std::string& key) const;
  double number_or(const std::string& key, double fallback) const;
  long integer_or(const std::string& key, long fallback) const;
  std::string text(const std::string& key) const;
  std::string text_or(const std::string& key, const std::string& fallback) const;
  std::vector<std::string> text_list(const std::string& key) const;
  std::vector<double> number_list(const std::string& key) const;
  /// A list of [a, b] pairs.
  std::vector<std::pair<double, double>> pair_list(const std::string& key) const;

  /// Three finite numbers [x, y, z].
  Eigen::Vector3d vec3(const std::string& key) const;
  Eigen::Vector3d vec3_or(const std::string& key, const Eigen::Vector3d& fallback) const;
  /// A finite number > 0 (required).
  double positive(const std::string& key) const;
  /// A finite number >= 0, or `fallback` when the field is absent.
  double non_negative_or(const std::string& key, double fallback) const;
  /// true or false, or `fallback` when the field is absent.
  bool flag_or(const std::string& key, bool fallback) const;
  /// A text value (required) that must be one of `options`.
  std::string choice(const std::string& key, const std::vector<std::string>& options) const;
  /// A text value that must be one of `options`, or `fallback` when absent.
  std::string choice_or(const std::string& key, const std::vector<std::string>& options,
                        const std::string& fallback) const;

  /// Throws if the mapping holds a key outside `allowed`.
  void only(const std::set<std::string>& allowed) const;

  /// "file:line:col: path.key: " for messages about `key` (or the mapping).
  std::string where(const std::string& key = "") const;

  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return file_; }

 private:
  YAML::Node get(const std::string& key) const;
  std::string dotted(const std::string& key) const;
  YAML::Node node_;
  std::string path_, file_;
};

}  // namespace tbio
