#include "msd/io/atomic_file.hpp"

#include "msd/core/types.hpp"

#include <filesystem>
#include <fstream>

namespace msd {

std::string partial_path(const std::string& path) { return path + ".partial"; }

void write_file_atomically(const std::string& path, const std::function<void(std::ostream& out)>& write) {
  const std::string tmp = partial_path(path);
  std::error_code ignore;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(path + ": cannot write");
    try {
      write(out);
      out.flush();
    } catch (...) {
      out.close();
      std::filesystem::remove(tmp, ignore);
      throw;
    }
    if (!out) {
      out.close();
      std::filesystem::remove(tmp, ignore);
      throw Error(path + ": write failed");
    }
  }
  std::error_code renamed;
  std::filesystem::rename(tmp, path, renamed);
  if (renamed) {
    std::filesystem::remove(tmp, ignore);
    throw Error(path + ": cannot rename the finished file into place");
  }
}

}  // namespace msd
