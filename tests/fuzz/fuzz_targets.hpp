// The fuzz targets' bodies (docs/fuzzing.md): each hands bytes to one of the
// file readers exactly as a file on disk would reach it. Compiled twice - into
// the libFuzzer programs (clang; scripts/fuzz.sh) and into the regression test
// that replays tests/fuzz/regressions/TARGET/ in the normal build - so a crash
// found by the fuzzer is replayed by the same code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tbfuzz {

struct Target {
  const char* name;         ///< e.g. "spec"; tests/fuzz/regressions/NAME/
  const char* reader;       ///< what it feeds, for the docs and messages
  std::string (*run)(const std::string& bytes);
};

/// Every target, in the order scripts/fuzz.sh runs them.
const std::vector<Target>& targets();
/// The target called `name`, or nullptr.
const Target* find_target(const std::string& name);

/// Feeds `bytes` to the target's reader. Returns "" when the reader read them
/// or refused them the way bad input must be refused (msd::Error: one message
/// for the user); otherwise what went wrong - any other exception escaping the
/// reader, which the program would print as an "unexpected error" naming no
/// file or field. Crashes, sanitizer findings, hangs and runaway memory are
/// caught by the fuzzer and the sanitizers, not here.
std::string run_target(const Target& target, const std::uint8_t* data, std::size_t size);

}  // namespace tbfuzz
