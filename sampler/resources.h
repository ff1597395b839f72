#pragma once
// Memory a command is about to need, checked against the machine's before
// allocating: a size the machine cannot hold is refused with the numbers,
// instead of std::bad_alloc or hours of swapping.

#include <cstdint>
#include <string>

namespace nuld {

std::uint64_t physicalMemoryBytes();    // 0 when the system does not say
std::string formatBytes(double bytes);  // "512 MiB", "1.5 GiB"

// The share of the physical memory one run may plan to take.
inline constexpr double kSpareMemoryShare = 0.9;

// Throws std::invalid_argument "<what> needs about X of memory, more than this
// machine's Y to spare (90 % of its Z)" when `bytes` exceeds that share of
// the physical memory.
void requireMemory(double bytes, const std::string &what);

}  // namespace nuld
