// The one JSON writer of the project (summaries, suite and sweep tables):
// nlohmann::json (Debian's nlohmann-json3-dev) with keys kept in insertion
// order, written whole-or-nothing (msd/io/atomic_file.hpp). NaN and infinity
// are written as null; invalid UTF-8 in a string is replaced (U+FFFD).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace tbio {

using Json = nlohmann::ordered_json;

/// Writes `value` to `path` (two-space indent, a final newline) through a
/// temporary name. Throws msd::Error naming the path when the write fails.
void write_json_file(const std::string& path, const Json& value);

/// A JSON number rounded to `digits` significant digits (as the summaries'
/// trajectories are written), null when not finite.
Json rounded(double value, int digits);

}  // namespace tbio
