// Whole-or-nothing file writing: the content goes to a temporary in the same
// folder that is unique to this process (PATH.partial-PID) and is renamed onto
// PATH only when every byte was written, so a crash, a full disk, an interrupt
// or an exception never leaves a half-written file under the real name, a
// refused write never touches an existing PATH, and two processes writing the
// same PATH never share a temporary (the last rename wins, each file whole).
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace msd {

/// The temporary name this process uses for `path`: PATH.partial-PID.
std::string partial_path(const std::string& path);

/// Creates partial_path(path) exclusively (O_EXCL; a leftover of a dead
/// process with this pid is removed first) and returns it. Throws msd::Error
/// "PATH: cannot write (...)" when it cannot be created.
std::string create_partial(const std::string& path);

/// Renames `tmp` onto `path`; on failure removes `tmp` and throws msd::Error.
void commit_partial(const std::string& tmp, const std::string& path);

/// Calls `write(out)` on a stream to partial_path(path), then renames it onto
/// `path`. Throws msd::Error "PATH: cannot write" / "PATH: write failed" (the
/// temporary removed) when the file cannot be opened or a write fails;
/// exceptions from `write` remove the temporary and propagate. The temporary
/// is removed too when SIGINT/SIGTERM ends the process (msd/io/interrupt.hpp).
void write_file_atomically(const std::string& path, const std::function<void(std::ostream& out)>& write);

}  // namespace msd
