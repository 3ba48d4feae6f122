#include "msd/io/atomic_file.hpp"

#include "msd/core/types.hpp"
#include "msd/io/interrupt.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace msd {

std::string partial_path(const std::string& path) { return path + ".partial-" + std::to_string(::getpid()); }

std::string create_partial(const std::string& path) {
  const std::string tmp = partial_path(path);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::close(fd);
      return tmp;
    }
    if (errno != EEXIST || attempt > 0) break;
    ::unlink(tmp.c_str());  // a dead process with our pid left it
  }
  throw Error(path + ": cannot write (" + std::strerror(errno) + ")");
}

void commit_partial(const std::string& tmp, const std::string& path) {
  std::error_code renamed, ignore;
  std::filesystem::rename(tmp, path, renamed);
  if (renamed) {
    std::filesystem::remove(tmp, ignore);
    throw Error(path + ": cannot rename the finished file into place (" + renamed.message() + ")");
  }
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream& out)>& write) {
  const std::string tmp = create_partial(path);
  const RegisteredTemporary registered(tmp);
  std::error_code ignore;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      std::filesystem::remove(tmp, ignore);
      throw Error(path + ": cannot write");
    }
    try {
      write(out);
      out.flush();
    } catch (...) {
      out.close();
      std::filesystem::remove(tmp, ignore);
      throw;
    }
    out.close();
    if (!out) {
      std::filesystem::remove(tmp, ignore);
      throw Error(path + ": write failed (" + std::strerror(errno) + "; disk full?)");
    }
  }
  commit_partial(tmp, path);
}

}  // namespace msd
