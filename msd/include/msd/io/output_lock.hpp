// One writer per output: an exclusive flock on a lock file beside the output
// (OUTPUT.lock), taken before anything is written and released when the run
// ends. A second run to the same output is refused (msd::Error naming the
// other run: its pid and command line, which the holder writes into the lock
// file). The lock file is unlinked on release; a run that locked a file that
// was unlinked meanwhile (its path now names another inode, or nothing) locks
// again, so two runs never both believe they hold the lock. SIGINT/SIGTERM
// outside a time loop remove it too (msd/io/interrupt.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace msd {

class RegisteredTemporary;

class OutputLock {
 public:
  /// Locks `output` (a file or a folder) with the lock file `output + ".lock"`.
  /// `what` describes this run for a refused one ("tissuebench run spec.yaml").
  /// Throws msd::Error when another process holds it or the file cannot be made.
  OutputLock(const std::string& output, const std::string& what);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::unique_ptr<RegisteredTemporary> registered_;  ///< removed by the signal handler too
};

/// Refuses (msd::Error naming `option`, the output and the input) when one of
/// the files a run writes names one of its inputs: the same file by path,
/// symbolic link or hard link. Empty names are ignored.
void refuse_output_over_inputs(const std::string& option, const std::vector<std::string>& outputs,
                               const std::vector<std::string>& inputs);

/// The command line of this process (from /proc/self/cmdline), for lock files.
std::string this_command_line();

}  // namespace msd
