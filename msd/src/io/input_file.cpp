#include "msd/io/input_file.hpp"

#include "msd/core/types.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace msd {

std::string read_input_file(const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(path + ": cannot read the " + what + " (" + std::strerror(errno) + ")");
  if (S_ISDIR(st.st_mode)) throw Error(path + ": the " + what + " is a folder, not a file");
  if (!S_ISREG(st.st_mode))
    throw Error(path + ": the " + what + " is not a regular file (a device, pipe or socket is not read)");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes)
    throw Error(path + ": the " + what + " is " + std::to_string(size) + " bytes, more than the limit of " +
                std::to_string(max_bytes) + " bytes for a " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot read the " + what + " (" + std::strerror(errno) + ")");
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uint64_t>(in.gcount()) != size) throw Error(path + ": cannot read the " + what + " (short read)");
  return text;
}

}  // namespace msd
