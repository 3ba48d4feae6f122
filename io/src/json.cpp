#include "tbio/json.hpp"

#include "msd/io/atomic_file.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace tbio {

void write_json_file(const std::string& path, const Json& value) {
  // Invalid UTF-8 in a string (a path, a message) is replaced, not a reason to lose the file.
  const std::string text = value.dump(2, ' ', false, Json::error_handler_t::replace);
  msd::write_file_atomically(path, [&](std::ostream& out) { out << text << '\n'; });
}

Json rounded(double value, int digits) {
  if (!std::isfinite(value)) return nullptr;
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return std::strtod(text, nullptr);
}

}  // namespace tbio
