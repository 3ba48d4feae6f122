#include "tbio/parameter.hpp"

#include "msd/core/types.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tbio {

std::string number_text(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string vector_text(const Eigen::Vector3d& v) {
  return "[" + number_text(v.x()) + ", " + number_text(v.y()) + ", " + number_text(v.z()) + "]";
}

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  const bool above = lo_closed ? v >= lo : v > lo;
  const bool below = hi_closed ? v <= hi : v < hi;
  return above && below;
}

std::string Range::text() const {
  if (std::isinf(lo) && std::isinf(hi)) return "any";
  return std::string(lo_closed ? "[" : "(") + number_text(lo) + ", " + number_text(hi) + (hi_closed ? "]" : ")");
}

std::string Parameter::key() const {
  const size_t dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

std::string Parameter::default_shown() const {
  if (!default_text.empty()) return default_text;
  switch (kind) {
    case Kind::Number:
    case Kind::Integer:
      return fallback ? number_text(*fallback) : "required";
    case Kind::Flag:
      return fallback ? (*fallback != 0.0 ? "true" : "false") : "required";
    case Kind::Vector3:
    case Kind::Choice:
    case Kind::Text:
    case Kind::List:
      return "required";
  }
  return "required";
}

double read_number(const Fields& f, const Parameter& p) {
  const std::string k = p.key();
  if (!f.has(k) && p.fallback) return *p.fallback;
  const double v = f.number(k);
  if (!p.range.contains(v))
    throw msd::Error(f.where(k) + "must lie in " + p.range.text() + (p.unit.empty() || p.unit == "1" ? "" : " " + p.unit) +
                     ", got " + number_text(v));
  return v;
}

long read_integer(const Fields& f, const Parameter& p) {
  const std::string k = p.key();
  if (!f.has(k)) {
    if (p.fallback) return static_cast<long>(*p.fallback);
    f.number(k);  // throws the missing-field message
  }
  const long v = f.integer_or(k, 0);
  if (!p.range.contains(static_cast<double>(v)))
    throw msd::Error(f.where(k) + "must lie in " + p.range.text() + ", got " + std::to_string(v));
  return v;
}

Eigen::Vector3d read_vector3(const Fields& f, const Parameter& p) {
  const std::string k = p.key();
  if (!f.has(k) && !p.default_text.empty() && p.default_text != "none") return p.fallback3;
  return f.vec3(k);
}

bool read_flag(const Fields& f, const Parameter& p) {
  if (!f.has(p.key()) && !p.fallback) f.text(p.key());  // throws the missing-field message
  return f.flag_or(p.key(), p.fallback.value_or(0.0) != 0.0);
}

std::string read_choice(const Fields& f, const Parameter& p) {
  return p.default_text.empty() || p.default_text == "none" ? f.choice(p.key(), p.choices)
                                                            : f.choice_or(p.key(), p.choices, p.default_text);
}

std::string markdown_table(const std::vector<Parameter>& params) {
  std::ostringstream o;
  o << "| field | unit | default | range | what |\n|---|---|---|---|---|\n";
  for (const Parameter& p : params) {
    std::string range;
    if (p.kind == Kind::Number || p.kind == Kind::Integer) range = p.range.text();
    if (p.kind == Kind::Choice)
      for (const auto& c : p.choices) range += (range.empty() ? "" : ", ") + c;
    if (p.kind == Kind::Flag) range = "true, false";
    if (p.kind == Kind::Vector3) range = "[x, y, z]";
    if (p.kind == Kind::List) range = "list";
    o << "| `" << p.path << "` | " << (p.unit.empty() ? "" : p.unit) << " | " << p.default_shown() << " | " << range
      << " | " << p.doc << " |\n";
  }
  return o.str();
}

const Parameter& find_parameter(const std::vector<Parameter>& params, const std::string& path, const std::string& what) {
  for (const Parameter& p : params)
    if (p.path == path) return p;
  throw std::logic_error(what + " parameter '" + path + "' is not declared");
}

namespace declare {

Parameter number(std::string path, std::string unit, std::optional<double> fallback, Range range, std::string doc) {
  Parameter p;
  p.path = std::move(path);
  p.unit = std::move(unit);
  p.fallback = fallback;
  p.range = range;
  p.doc = std::move(doc);
  return p;
}

Parameter optional_number(std::string path, std::string unit, Range range, std::string doc, std::string default_text) {
  Parameter p = number(std::move(path), std::move(unit), std::nullopt, range, std::move(doc));
  p.default_text = std::move(default_text);
  return p;
}

Parameter integer(std::string path, double fallback, Range range, std::string doc) {
  Parameter p = number(std::move(path), "1", fallback, range, std::move(doc));
  p.kind = Kind::Integer;
  return p;
}

Parameter vector3(std::string path, std::string unit, std::optional<Eigen::Vector3d> fallback, std::string doc,
                  std::string default_text) {
  Parameter p = other(std::move(path), Kind::Vector3, std::move(unit), std::move(default_text), std::move(doc));
  if (fallback) {
    p.fallback3 = *fallback;
    p.default_text = vector_text(*fallback);
  }
  return p;
}

Parameter choice(std::string path, std::vector<std::string> choices, std::string fallback, std::string doc) {
  Parameter p = other(std::move(path), Kind::Choice, "", std::move(fallback), std::move(doc));
  p.choices = std::move(choices);
  return p;
}

Parameter flag(std::string path, bool fallback, std::string doc) {
  Parameter p = other(std::move(path), Kind::Flag, "", "", std::move(doc));
  p.fallback = fallback ? 1.0 : 0.0;
  return p;
}

Parameter other(std::string path, Kind kind, std::string unit, std::string default_text, std::string doc) {
  Parameter p;
  p.path = std::move(path);
  p.kind = kind;
  p.unit = std::move(unit);
  p.default_text = std::move(default_text);
  p.doc = std::move(doc);
  return p;
}

}  // namespace declare

}  // namespace tbio
