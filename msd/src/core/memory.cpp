#include "msd/core/memory.hpp"

#include "msd/core/types.hpp"

#include <unistd.h>

#include <cstdio>

namespace msd {

namespace {

std::string gb(double bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f GB", bytes / 1e9);
  return b;
}

}  // namespace

double physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

double MemoryLimit::effective_bytes() const {
  if (bytes > 0.0) return bytes;
  const double machine = physical_memory_bytes();
  return machine > 0.0 ? 0.5 * machine : 8e9;  // unreadable: a modest 8 GB
}

std::string MemoryLimit::describe() const {
  if (bytes > 0.0) return "the memory limit of " + gb(bytes) + " (set by " + how_to_raise + ")";
  const double machine = physical_memory_bytes();
  return "the memory limit of " + gb(effective_bytes()) +
         (machine > 0.0 ? " (half of this machine's " + gb(machine) + ")" : " (this machine's memory is unknown)");
}

void check_memory(double cubes, double bytes_per_cube, const std::string& what, const MemoryLimit& limit,
                  const std::string& where) {
  const double need = cubes * bytes_per_cube;
  if (need <= limit.effective_bytes()) return;
  char n[32];
  std::snprintf(n, sizeof n, "%.0f", cubes);
  throw Error((limit.context.empty() ? where : limit.context) + what + " of " + n + " cubes needs about " + gb(need) + " (" +
              std::to_string(static_cast<long>(bytes_per_cube)) +
              " bytes per cube, measured: docs/memory.md), more than " + limit.describe() + "; raise " +
              (limit.how_to_raise.empty() ? std::string("the limit") : limit.how_to_raise) +
              " or increase the grid spacing");
}

}  // namespace msd
