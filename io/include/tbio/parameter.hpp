// A file parameter declared once - where it lives, its unit, default, allowed
// range and a one-line doc - in the spirit of deal.II's ParameterHandler
// (declare, then parse), in our own small form. Readers read through the
// declaration, so a field's default, its range check and its message are
// written in one place; the docs' field tables are generated from the
// declarations (markdown_table) and a test holds the docs to them.
#pragma once

#include "tbio/yaml_fields.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace tbio {

/// Allowed values: an interval whose ends may be open or unbounded.
struct Range {
  double lo = -1.0 / 0.0, hi = 1.0 / 0.0;
  bool lo_closed = false, hi_closed = false;

  static Range any() { return {}; }
  static Range positive() { return {0.0, 1.0 / 0.0, false, false}; }
  static Range non_negative() { return {0.0, 1.0 / 0.0, true, false}; }
  static Range closed(double a, double b) { return {a, b, true, true}; }
  static Range open(double a, double b) { return {a, b, false, false}; }
  static Range closed_open(double a, double b) { return {a, b, true, false}; }
  bool contains(double v) const;
  /// "(0, inf)", "[0, 1]", "any".
  std::string text() const;
};

/// What a parameter holds. Text: a word or path the reader checks itself. List: a list or mapping the reader parses itself
/// (keyframes, boxes, obstacles); declared for its documentation.
enum class Kind { Number, Integer, Vector3, Flag, Choice, Text, List };

struct Parameter {
  std::string path;   ///< dotted path in the file, e.g. "knee.damping"
  Kind kind = Kind::Number;
  std::string unit;   ///< SI unit ("1": dimensionless; "": none)
  std::optional<double> fallback;  ///< Number/Integer/Flag default; none: required (or documented in `default_text`)
  Range range;                     ///< Number/Integer
  std::string doc;                 ///< one line
  std::vector<std::string> choices;  ///< Choice: the allowed words
  std::string default_text;          ///< the default as the docs show it, when not a number ("none": optional, no default)
  Eigen::Vector3d fallback3{Eigen::Vector3d::Zero()};  ///< Vector3 default when default_text is set

  /// The last component of `path` (the key within its section).
  std::string key() const;
  /// The default as the docs show it ("required" when there is none).
  std::string default_shown() const;
};

/// A Number parameter's value in section `f` (the mapping at the parameter's
/// parent path): the default when absent and there is one. Throws msd::Error
/// "FILE:LINE:COL: path: must lie in RANGE (UNIT), got V" when out of range,
/// or "required field is missing".
double read_number(const Fields& f, const Parameter& p);
long read_integer(const Fields& f, const Parameter& p);
Eigen::Vector3d read_vector3(const Fields& f, const Parameter& p);
bool read_flag(const Fields& f, const Parameter& p);
std::string read_choice(const Fields& f, const Parameter& p);

/// A Markdown table of the parameters: | field | unit | default | range | what |.
std::string markdown_table(const std::vector<Parameter>& params);

/// The parameter declared at `path` in `params`; throws std::logic_error
/// naming `what` (e.g. "spec") when it is not declared - a programming error.
const Parameter& find_parameter(const std::vector<Parameter>& params, const std::string& path, const std::string& what);

/// A number as the docs show it (stream default: six significant digits; "inf").
std::string number_text(double v);
/// "[x, y, z]" with number_text's digits.
std::string vector_text(const Eigen::Vector3d& v);

/// Builders for declaration tables: one call a parameter, each filling only
/// the members its kind uses.
namespace declare {

/// A number; `fallback` none: required.
Parameter number(std::string path, std::string unit, std::optional<double> fallback, Range range, std::string doc);
/// A number without a default: absent means "not given" (or, with
/// `default_text`, what the docs say happens then).
Parameter optional_number(std::string path, std::string unit, Range range, std::string doc,
                          std::string default_text = "none");
/// A dimensionless whole number with a default.
Parameter integer(std::string path, double fallback, Range range, std::string doc);
/// A vector; `fallback` none: required, or `default_text` says what happens.
Parameter vector3(std::string path, std::string unit, std::optional<Eigen::Vector3d> fallback, std::string doc,
                  std::string default_text = "");
/// A word out of `choices`; `fallback` empty: required.
Parameter choice(std::string path, std::vector<std::string> choices, std::string fallback, std::string doc);
/// true or false, with a default.
Parameter flag(std::string path, bool fallback, std::string doc);
/// A Text or List (or a number with special words) the reader parses itself,
/// declared for its documentation.
Parameter other(std::string path, Kind kind, std::string unit, std::string default_text, std::string doc);

}  // namespace declare

}  // namespace tbio
