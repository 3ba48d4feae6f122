// Reading an input file whole, with a size cap: every reader of user files
// (specs, scenes, calibration and baseline files, activation scripts, OBJ/STL/
// PLY surfaces) goes through here, so a link to /dev/zero, a FIFO or a file of
// many gigabytes is refused with its name instead of being read until memory
// runs out.
#pragma once

#include <cstdint>
#include <string>

namespace msd {

/// Size caps (bytes). Text inputs (YAML, activation scripts) are hand-written
/// and small: the largest shipped one is a few kB. Surfaces are larger: the
/// shipped leg's OBJ files are under 1 MB, a 1 M-triangle binary STL is 50 MB.
inline constexpr std::uint64_t kMaxTextInputBytes = 16ull << 20;     // 16 MiB
inline constexpr std::uint64_t kMaxSurfaceInputBytes = 1ull << 30;   // 1 GiB

/// The whole content of `path`. Throws msd::Error naming the file and `what`
/// ("PATH: cannot read the WHAT", "PATH: the WHAT is not a regular file",
/// "PATH: the WHAT is N bytes, more than the limit of M bytes") for a missing
/// or unreadable file, a device, FIFO, socket or folder (after following links),
/// or a file larger than `max_bytes`.
std::string read_input_file(const std::string& path, const std::string& what,
                            std::uint64_t max_bytes = kMaxTextInputBytes);

}  // namespace msd
