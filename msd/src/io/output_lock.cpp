#include "msd/io/output_lock.hpp"

#include "msd/core/types.hpp"
#include "msd/io/interrupt.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace msd {

std::string this_command_line() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (char& c : all)
    if (c == '\0') c = ' ';
  while (!all.empty() && all.back() == ' ') all.pop_back();
  return all;
}

namespace {

bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code e1, e2;
  if (fs::exists(a, e1) && fs::exists(b, e2)) return fs::equivalent(a, b, e1);
  return fs::weakly_canonical(a, e1) == fs::weakly_canonical(b, e2);
}

}  // namespace

void refuse_output_over_inputs(const std::string& option, const std::vector<std::string>& outputs,
                               const std::vector<std::string>& inputs) {
  for (const std::string& out : outputs)
    for (const std::string& in : inputs)
      if (!out.empty() && !in.empty() && same_file(out, in))
        throw Error(option + ": the run would write " + out + ", which is its input " + in +
                    "; refused (choose another output)");
}

namespace {

std::string holder_of(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line.empty() ? "another process" : line;
}

}  // namespace

OutputLock::OutputLock(const std::string& output, const std::string& what) : path_(output + ".lock") {
  // Held back until the lock file is registered for removal: a signal in
  // between would leave it behind.
  const SignalsBlocked held;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw Error(output + ": cannot create the lock file " + path_ + ": " + std::strerror(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      ::close(fd);
      if (e == EWOULDBLOCK)
        throw Error(output + ": another run is writing it (" + holder_of(path_) +
                    "); refused, nothing written (wait for it to end or choose another --out)");
      throw Error(output + ": cannot lock " + path_ + ": " + std::strerror(e));
    }
    // The holder before us may have unlinked the file between our open and
    // our lock: then we hold a lock nobody else can see. Check that the path
    // still names the inode we locked.
    struct stat a {}, b {};
    if (::fstat(fd, &a) == 0 && ::stat(path_.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino) {
      std::ostringstream who;
      who << "pid " << ::getpid() << ": " << what << "\n";
      const std::string text = who.str();
      if (::ftruncate(fd, 0) == 0 && ::write(fd, text.data(), text.size()) < 0) {
        // the holder's description is a courtesy; the lock is what counts
      }
      fd_ = fd;
      registered_ = std::make_unique<RegisteredTemporary>(path_);
      return;
    }
    ::close(fd);
  }
  throw Error(output + ": cannot lock " + path_ + " (it keeps being replaced)");
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  registered_.reset();
  ::unlink(path_.c_str());  // before the close: a waiter that locks the old inode sees it gone and retries
  ::close(fd_);
}

}  // namespace msd
