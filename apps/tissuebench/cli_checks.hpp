// Checks of command-line values, in the style of the spec fields' messages:
// "--duration: must be a positive finite number (s); got -1". CLI11's own
// range checks let NaN through (every comparison with NaN is false); these do
// not. A failed check is a usage error: exit 2 (README, "Exit codes").
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>
#include <type_traits>

namespace app {

namespace detail {

/// One value of type T (double or long) in [lo, hi] (`(lo, hi]` when
/// `lo_open`), the whole text parsed; a double must also be finite. `what`
/// names what the value is ("simulated seconds", "m").
template <class T>
CLI::Validator value_in(T lo, T hi, const std::string& what, bool lo_open, const std::string& name) {
  constexpr bool real = std::is_floating_point_v<T>;
  const std::string kind = real ? "a number" : "an integer";
  const auto text_of = [](T v) {
    if constexpr (real) return std::isinf(v) ? std::string(v < 0 ? "-inf" : "inf") : CLI::detail::to_string(v);
    else return std::to_string(v);
  };
  const std::string range = std::string(lo_open ? "(" : "[") + text_of(lo) + ", " + text_of(hi) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        T v{};
        std::size_t used = 0;
        try {
          if constexpr (real) v = std::stod(text, &used);
          else v = std::stol(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == 0 || used != text.size()) return "must be " + kind + " (" + what + "); got '" + text + "'";
        if constexpr (real)
          if (!std::isfinite(v)) return "must be a finite number (" + what + "); got " + text;
        if (v < lo || v > hi || (lo_open && v == lo))
          return "must be in " + range + " (" + what + "); got " + text;
        return {};
      },
      (real ? "number in " : "integer in ") + range, name);
}

}  // namespace detail

/// A finite number in [lo, hi] (either bound may be infinite); `what` names
/// what the number is ("simulated seconds", "m").
inline CLI::Validator finite_in(double lo, double hi, const std::string& what, bool lo_open = false) {
  return detail::value_in<double>(lo, hi, what, lo_open, "finite_in");
}

/// A finite number > 0.
inline CLI::Validator finite_positive(const std::string& what) {
  return finite_in(0.0, INFINITY, what, true);
}

/// A finite number >= 0.
inline CLI::Validator finite_non_negative(const std::string& what) { return finite_in(0.0, INFINITY, what); }

/// An integer in [lo, hi].
inline CLI::Validator integer_in(long lo, long hi, const std::string& what) {
  return detail::value_in<long>(lo, hi, what, false, "integer_in");
}

}  // namespace app
