// Runs the tissuebench program through the shell for the command-line suites.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <memory>
#include <string>

namespace testing_support {

/// What one command printed (stdout and stderr together) and its exit code
/// (128 + N when the shell or the program ended on signal N).
struct ShellResult {
  int code;
  std::string output;
};

/// Runs `prefix` + TISSUEBENCH_BINARY + " " + `args` through /bin/sh, with
/// stderr joined to stdout. `prefix` may set limits or the environment
/// ("ulimit -f 100; ", "OMP_NUM_THREADS=1 ").
inline ShellResult sh(const std::string& args, const std::string& prefix = "") {
  const std::string cmd = prefix + std::string(TISSUEBENCH_BINARY) + " " + args + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p.get())) out.append(buf, n);
  const int status = pclose(p.release());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

}  // namespace testing_support
