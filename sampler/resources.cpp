#include "sampler/resources.h"

#include <unistd.h>

#include <cstdio>
#include <stdexcept>

namespace nuld {

std::uint64_t physicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : 0;
}

std::string formatBytes(double bytes) {
  const char *units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) {
    bytes /= 1024;
    ++u;
  }
  char text[48];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return text;
}

void requireMemory(double bytes, const std::string &what) {
  const std::uint64_t have = physicalMemoryBytes();
  // The system and other processes hold part of it: a run that needs
  // nearly all of it fails with std::bad_alloc or swaps for hours.
  const double spare = kSpareMemoryShare * double(have);
  if (have > 0 && !(bytes <= spare))
    throw std::invalid_argument(what + " needs about " + formatBytes(bytes) +
                                " of memory, more than this machine's " + formatBytes(spare) +
                                " to spare (" + std::to_string(int(100 * kSpareMemoryShare)) +
                                " % of its " + formatBytes(double(have)) + ")");
}

}  // namespace nuld
