// One libFuzzer program per target (TB_FUZZ_TARGET, set by tests/fuzz/CMakeLists.txt):
// the body is tbfuzz::run_target, shared with the regression test. A reader that
// lets an exception other than msd::Error escape is a finding: abort, so
// libFuzzer keeps the input as a crash.
#include "fuzz_targets.hpp"

#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const tbfuzz::Target* target = tbfuzz::find_target(TB_FUZZ_TARGET);
  if (!target) {
    std::fprintf(stderr, "tbfuzz: no target '%s'\n", TB_FUZZ_TARGET);
    std::abort();
  }
  const std::string finding = tbfuzz::run_target(*target, data, size);
  if (!finding.empty()) {
    std::fprintf(stderr, "tbfuzz: %s\n", finding.c_str());
    std::abort();
  }
  return 0;
}
