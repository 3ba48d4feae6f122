// Checks of command-line values, in the style of the spec fields' messages:
// "--duration: must be a positive finite number (s); got -1". CLI11's own
// range checks let NaN through (every comparison with NaN is false); these do
// not. A failed check is a usage error: exit 2 (README, "Exit codes").
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

namespace app {

/// A finite number in [lo, hi] (either bound may be infinite); `what` names
/// what the number is ("simulated seconds", "m").
inline CLI::Validator finite_in(double lo, double hi, const std::string& what, bool lo_open = false) {
  const std::string range = std::string(lo_open ? "(" : "[") + CLI::detail::to_string(lo) + ", " +
                            (std::isinf(hi) ? std::string("inf") : CLI::detail::to_string(hi)) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0.0;
        std::size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          return "must be a number (" + what + "); got '" + text + "'";
        }
        if (used != text.size()) return "must be a number (" + what + "); got '" + text + "'";
        if (!std::isfinite(v)) return "must be a finite number (" + what + "); got " + text;
        if (v < lo || v > hi || (lo_open && v == lo))
          return "must be in " + range + " (" + what + "); got " + text;
        return {};
      },
      "number in " + range, "finite_in");
}

/// A finite number > 0.
inline CLI::Validator finite_positive(const std::string& what) {
  return finite_in(0.0, INFINITY, what, true);
}

/// A finite number >= 0.
inline CLI::Validator finite_non_negative(const std::string& what) { return finite_in(0.0, INFINITY, what); }

/// An integer in [lo, hi].
inline CLI::Validator integer_in(long lo, long hi, const std::string& what) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        long v = 0;
        std::size_t used = 0;
        try {
          v = std::stol(text, &used);
        } catch (const std::exception&) {
          return "must be an integer (" + what + "); got '" + text + "'";
        }
        if (used != text.size()) return "must be an integer (" + what + "); got '" + text + "'";
        if (v < lo || v > hi) return "must be in " + range + " (" + what + "); got " + text;
        return {};
      },
      "integer in " + range, "integer_in");
}

}  // namespace app
