// Whole-or-nothing file writing: the content goes to PATH.partial in the same
// folder and is renamed onto PATH only when every byte was written, so a crash,
// a full disk or an exception never leaves a half-written file under the real
// name, and a refused write never touches an existing PATH.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace msd {

/// The temporary name a whole-or-nothing write uses for `path`.
std::string partial_path(const std::string& path);

/// Calls `write(out)` on a stream to partial_path(path), then renames it onto
/// `path`. Throws msd::Error "PATH: cannot write" / "PATH: write failed" (the
/// temporary removed) when the file cannot be opened or a write fails;
/// exceptions from `write` remove the temporary and propagate.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream& out)>& write);

}  // namespace msd
