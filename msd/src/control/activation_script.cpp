#include "msd/control/activation_script.hpp"

#include "msd/core/types.hpp"
#include "msd/io/input_file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace msd {

namespace {

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

double number(const std::string& token, const std::string& where, const char* what) {
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(token, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != token.size() || !std::isfinite(v))
    throw Error(where + "the " + std::string(what) + " '" + token + "' is not a number");
  return v;
}

}  // namespace

double ActivationScript::activation(const std::string& muscle, double t) const {
  const std::string name = upper(muscle);
  // The ramp in effect: from `from` at `start` to `target` over `tau`.
  double from = 0.0, start = 0.0, target = 0.0, tau = 0.0;
  auto value_at = [&](double time) {
    if (tau <= 0.0 || time >= start + tau) return target;
    return from + (target - from) * std::max(0.0, time - start) / tau;
  };
  for (const ActivationCommand& c : commands) {
    if (c.time > t) break;
    if (upper(c.muscle) != name) continue;
    from = value_at(c.time);
    start = c.time;
    target = c.activation;
    tau = c.timescale;
  }
  return value_at(t);
}

std::vector<std::string> ActivationScript::muscles() const {
  std::set<std::string> names;
  for (const auto& c : commands) names.insert(upper(c.muscle));
  return {names.begin(), names.end()};
}

ActivationScript parse_activation_script(const std::string& text, const std::string& source,
                                         const std::set<std::string>& known_muscles) {
  std::set<std::string> known;
  std::string known_list;
  for (const auto& k : known_muscles) {
    known.insert(upper(k));
    known_list += (known_list.empty() ? "" : ", ") + k;
  }
  ActivationScript s;
  s.source = source;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  double last_time = 0.0;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string where = source + ":" + std::to_string(lineno) + ": ";
    const size_t comment = line.find('%');
    if (comment != std::string::npos) line.erase(comment);
    std::istringstream fields(line);
    std::vector<std::string> tok;
    for (std::string t; fields >> t;) tok.push_back(t);
    if (tok.empty()) continue;
    if (tok.size() != 4)
      throw Error(where + "expected '<time> <muscle name> <activation value> <time scale>', found " +
                  std::to_string(tok.size()) + " field" + (tok.size() == 1 ? "" : "s"));
    ActivationCommand c;
    c.line = lineno;
    c.time = number(tok[0], where, "time");
    c.muscle = tok[1];
    c.activation = number(tok[2], where, "activation value");
    c.timescale = number(tok[3], where, "time scale");
    if (c.time < 0.0) throw Error(where + "the time must not be negative");
    if (c.time < last_time)
      throw Error(where + "the time " + tok[0] + " s is earlier than the line before (commands must be in time order)");
    if (c.activation < 0.0 || c.activation > 1.0) throw Error(where + "the activation value must lie in [0, 1]");
    if (c.timescale < 0.0) throw Error(where + "the time scale must not be negative");
    if (!known.empty() && !known.count(upper(c.muscle)))
      throw Error(where + "unknown muscle '" + c.muscle + "' (known: " + known_list + ")");
    last_time = c.time;
    s.commands.push_back(c);
  }
  return s;
}

ActivationScript read_activation_script(const std::string& path, const std::set<std::string>& known_muscles) {
  return parse_activation_script(read_input_file(path, "activation script"), path, known_muscles);
}

}  // namespace msd
